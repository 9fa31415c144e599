#!/bin/bash
# NUMA placement sweep: solves one scene under every pin x placement x scheduler given
# and prints a Markdown table of the run's local-access ratio (sum of tasks_local over
# sum of tasks, all iterations), the element and link bytes per node, the refinement
# time and the steals, read from each run's stats.json.
#
# usage: tools/numa-sweep.sh SCENE THREADS "PINS" "PLACEMENTS" "SCHEDULERS"
#   e.g. HWLOC_SYNTHETIC="node:2 core:2 pu:1" tools/numa-sweep.sh builtin:cornell 2 \
#          "none compact scatter node-round-robin" "first-touch interleave node0" \
#          "blocked locality stealing"
# Environment: HRAD (default build/hrad), OUT (default results/numa-sweep), and
# HWLOC_SYNTHETIC / HWLOC_XMLFILE for a machine other than this one (unset both on a
# real NUMA server, so that bindings are applied).
set -u
if [ $# -ne 5 ]; then
  echo "usage: $0 SCENE THREADS \"PINS\" \"PLACEMENTS\" \"SCHEDULERS\"" >&2
  exit 1
fi
H=${HRAD:-build/hrad}
SCENE=$1
T=$2
OUT=${OUT:-results/numa-sweep}
mkdir -p "$OUT"
echo "| pin | placement | scheduler | local ratio (run) | bytes per node (KiB) | refine wall (s) | steals |"
echo "|---|---|---|---|---|---|---|"
for pin in $3; do
  for pl in $4; do
    for s in $5; do
      d=$OUT/$(echo "$SCENE" | tr ':?&=' '____')-$T-$pin-$pl-$s
      if ! "$H" solve "$SCENE" --threads "$T" --block-size 8 --pin "$pin" --placement "$pl" \
          --scheduler "$s" --quiet --set image_width=64 --out "$d" >/dev/null 2>"$d.err"; then
        echo "| $pin | $pl | $s | failed: see $d.err | | | |"
        continue
      fi
      python3 - "$d/stats.json" "$pin" "$pl" "$s" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
its = d["iterations"]
local = sum(r["tasks_local"] for it in its for r in it["refiners"])
total = sum(r["tasks"] for it in its for r in it["refiners"])
ratio = f"{local / total:.3f}" if total else "-"
per_node = " / ".join(str(b // 1024) for b in its[-1]["bytes_per_node"]) if its else "-"
steals = sum(it["steals"] for it in its)
print(f"| {sys.argv[2]} | {sys.argv[3]} | {sys.argv[4]} | {ratio} | {per_node} | "
      f"{d['totals']['refine_wall_s']:.2f} | {steals} |")
PY
    done
  done
done

#!/bin/bash
# Speed-up check (a benchmark, not a test): solves one scene at 1 and at P threads in
# alternation, RUNS times each, and prints the medians of the refinement, propagation
# and whole-run wall times, the speed-ups they give, the per-task cost ratio (refiner
# thread CPU time per task at P threads over the same at 1 thread), and the spread of
# each series (max/min wall time: a value well above 1.15 means runs fall into
# different modes). Every figure is read from the runs' stats.json.
#
# usage: tools/speedup-check.sh [SCENE] [-- SOLVE OPTIONS...]
#   e.g. tools/speedup-check.sh builtin:lab
#        tools/speedup-check.sh builtin:office -- --eps 1e-5
#        RUNS=7 THREADS=2 tools/speedup-check.sh builtin:lab -- --scheduler stealing
# Environment: HRAD (default build/hrad), RUNS (default 5), THREADS (P, default 2),
# OUT (scratch folder, default a fresh one under /tmp, removed at the end).
# The solve's own defaults (the `blocked` scheduler, guided blocks) unless the options
# name their own.
set -euo pipefail
H=${HRAD:-build/hrad}
RUNS=${RUNS:-5}
P=${THREADS:-2}
SCENE=${1:-builtin:lab}
shift || true
if [ "${1:-}" = "--" ]; then shift; fi
OUT=${OUT:-$(mktemp -d /tmp/hrad-speedup.XXXXXX)}
cleanup() { [ -z "${KEEP:-}" ] && rm -rf "$OUT"; }
trap cleanup EXIT
PY=${HRAD_PYTHON:-python3}

defaults=()

for ((i = 1; i <= RUNS; ++i)); do
  for t in 1 "$P"; do
    d=$OUT/t$t-r$i
    "$H" solve "$SCENE" "${defaults[@]}" "$@" --threads "$t" --out "$d" --quiet >/dev/null
    printf '.' >&2
  done
done
echo >&2

"$PY" - "$OUT" "$RUNS" "$P" "$SCENE" "$*" <<'PY'
import json, statistics, sys
out, runs, p, scene, extra = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4], sys.argv[5]

def load(t, i):
    s = json.load(open(f"{out}/t{t}-r{i}/stats.json"))
    its = s["iterations"]
    tasks = sum(it["tasks"] for it in its)
    cpu = sum(it["refine_thread_cpu_s"] for it in its)
    return {
        "wall": s["totals"]["wall_s"],
        "refine": s["totals"]["refine_wall_s"],
        "prop": sum(it["propagate_wall_s"] for it in its),
        "it1": its[0]["refine_wall_s"],
        "task_ns": 1e9 * cpu / tasks if tasks else 0.0,
        "links": s["totals"]["links"],
    }

one = [load(1, i) for i in range(1, runs + 1)]
par = [load(p, i) for i in range(1, runs + 1)]
med = lambda rows, k: statistics.median(r[k] for r in rows)
spread = lambda rows, k: max(r[k] for r in rows) / min(r[k] for r in rows)
print(f"scene {scene} {extra}  ({runs} alternating runs each, medians)")
print(f"{'':22}{'1 thread':>10}{f'{p} threads':>12}{'speed-up':>10}")
for k, name in (("refine", "refinement wall (s)"), ("it1", "  iteration 1 (s)"),
                ("prop", "propagation wall (s)"), ("wall", "whole run (s)")):
    a, b = med(one, k), med(par, k)
    print(f"{name:22}{a:10.3f}{b:12.3f}{a / b if b else 0:10.2f}")
a, b = med(one, "task_ns"), med(par, "task_ns")
print(f"{'CPU per task (ns)':22}{a:10.0f}{b:12.0f}{'ratio %.2f' % (b / a if a else 0):>11}")
print(f"{'max/min wall':22}{spread(one, 'wall'):10.2f}{spread(par, 'wall'):12.2f}")
for rows, t in ((one, 1), (par, p)):
    print(f"  {t} thread(s), each run: wall " + " ".join(f"{r['wall']:.2f}" for r in rows) +
          " | refine " + " ".join(f"{r['refine']:.2f}" for r in rows) +
          " | ns/task " + " ".join(f"{r['task_ns']:.0f}" for r in rows))
if len({r['links'] for r in one + par}) != 1:
    print("warning: the runs did not all find the same number of links")
PY

#!/bin/bash
# Scaling check (a benchmark, not a test): how far hrad's parallel refinement and whole
# run are from what the machine allows, in one CSV and one figure.
#
#  1. Hardware control: the lab solved on 1 thread alone, then N independent 1-thread
#     solves at once. Their speed against the one alone (refinement and whole run) is
#     the machine's own limit: N solves that share nothing but the hardware reach
#     N x that efficiency, and anything below it at N threads is hrad's.
#  2. Thread sweep on builtin:lab: every scheduler at 1, 2, 4, ... N threads (and N),
#     at the defaults (guided blocks).
#  3. Block sizes 1, 10, 100 of `blocked` at N threads (the paper's fixed blocks), and
#     the guided default.
#  4. builtin:cabin at 1 and N threads (default scheduler).
# Each row of scaling.csv is one run: its kind, scene, scheduler, block size, threads,
# repetition, the times read from its stats.json, the load average, hrad's revision and the
# host. scaling.png (plots/scaling_check.py)
# draws each scheduler's refinement and whole-run speed-up against threads with the
# control's limit. The script prints the table as it goes and writes every row as soon
# as its run ends, so a cut-off run still leaves what it measured.
#
# usage: tools/scaling-check.sh [N]      N: threads (default: the machine's cores)
# Environment: HRAD (default build/hrad), OUT (default results/scaling-check/<stamp>),
# REPS (repetitions of each run, alternating, default 1), SCHEDULERS (default all),
# CABIN=0 to leave the cabin out, LAB (default builtin:lab).
# About 3 minutes on a 16-core machine; a few minutes with N = 2.
set -euo pipefail
H=${HRAD:-build/hrad}
N=${1:-$(nproc)}
REPS=${REPS:-1}
LAB=${LAB:-builtin:lab}
OUT=${OUT:-results/scaling-check/$(date +%Y%m%d-%H%M%S)}
SCHEDULERS=${SCHEDULERS:-blocked stealing stack fifo priority locality}
if ! [[ "$N" =~ ^[0-9]+$ ]] || [ "$N" -lt 1 ]; then
  echo "scaling-check: N must be a positive integer, not '$N'" >&2
  exit 2
fi
mkdir -p "$OUT/runs"
CSV=$OUT/scaling.csv
echo "kind,scene,scheduler,block_size,threads,rep,wall_s,refine_wall_s,propagate_wall_s,sweeps_s,prepare_s,lock_wait_scheduler_s,tasks,links,load_1m,revision,host" >"$CSV"
PY=${HRAD_PYTHON:-python3}

# Appends one row from a run folder's stats.json.
row() { # kind scene scheduler block threads rep dir
  "$PY" - "$@" >>"$CSV" <<'EOF'
import json, os, socket, sys
kind, scene, sched, block, threads, rep, d = sys.argv[1:8]
s = json.load(open(os.path.join(d, "stats.json")))
t = s["totals"]
lock = sum(i["lock_wait_s"].get("scheduler", 0) for i in s["iterations"])
tasks = sum(i["tasks"] for i in s["iterations"])
load = os.getloadavg()[0]
print(f"{kind},{scene},{sched},{block},{threads},{rep},{t['wall_s']:.4f},{t['refine_wall_s']:.4f},"
      f"{t['propagate_wall_s']:.4f},{t['sweeps_s']:.4f},{t['prepare_s']:.4f},{lock:.4f},"
      f"{tasks},{t['links']},{load:.2f},{s['hrad']['git_revision']},{socket.gethostname()}")
EOF
  tail -1 "$CSV" >&2
}

run() { # kind scene scheduler block threads rep
  local d=$OUT/runs/$1-$(echo "$2" | tr ':?&=' '____')-$3-b$4-t$5-r$6
  local opts=(--scheduler "$3" --threads "$5" --out "$d" --quiet)
  [ "$4" = guided ] || opts+=(--block-size "$4")
  "$H" solve "$2" "${opts[@]}" >/dev/null 2>"$d.log" || {
    echo "scaling-check: $2 $3 b$4 t$5 failed (see $d.log)" >&2
    return 1
  }
  row "$@" "$d"
}

threads_list() {
  local t=1 list=""
  while [ "$t" -lt "$N" ]; do
    list="$list $t"
    t=$((t * 2))
  done
  echo "$list $N"
}

echo "scaling-check: N = $N, $REPS repetition(s), results in $OUT" >&2
for ((r = 1; r <= REPS; ++r)); do
  # 1. The control: one alone, then N at once.
  run control-alone "$LAB" blocked guided 1 "$r"
  pids=()
  for ((k = 1; k <= N; ++k)); do
    run control-parallel "$LAB" blocked guided 1 "$r-$k" &
    pids+=($!)
  done
  for p in "${pids[@]}"; do wait "$p"; done
  # 2. The thread sweep, schedulers alternating at each thread count.
  for t in $(threads_list); do
    for s in $SCHEDULERS; do run sweep "$LAB" "$s" guided "$t" "$r"; done
  done
  # 3. Fixed block sizes at N threads.
  for b in 1 10 100; do run block "$LAB" blocked "$b" "$N" "$r"; done
  # 4. The cabin.
  if [ "${CABIN:-1}" != 0 ]; then
    run cabin builtin:cabin blocked guided 1 "$r"
    run cabin builtin:cabin blocked guided "$N" "$r"
  fi
done
# The figure needs matplotlib (tools/plot-python.sh); without it no table is printed
# either, the CSV is there.
if plot=$(bash "$(dirname "$0")/plot-python.sh"); then
  "$plot" "$(dirname "$0")/../plots/scaling_check.py" "$CSV" --out "$OUT/scaling.png"
  echo "scaling-check: wrote $CSV and $OUT/scaling.png" >&2
else
  echo "scaling-check: no python3 with matplotlib: $CSV written, no figure" >&2
fi

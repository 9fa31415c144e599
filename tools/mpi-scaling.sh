#!/usr/bin/env bash
# Runs per minute of one experiment config against the number of MPI ranks:
#   tools/mpi-scaling.sh BUILD_DIR OUT_DIR [CONFIG] [RANKS...]
# For each rank count N (default 1 2 3): `mpirun -np N hrad experiment CONFIG` into
# OUT_DIR/np<N>/, timed from launch to exit (MPI start-up included). Writes
# OUT_DIR/scaling.csv (ranks, workers, runs, wall_s, runs_per_min, mean_run_s,
# handoff_wait_mean_s, handoff_wait_max_s, coordinator_cpu_s) and the figure
# (plots/mpi_scaling.py). One rank runs the serial loop; N > 1 ranks have N-1 workers
# (rank 0 only coordinates). More ranks than cores oversubscribe (--oversubscribe).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 2 ]; then
  echo "usage: $0 BUILD_DIR OUT_DIR [CONFIG] [RANKS...]" >&2
  exit 1
fi
build=$1 out=$2
config=${3:-docs/figures/mpi-scaling/config.json}
shift $(( $# >= 3 ? 3 : 2 ))
ranks=("$@")
[ ${#ranks[@]} -gt 0 ] || ranks=(1 2 3)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$out"
csv=$out/scaling.csv
echo "ranks,workers,runs,wall_s,runs_per_min,mean_run_s,handoff_wait_mean_s,handoff_wait_max_s,coordinator_cpu_s" > "$csv"
for n in "${ranks[@]}"; do
  dir=$out/np$n
  rm -rf "$dir"
  t0=$(date +%s.%N)
  mpirun --oversubscribe --bind-to none -np "$n" "$build/hrad" experiment "$config" \
    --out "$dir" --no-plot --quiet
  t1=$(date +%s.%N)
  python3 - "$dir" "$n" "$t0" "$t1" >> "$csv" <<'PY'
import csv, json, sys
d, n, t0, t1 = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
with open(f"{d}/runs.csv", newline="") as f:
    rows = list(csv.DictReader(f))
wall = t1 - t0
mean_run = sum(float(r["wall_s"]) for r in rows) / len(rows)
o = {}
m = json.load(open(f"{d}/manifest.json"))
if m.get("mpi"):
    o = m["mpi"][-1]["overhead"]
workers = max(1, n - 1)
print(f"{n},{workers},{len(rows)},{wall:.3f},{60 * len(rows) / wall:.2f},{mean_run:.4f},"
      f"{o.get('handoff_wait_mean_s', '')},{o.get('handoff_wait_max_s', '')},"
      f"{o.get('coordinator_cpu_s', '')}")
PY
  tail -1 "$csv"
done
# The plot needs matplotlib (tools/plot-python.sh).
if ! py=$(bash "$(dirname "$0")/plot-python.sh"); then
  echo "mpi-scaling: no python3 with matplotlib: $csv written, no figure" >&2
  exit 0
fi
"$py" plots/mpi_scaling.py "$out"

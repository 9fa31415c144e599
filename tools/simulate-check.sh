#!/usr/bin/env bash
# Checks `hrad simulate`'s contention model against the 16-core measurements
# (shared/measurements/16-core-2026-12-04): a 1-thread trace of builtin:lab (blocked,
# block 10) made here, every time in it scaled so that its 1-processor replay takes the
# 16-core machine's 1-thread refinement (3.84 s), replayed with
# experiments/sim/costs-16core-44e96be.json at blocked b10 on 4, 8, 16 processors and b1,
# b100 on 16. Prints measured (medians) against simulated; exit 1 when one is off by
# more than TOLERANCE (default 0.15). b1 at 16 is the calibration point.
# Usage: tools/simulate-check.sh [BUILD_DIR] (TRACE_DIR, default /tmp/hrad-simcheck).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
HRAD=$BUILD/hrad
DIR=${TRACE_DIR:-/tmp/hrad-simcheck}
DATA=../shared/measurements/16-core-2026-12-04/runs.jsonl
COSTS=experiments/sim/costs-16core-44e96be.json
mkdir -p "$DIR"
if [[ ! -s $DIR/lab.trace ]]; then
  echo "recording $DIR/lab.trace (1 thread, about 10-20 s)"
  nice -n 10 "$HRAD" solve builtin:lab --threads 1 --scheduler blocked --block-size 10 \
    --set trace="$DIR/lab.trace" --out "$DIR/traced" --quiet
fi
python3 - "$HRAD" "$DIR" "$DATA" "$COSTS" "${TOLERANCE:-0.15}" <<'PY'
import csv, json, statistics, subprocess, sys
hrad, d, data, costs, tol = sys.argv[1:6]
tol = float(tol)

def sim(block, procs, scale):
    out = f"{d}/check.csv"
    subprocess.run(["nice", "-n", "10", hrad, "simulate", f"{d}/lab.trace", "--procs", procs,
                    "--block-size", str(block), "--scale", str(scale), "--costs", costs,
                    "--quiet", "--out", out], check=True, stdout=subprocess.DEVNULL)
    return {int(r["procs"]): float(r["time_s"]) for r in csv.DictReader(open(out))
            if r["kind"] == "simulated" and r["iteration"] == "all"}

runs = [json.loads(l) for l in open(data)]
alone = [r["refine_wall_s"] for r in runs if r["tag"] == "control-alone"][0]
def measured(block, threads, tags=("curve", "block")):
    return statistics.median(r["refine_wall_s"] for r in runs if r["tag"] in tags
                             and r["scheduler"] == "blocked" and r["block"] == block
                             and r["threads"] == threads and r["scene"] == "builtin:lab")
scale = alone / sim(10, "1", 1.0)[1]
print(f"scale {scale:.4f}: 16-core 1-thread refinement {alone:.2f} s / this trace's replay")
points = [(10, 4, ""), (10, 8, ""), (10, 16, ""), (1, 16, "calibration"), (100, 16, "")]
bad = 0
print(f"{'block':>5} {'threads':>7} {'measured s':>10} {'simulated s':>11} {'error':>7}")
for block, threads, note in points:
    m = measured(block, threads)
    s = sim(block, str(threads), scale)[threads]
    err = (s - m) / m
    bad += abs(err) > tol and not note
    print(f"{block:>5} {threads:>7} {m:>10.3f} {s:>11.3f} {100*err:>+6.1f}% {note}")
print(f"{bad} point(s) off by more than {100*tol:.0f}%")
sys.exit(1 if bad else 0)
PY

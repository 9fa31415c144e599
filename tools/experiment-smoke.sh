#!/usr/bin/env bash
# Runs every shipped experiment config (experiments/configs/*.json) with --quick into a
# scratch folder and prints how long each took: the smoke test of `hrad experiment`,
# its result files and its plots. Each config takes well under a minute on 2 cores.
# Usage: tools/experiment-smoke.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
out="${2:-$(mktemp -d)}"
status=0
for config in "$here"/experiments/configs/*.json; do
  name="$(basename "$config" .json)"
  start=$(date +%s%N)
  if "$build/hrad" experiment "$config" --quick --quiet --out "$out/$name"; then
    result=ok
  else
    result=FAILED
    status=1
  fi
  ms=$(( ($(date +%s%N) - start) / 1000000 ))
  printf '%-20s %4d.%01d s  %s\n' "$name" $((ms / 1000)) $((ms % 1000 / 100)) "$result"
done
echo "results in $out"
exit $status

#!/usr/bin/env bash
# Fuzz smoke test: configures build-fuzz/ with clang (HRAD_FUZZ=ON), builds the
# libFuzzer targets and runs each for SECONDS (default 30) from a scratch copy of
# its seed corpus (tests/fuzz/corpus/NAME/), so the checked-in corpus is unchanged.
# Fails on the first crash, sanitizer report, uncaught exception, leak or timeout;
# the input that triggered it is kept in build-fuzz/artifacts/.
#
#   tools/fuzz-smoke.sh [SECONDS]
# Environment: HRAD_FUZZ_BUILD (build dir, default build-fuzz), CC/CXX (default
# clang-14/clang++-14), HRAD_FUZZ_TARGETS (default "obj mgf config probes").
set -euo pipefail

seconds=${1:-30}
root=$(cd "$(dirname "$0")/.." && pwd)
build=${HRAD_FUZZ_BUILD:-$root/build-fuzz}
targets=${HRAD_FUZZ_TARGETS:-obj mgf config probes}

CC=${CC:-clang-14} CXX=${CXX:-clang++-14} cmake -S "$root" -B "$build" -G Ninja \
  -DHRAD_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
for t in $targets; do
  cmake --build "$build" --target "fuzz_$t"
done

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
artifacts=$build/artifacts
mkdir -p "$artifacts"

for t in $targets; do
  mkdir -p "$work/$t"
  if [[ -d $root/tests/fuzz/corpus/$t ]]; then
    cp -R "$root/tests/fuzz/corpus/$t/." "$work/$t/"
  fi
  echo "== fuzz_$t for ${seconds}s"
  if ! "$build/tests/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 \
      -max_len=16384 -print_final_stats=1 -artifact_prefix="$artifacts/$t-" "$work/$t"; then
    echo "fuzz_$t FAILED; reproduce with: $build/tests/fuzz/fuzz_$t $artifacts/$t-<file>" >&2
    exit 1
  fi
done
echo "fuzz smoke test passed: $targets"

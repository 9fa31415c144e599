#!/usr/bin/env bash
# Checks that every C++ source file in the repository is formatted as .clang-format
# says (clang-format-14, as Debian bookworm ships it); lists the files that are not.
# With --fix, formats them in place instead.
set -euo pipefail
cd "$(dirname "$0")/.."
fmt=$(command -v clang-format-14 || command -v clang-format || true)
if [ -z "$fmt" ]; then
  echo "format-check: clang-format-14 is not installed (tools/install-deps.sh installs it)" >&2
  exit 2
fi
mapfile -t files < <(git ls-files '*.cpp' '*.h')
if [ "${1:-}" = "--fix" ]; then
  "$fmt" -i "${files[@]}"
  echo "format-check: formatted ${#files[@]} files"
  exit 0
fi
bad=()
for f in "${files[@]}"; do
  "$fmt" --dry-run -Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if [ ${#bad[@]} -gt 0 ]; then
  printf 'format-check: not formatted (tools/format-check.sh --fix): %s\n' "${bad[@]}" >&2
  exit 1
fi
echo "format-check: all ${#files[@]} files formatted"

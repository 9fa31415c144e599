#!/usr/bin/env bash
# Installs (from Debian bookworm's packages) everything hrad's build, tests, fuzzing
# and plots need, and only what is missing. Non-interactive; as root, or through sudo.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libembree-dev libhwloc-dev hwloc libeigen3-dev libcli11-dev nlohmann-json3-dev
  libtinyobjloader-dev libstb-dev libfmt-dev libgtest-dev libbenchmark-dev
  clang clang-format-14 libomp-14-dev libclang-rt-14-dev
  libopenmpi-dev openmpi-bin
  python3 python3-matplotlib python3-numpy
)

missing=()
for p in "${packages[@]}"; do
  # "install ok installed" is dpkg's status of a fully installed package.
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages are installed"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
  sudo=()
elif command -v sudo >/dev/null 2>&1; then
  sudo=(sudo)
else
  echo "install-deps: missing packages (${missing[*]}) and not root; no sudo to install them" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
"${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends \
  "${missing[@]}" </dev/null

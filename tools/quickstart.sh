#!/usr/bin/env bash
# From a fresh checkout to a solved scene: installs what is missing, builds hrad
# (Release, into build/), solves the built-in office and says where the results are.
set -euo pipefail
cd "$(dirname "$0")/.."

bash tools/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"

out=results/office-quickstart
build/hrad solve builtin:office --out "$out"
echo
echo "quickstart: image       $out/render.png"
echo "quickstart: statistics  $out/stats.json"
echo "quickstart: mesh        $out/solution.ply (MeshLab, Blender)"

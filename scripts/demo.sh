#!/usr/bin/env bash
# The README's main command: installs dependencies, builds, and runs the main job on the
# built-in default scene. For now that job is rendering: the built-in procedural model is
# written to out/demo/model.ply with 8 orbit cameras, and rendered to out/demo/renders/*.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$(nproc)"
out="out/demo"
build/tools/splat-demo --out "$out"
build/tools/splat-render --model "$out/model.ply" --cameras "$out/cameras.json" --out "$out/renders"
echo "outputs: $(pwd)/$out/model.ply (open it in any 3DGS viewer) and $(pwd)/$out/renders/*.png"

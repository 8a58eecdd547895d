#!/usr/bin/env bash
# The ridge demo: builds the bundled real DEM (Everest, SRTM) into an archive, describes it,
# verifies every error bound against the source, writes a shaded-relief PNG, and renders the
# terrain in 3D with the hardware-tessellation renderer (headless, EGL).
# Output goes to ./out/. Usage: bash scripts/demo.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh >/dev/null
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target ridge_cli

src=tests/data/everest_crop.tif
mkdir -p out
set -x
./build/ridge build "$src" -o out/everest.ridge
./build/ridge info out/everest.ridge
./build/ridge verify out/everest.ridge --source "$src"
./build/ridge hillshade out/everest.ridge -o out/everest_hillshade.png
./build/ridge render out/everest.ridge -o out/everest_render.png
{ set +x; } 2>/dev/null
echo "demo: wrote out/everest.ridge, out/everest_hillshade.png and out/everest_render.png"

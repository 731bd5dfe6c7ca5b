#!/usr/bin/env bash
# Installs what is missing, builds sgfx and renders the proving-ground demo headless to a PNG.
# Extra arguments go to the demo (see `build/demos/polygon --help`).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build --target polygon -j "$(nproc)"
if [ $# -eq 0 ]; then set -- --out polygon.png --size 1280x720; fi
./build/demos/polygon "$@"

#!/usr/bin/env bash
# Regenerates docs/materials.md's images (docs/images/materials/): every shared glTF sample model
# as sgfx-view draws it by default (sky light, sun, ground), and the before/after pairs of
# mirrored parts, image-based light and transmission.
#   scripts/material-figures.sh [BUILD_DIR] [OUT_DIR] [ASSETS_DIR]
#     (defaults: build, docs/images/materials, ../shared/assets/gltf)
# About three minutes on two cores.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-docs/images/materials}
assets=${3:-../shared/assets/gltf}
mkdir -p "$out"
for tool in demos/sgfx-view demos/materials_figure; do
  [ -x "$build/$tool" ] || { echo "material-figures: $build/$tool not built" >&2; exit 1; }
done
view() { "$build/demos/sgfx-view" --size 320x240 "$@" > /dev/null; echo "material-figures: ${*: -1}"; }

# Each model as a new user sees it: sgfx-view's defaults. The .gltf, else the .glb.
for dir in "$assets"/*/; do
  name=$(basename "$dir")
  file="$dir/glTF/$name.gltf"
  [ -f "$file" ] || file="$dir/glTF-Binary/$name.glb"
  [ -f "$file" ] || { echo "material-figures: no glTF for $name" >&2; continue; }
  "$build/demos/sgfx-view" --size 320x240 --out "$out/$name.png" "$file" > /dev/null
  echo "material-figures: $name.png"
done

# Image-based light: the metal/roughness sphere grid without and with the sky's light.
spheres="$assets/MetalRoughSpheresNoTextures/glTF/MetalRoughSpheresNoTextures.gltf"
"$build/demos/sgfx-view" --size 480x320 --env none --out "$out/ibl_before.png" "$spheres" > /dev/null
"$build/demos/sgfx-view" --size 480x320 --env sky --out "$out/ibl_after.png" "$spheres" > /dev/null
echo "material-figures: ibl_before.png, ibl_after.png"

# Mirrored parts and transmission.
"$build/demos/materials_figure" --out-dir "$out" --size 480x320 \
  --transmission-model "$assets/TransmissionRoughnessTest/glTF/TransmissionRoughnessTest.gltf" |
  sed 's/^wrote .*\//material-figures: /'

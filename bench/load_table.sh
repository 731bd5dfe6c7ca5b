#!/usr/bin/env bash
# Load time and peak memory of the loaders: the largest shared model, and the proving ground
# exported by the demo as .glb, .gltf and .obj. One process per file (peak RSS is per process),
# 5 loads each (median). Usage: bench/load_table.sh [BUILD_DIR] [SCALE]
set -euo pipefail
shopt -s nullglob
cd "$(dirname "$0")/.."
. bench/common.sh
build=${1:-build}
scale=${2:-1}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/demos/polygon" --scale "$scale" --export-gltf "$work/polygon.glb" >/dev/null
"$build/demos/polygon" --scale "$scale" --export-gltf "$work/polygon.gltf" >/dev/null
"$build/demos/polygon" --scale "$scale" --export-obj "$work/polygon.obj" >/dev/null
stamp "$build"
echo
echo "| file | size (MB) | triangles | load ms (median of 5) | peak RSS (MB) |"
echo "|---|---:|---:|---:|---:|"
for f in ../shared/assets/gltf/MetalRoughSpheresNoTextures/glTF/MetalRoughSpheresNoTextures.gltf \
         "$work/polygon.glb" "$work/polygon.gltf" "$work/polygon.obj"; do
  line=$("$build/bench/load_model" "$f" --repeat 5)
  # A .gltf's size includes the .bin files beside it.
  if [[ $f == *.gltf ]]; then size=$(cat "$f" "$(dirname "$f")"/*.bin 2>/dev/null | wc -c); else size=$(wc -c <"$f"); fi
  printf '| %s | %.1f | %s | %s | %s |\n' "$(basename "$f")" "$(echo "$size / 1048576" | bc -l)" \
    "$(echo "$line" | field triangles)" "$(echo "$line" | field ms_median)" "$(echo "$line" | field peak_rss_mb)"
done

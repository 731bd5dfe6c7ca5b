#!/usr/bin/env bash
# Foreign content (issue 24, Must 7): the proving ground written at full detail by another program
# (`polygon --export-gltf` and `--export-obj`: no levels of detail, no instancing hints), loaded as
# a new user would: sgfx through loadModel (`sgfx-view FILE --bench N --orbit`), OpenSceneGraph 3.6
# through osgDB's OBJ plugin (`osg_view FILE --frames N --orbit`). Both orbit the model the same
# way (eye at 1.5x the bounding radius, 30 degrees elevation, 60 degree vertical field of view,
# the azimuth advancing a full turn over the N frames; demos/view/main.cpp orbitCamera), without
# sgfx-view's ground plane, at two sizes, fog off and on (sgfx: its height fog hiding half of the
# model's centre; OSG: EXP2 fog of the density that does the same from the orbit's distance).
# A third sgfx series loads the glTF with levels of detail made at load (`--auto-lod`: every mesh
# simplified, each level within a pixel of full detail). Every round runs all twelve programs once
# (interleaved, so machine drift hits all of them), malloc pinned (common.sh). Ratios are medians of the per-round ratios, not ratios of medians.
#
# Columns: ms/frame (median over rounds of each run's median), x OSG; per-pixel cost: the frame
# time's growth from the small to the large size over the added pixels, ns/pixel, and its ratio;
# fog overhead: (fog on / fog off - 1) per round, the median.
#
# Usage: bench/foreign_table.sh [BUILD_DIR] [ROUNDS] [FRAMES] [LARGE,SMALL] [polygon export flags...]
#   e.g. bench/foreign_table.sh build 5 30 1280x720,320x180
#        bench/foreign_table.sh build 1 2 64x36,32x18 --scale 0.05   (the ctest smoke run)
# Extra sgfx-view flags through SGFX_VIEW_FLAGS (e.g. "--env none"), osg_view's through OSG_VIEW_FLAGS.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh" # malloc pins, field, median, median_ratio, stamp
build=${1:-build}; rounds=${2:-5}; frames=${3:-30}; sizes=${4:-1280x720,320x180}
shift $(($# < 4 ? $# : 4))
export_flags=("$@")
for exe in demos/polygon demos/sgfx-view bench/osg_view; do
  [ -x "$build/$exe" ] || { echo "foreign_table: $build/$exe not built (osg_view needs OpenSceneGraph)" >&2; exit 1; }
done
IFS=, read -r large small <<<"$sizes"
[[ $large =~ ^[0-9]+x[0-9]+$ && $small =~ ^[0-9]+x[0-9]+$ ]] ||
  { echo "foreign_table: sizes '$sizes' are not LARGE,SMALL (WxH,WxH)" >&2; exit 2; }
pixels() { echo $((${1%x*} * ${1#*x})); }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$build/demos/polygon" --export-gltf "$tmp/city.glb" "${export_flags[@]}" >/dev/null
"$build/demos/polygon" --export-obj "$tmp/city.obj" "${export_flags[@]}" >"$tmp/export.txt"
scene=$(sed -n 's/^scene: \([0-9]*\) triangles.* \([0-9]*\) drawables.*/\1 triangles, \2 drawables/p' "$tmp/export.txt")

read -ra sgfx_flags <<<"${SGFX_VIEW_FLAGS:-}"
read -ra osg_flags <<<"${OSG_VIEW_FLAGS:-}"
# run NAME COMMAND...: one run; appends its median ms to the array NAME. A run without a BENCH
# line (a crash, a GL error message is not one) stops the table.
run() {
  local name=$1; shift
  local out; out=$("$@" 2>"$tmp/stderr" | grep '^BENCH') ||
    { echo "foreign_table: no BENCH line from: $*" >&2; cat "$tmp/stderr" >&2; exit 1; }
  grep -q 'GL:' "$tmp/stderr" && { echo "foreign_table: GL errors from: $*" >&2; cat "$tmp/stderr" >&2; exit 1; }
  local ms; ms=$(echo "$out" | field median_ms)
  eval "$name+=(\"$ms\")"
  case $name in sgfx_* | lod_*) eval "${name%%_*}_load+=(\"$(echo "$out" | field load_ms)\")" ;; esac
  echo "  $name: $ms ms" >&2
}
names=()
sgfx_load=(); lod_load=()
for s in L S; do for f in off on; do for p in sgfx lod osg; do names+=("${p}_${s}_${f}"); eval "${p}_${s}_${f}=()"; done; done; done
for ((r = 0; r < rounds; ++r)); do
  echo "round $((r + 1)) of $rounds" >&2
  for s in L S; do
    size=$large; [ $s = S ] && size=$small
    for f in off on; do
      run "sgfx_${s}_${f}" "$build/demos/sgfx-view" "$tmp/city.glb" --bench "$frames" --orbit --size "$size" \
        --no-ground --fog "$f" "${sgfx_flags[@]}"
      run "lod_${s}_${f}" "$build/demos/sgfx-view" "$tmp/city.glb" --bench "$frames" --orbit --size "$size" \
        --no-ground --fog "$f" --auto-lod "${sgfx_flags[@]}"
      run "osg_${s}_${f}" "$build/bench/osg_view" "$tmp/city.obj" --osg-options noRotation --frames "$frames" \
        --orbit --size "$size" --no-ground --fog "$f" "${osg_flags[@]}"
    done
  done
done

# Per-round derived series: the per-pixel cost (ns/pixel) and the fog overhead (%).
dpx=$(($(pixels "$large") - $(pixels "$small")))
for p in sgfx osg; do for f in off on; do
  eval "${p}_px_${f}=()"
  for ((r = 0; r < rounds; ++r)); do
    eval "${p}_px_${f}+=(\"\$(awk -v a=\${${p}_L_${f}[$r]} -v b=\${${p}_S_${f}[$r]} -v n=$dpx 'BEGIN { print (a - b) * 1e6 / n }')\")"
  done
done; done
fmt() { awk -v x="$1" -v f="$2" 'BEGIN { printf f, x }'; }
pct() { awk -v x="$1" 'BEGIN { printf "%+.0f %%", (x - 1) * 100 }'; }
# One table row: the leading cells, then sgfx's and OSG's medians and the median per-round ratio
# of the two named series.
pair_row() {
  local cells=$1
  eval "local a=(\"\${$2[@]}\") o=(\"\${$3[@]}\")"
  echo "| $cells | $(fmt "$(median "${a[@]}")" %.1f) | $(fmt "$(median "${o[@]}")" %.1f) | $(fmt "$(median_ratio a o)" %.2f) |"
}

stamp "$build"
echo
echo "Foreign content: the proving ground exported at full detail ($scene; ${export_flags[*]:-default scale}), sgfx loading the glTF (metallic-roughness; sgfx-view flags: ${SGFX_VIEW_FLAGS:-none}), OSG the OBJ (osg_view flags: ${OSG_VIEW_FLAGS:-none}), orbit camera, $frames frames a run, $rounds interleaved rounds."
echo
# frame_table SERIES LABEL: the series' frames against OSG's, both sizes, fog off and on.
frame_table() {
  echo "| size | fog | $2 ms | OSG ms | $2 × OSG |"
  echo "|---|---|---:|---:|---:|"
  for s in L S; do
    size=$large; [ $s = S ] && size=$small
    for f in off on; do pair_row "$size | $f" "${1}_${s}_${f}" "osg_${s}_${f}"; done
  done
}
frame_table sgfx sgfx
echo
echo "The same with levels of detail made at load (sgfx-view --auto-lod: GltfOptions::autoLod, 1 pixel); load time (median): $(median "${lod_load[@]}") ms with them, $(median "${sgfx_load[@]}") ms without."
echo
frame_table lod sgfx+LOD
echo
echo "Per-pixel cost: (ms at $large − ms at $small) / $dpx added pixels, per round; medians."
echo
echo "| fog | sgfx ns/pixel | OSG ns/pixel | sgfx × OSG |"
echo "|---|---:|---:|---:|"
for f in off on; do pair_row "$f" "sgfx_px_${f}" "osg_px_${f}"; done
echo
echo "Fog overhead: median over rounds of (fog on / fog off − 1)."
echo
echo "| size | sgfx | OSG |"
echo "|---|---:|---:|"
for s in L S; do
  size=$large; [ $s = S ] && size=$small
  eval "son=(\"\${sgfx_${s}_on[@]}\"); soff=(\"\${sgfx_${s}_off[@]}\"); oon=(\"\${osg_${s}_on[@]}\"); ooff=(\"\${osg_${s}_off[@]}\")"
  echo "| $size | $(pct "$(median_ratio son soff)") | $(pct "$(median_ratio oon ooff)") |"
done

#!/bin/bash
# Per-pixel cost, sgfx against OSG on the same files (docs/performance.md, "Per-pixel cost on
# foreign content"): bench/pixel_cost (sgfx, loadModel, no effects: one sun and an ambient light)
# on the OBJ as it draws by default and at the floor (constant shading, unorm8 target, one
# submission), and on the glTF; bench/osg_view (OpenSceneGraph 3.6, fixed function, drawing into
# OSMesa's own buffer) on the OBJ. Same orbit (eye at 1.5x the bounding radius, 30 degrees up, 60
# degree field of view, a full turn over the frames: pixel_cost --turn). Per round every program runs at 1280x720 and 320x180, interleaved; the
# per-pixel cost is the difference, and the ratio column is the median of its per-round ratios.
#   bench/pixel_vs_osg.sh [BUILD_DIR] [ROUNDS] [FRAMES] [FILE.glb] [FILE.obj]
# PIXEL_TIME=wall times frames by wall time (default cpu: the CPU time of all threads, steadier on a
# shared machine; both programs take the flag --cpu-time).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh"
build=${1:-build}; rounds=${2:-5}; frames=${3:-12}; glb=${4:-/tmp/city.glb}; obj=${5:-/tmp/city.obj}
time_flag=--cpu-time
[ "${PIXEL_TIME:-cpu}" = wall ] && time_flag=
floor=(--target unorm8 --submit-triangles 0 --shading constant)
ms() { "$@" | field median_ms; }
sg=(--turn --frames "$frames" $time_flag) # osg_view --orbit's views
add() { eval "$1+=(\"$2\")"; } # add ARRAY VALUE
names=(obj_default obj_floor glb_default osg)
for n in "${names[@]}"; do eval "${n}_L=(); ${n}_S=()"; done
for ((r = 0; r < rounds; ++r)); do
  for s in L S; do
    size=1280x720; [ $s = S ] && size=320x180
    add obj_default_$s "$(ms "$build/bench/pixel_cost" "$obj" --size $size "${sg[@]}")"
    add obj_floor_$s "$(ms "$build/bench/pixel_cost" "$obj" --size $size "${sg[@]}" "${floor[@]}")"
    add glb_default_$s "$(ms "$build/bench/pixel_cost" "$glb" --size $size "${sg[@]}")"
    add osg_$s "$(ms "$build/bench/osg_view" "$obj" --osg-options noRotation --frames "$frames" --orbit \
      --size $size --no-ground $time_flag)"
  done
  echo "round $((r + 1)) of $rounds" >&2
done
for n in "${names[@]}"; do
  eval "${n}_px=()"
  for ((r = 0; r < rounds; ++r)); do
    eval "${n}_px+=(\"\$(awk -v a=\${${n}_L[$r]} -v b=\${${n}_S[$r]} 'BEGIN { print a - b }')\")"
  done
done
stamp "$build"
echo "pixel_vs_osg: ${PIXEL_TIME:-cpu} time, $rounds interleaved rounds of $frames frames"
echo
echo "| program | 1280×720 ms | 320×180 ms | per-pixel ms | per-pixel × OSG |"
echo "|---|---:|---:|---:|---:|"
for n in "${names[@]}"; do
  eval "l=(\"\${${n}_L[@]}\"); s=(\"\${${n}_S[@]}\"); p=(\"\${${n}_px[@]}\")"
  printf '| %s | %.1f | %.1f | %.1f | %.2f |\n' "$n" "$(median "${l[@]}")" "$(median "${s[@]}")" \
    "$(median "${p[@]}")" "$(median_ratio "${n}_px" osg_px)"
done

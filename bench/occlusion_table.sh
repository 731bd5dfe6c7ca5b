#!/usr/bin/env bash
# Occlusion culling on foreign content (issue 24, Must 3, plan C3): the proving ground exported as
# glTF at full detail (as bench/foreign_table.sh makes it), drawn by sgfx-view with
# RendererOptions::occlusionCulling off and on (--occlusion), from the foreign table's orbit
# camera and from a low home camera (--pitch 2: the city seen across its near streets), at two
# sizes. Each round runs every case once (interleaved), malloc pinned (common.sh); the ratio is
# the median of the per-round ratios (on / off), the culled share the mean per frame of
# FrameStats::occlusionCulled / FrameStats::items.
#
# Usage: bench/occlusion_table.sh [BUILD_DIR] [ROUNDS] [FRAMES] [LARGE,SMALL] [polygon export flags...]
#   e.g. bench/occlusion_table.sh build 5 20 1280x720,320x180
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh" # malloc pins, field, median, median_ratio, stamp
build=${1:-build}; rounds=${2:-5}; frames=${3:-20}; sizes=${4:-1280x720,320x180}
shift $(($# < 4 ? $# : 4))
export_flags=("$@")
for exe in demos/polygon demos/sgfx-view; do
  [ -x "$build/$exe" ] || { echo "occlusion_table: $build/$exe not built" >&2; exit 1; }
done
IFS=, read -r large small <<<"$sizes"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$build/demos/polygon" --export-gltf "$tmp/city.glb" "${export_flags[@]}" >/dev/null
cams=(orbit low)
camflags() { if [ "$1" = orbit ]; then echo "--orbit"; else echo "--pitch 2"; fi; }
run() { # NAME SIZE CAMERA [--occlusion]: appends median ms to NAME, the culled share to NAME_c
  local name=$1 size=$2 cam=$3; shift 3
  local out
  # shellcheck disable=SC2046
  out=$("$build/demos/sgfx-view" "$tmp/city.glb" --bench "$frames" $(camflags "$cam") --size "$size" \
    --no-ground --fog off "$@" 2>"$tmp/stderr" | grep '^BENCH') ||
    { echo "occlusion_table: no BENCH line" >&2; cat "$tmp/stderr" >&2; exit 1; }
  eval "$name+=(\"$(echo "$out" | field median_ms)\"); ${name}_c+=(\"$(echo "$out" | field occlusion_culled)\")"
  echo "  $name: $(echo "$out" | field median_ms) ms" >&2
}
for s in L S; do for c in "${cams[@]}"; do for m in off on; do eval "${c}_${s}_${m}=(); ${c}_${s}_${m}_c=()"; done; done; done
for ((r = 0; r < rounds; ++r)); do
  echo "round $((r + 1)) of $rounds" >&2
  for s in L S; do
    size=$large; [ $s = S ] && size=$small
    for c in "${cams[@]}"; do
      run "${c}_${s}_off" "$size" "$c"
      run "${c}_${s}_on" "$size" "$c" --occlusion
    done
  done
done
fmt() { awk -v x="$1" -v f="$2" 'BEGIN { printf f, x }'; }
stamp "$build"
echo
echo "Occlusion culling, the proving ground's glTF in sgfx-view, $frames frames a run, $rounds interleaved rounds."
echo
echo "| camera | size | off ms | on ms | on / off | culled share |"
echo "|---|---|---:|---:|---:|---:|"
for c in "${cams[@]}"; do for s in L S; do
  size=$large; [ $s = S ] && size=$small
  eval "a=(\"\${${c}_${s}_on[@]}\"); b=(\"\${${c}_${s}_off[@]}\"); k=(\"\${${c}_${s}_on_c[@]}\")"
  echo "| $c | $size | $(fmt "$(median "${b[@]}")" %.1f) | $(fmt "$(median "${a[@]}")" %.1f) | $(fmt "$(median_ratio a b)" %.3f) | $(fmt "$(median "${k[@]}")" %.3f) |"
done; done

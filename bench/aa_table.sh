#!/usr/bin/env bash
# Anti-aliasing cost on the proving ground: alternates `polygon --bench` with --aa none, msaa4,
# ssaa2, fxaa, taa, smaa (high preset, luma edges) and smaa-t2x, ROUNDS times (interleaved), at
# each size; prints median ms/frame and the ratio of each mode to no AA (fog off, so only AA differs).
# Usage: bench/aa_table.sh [BUILD_DIR] [ROUNDS] [SIZE:FRAMES ...]   (default 1280x720:24 1920x1080:16)
set -euo pipefail
source "$(dirname "$0")/common.sh"
build=${1:-build}; rounds=${2:-3}; shift $(( $# < 2 ? $# : 2 ))
sizes=("$@"); [ ${#sizes[@]} -gt 0 ] || sizes=(1280x720:24 1920x1080:16)
modes=(none msaa4 ssaa2 fxaa taa smaa smaa-t2x)
stamp "$build"
echo
echo "| size | none ms (FPS) | MSAA 4x | SSAA 2x | FXAA | TAA | SMAA | SMAA T2x |"
echo "|---|---|---|---|---|---|---|---|"
for entry in "${sizes[@]}"; do
  size=${entry%%:*}; frames=${entry##*:}
  declare -A runs=()
  for ((r = 0; r < rounds; ++r)); do
    for m in "${modes[@]}"; do
      runs[$m]+=" $("$build/demos/polygon" --bench "$frames" --size "$size" --fog off --aa "$m" | grep '^BENCH' | field ms_per_frame)"
    done
  done
  for m in "${modes[@]}"; do echo "# $size $m: ${runs[$m]}" >&2; done
  base=$(median ${runs[none]})
  row="| $size | $(awk -v m="$base" 'BEGIN { printf "%.1f (%.1f)", m, 1000 / m }')"
  for m in msaa4 ssaa2 fxaa taa smaa smaa-t2x; do
    row+=" | $(awk -v m="$(median ${runs[$m]})" -v b="$base" 'BEGIN { printf "%.1f ms, %.2fx", m, m / b }')"
  done
  echo "$row |"
  unset runs
done

#!/usr/bin/env bash
# Volume and sky cost on the proving ground: `polygon --bench` from a fixed view towards the
# smoke cloud (`--smoke`, 40 × 40 × 24 m of noise density with single scattering of the sun),
# with each raymarch option and with slicing, and the sky alone, alternated ROUNDS times
# (interleaved); medians and the ratio to the scene without them.
# Usage: bench/volume_table.sh [BUILD_DIR] [ROUNDS] [SIZE] [FRAMES]   (default build 2 1280x720 6)
set -euo pipefail
source "$(dirname "$0")/common.sh"
build=${1:-build}; rounds=${2:-2}; size=${3:-1280x720}; frames=${4:-6}
look=(--look 0,-90,30,0,0,20 --fog off)
declare -A args=(
  [off]=""
  [smoke]="--smoke"
  ["smoke, empty-space skipping"]="--smoke --volume-skip on"
  ["smoke, jitter"]="--smoke --volume-jitter"
  ["smoke, half resolution"]="--smoke --volume-half"
  ["smoke, 128 steps"]="--smoke --volume-steps 128"
  ["smoke, slicing 64"]="--smoke --volume-slices 64"
  ["smoke, slicing 128"]="--smoke --volume-slices 128"
  ["sky (17 h)"]="--sky 17"
  ["sky (17 h), per pixel"]="--sky 17 --sky-direct"
)
order=(off smoke "smoke, empty-space skipping" "smoke, jitter" "smoke, half resolution" "smoke, 128 steps" "smoke, slicing 64" "smoke, slicing 128" "sky (17 h)" "sky (17 h), per pixel")
declare -A ms=()
for ((r = 0; r < rounds; ++r)); do
  for c in "${order[@]}"; do
    echo "round $((r + 1))/$rounds: $c" >&2
    # shellcheck disable=SC2086
    out=$("$build/demos/polygon" --bench "$frames" --size "$size" "${look[@]}" ${args[$c]})
    ms[$c]+=" $(grep '^BENCH' <<<"$out" | field ms_per_frame)"
  done
done
off=$(median ${ms[off]})
echo "| $size | ms/frame (FPS) | vs off |"
echo "|---|---|---|"
for c in "${order[@]}"; do
  m=$(median ${ms[$c]})
  awk -v c="$c" -v m="$m" -v o="$off" 'BEGIN { printf "| %s | %.1f (%.1f) | %.2f |\n", c, m, 1000 / m, m / o }'
done

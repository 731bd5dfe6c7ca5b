#!/usr/bin/env bash
# Volume and sky cost on the proving ground: `polygon --bench` from a fixed view towards the
# smoke cloud (`--smoke`, 40 × 40 × 24 m of noise density with single scattering of the sun),
# with each raymarch option, with slicing and with splatting, and the sky alone, alternated ROUNDS
# times (interleaved); medians and the ratio to the scene without them. Then the quality table:
# one still of the same view per smoke mode at ERROR_SIZE, mean error (8-bit sRGB steps, over the
# pixels the smoke covers) against a 1024-step march, in the default 8-bit sRGB target and in an
# RGBA32F target (bench/png_error.py; slices blended straight into 8 bits lose their small
# opacities; splats accumulate in a float target of their own).
# Usage: bench/volume_table.sh [BUILD_DIR] [ROUNDS] [SIZE] [FRAMES] [ERROR_SIZE] [ONLY]
#        (default build 2 1280x720 6 320x180; ONLY: a regex, the rows to run besides "off",
#        e.g. splatting)
set -euo pipefail
source "$(dirname "$0")/common.sh"
build=${1:-build}; rounds=${2:-2}; size=${3:-1280x720}; frames=${4:-6}; errsize=${5:-320x180}
only=${6:-}
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
  ["smoke, splatting 2 m"]="--smoke --volume-splats 2"
  ["smoke, splatting 1 m"]="--smoke --volume-splats 1"
  ["smoke, splatting 0.5 m"]="--smoke --volume-splats 0.5"
  ["sky (17 h)"]="--sky 17"
  ["sky (17 h), per pixel"]="--sky 17 --sky-direct"
)
order=(off smoke "smoke, empty-space skipping" "smoke, jitter" "smoke, half resolution" "smoke, 128 steps" "smoke, slicing 64" "smoke, slicing 128" "smoke, splatting 2 m" "smoke, splatting 1 m" "smoke, splatting 0.5 m" "sky (17 h)" "sky (17 h), per pixel")
quality=(smoke "smoke, jitter" "smoke, half resolution" "smoke, 128 steps" "smoke, slicing 64" "smoke, slicing 128" "smoke, splatting 2 m" "smoke, splatting 1 m" "smoke, splatting 0.5 m")
if [[ -n $only ]]; then
  keep() { local c; for c in "$@"; do [[ $c == off || $c =~ $only ]] && echo "$c"; done; }
  mapfile -t order < <(keep "${order[@]}")
  mapfile -t quality < <(keep "${quality[@]}")
fi
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
stamp "$build"
echo
echo "| $size | ms/frame (FPS) | vs off |"
echo "|---|---|---|"
for c in "${order[@]}"; do
  m=$(median ${ms[$c]})
  awk -v c="$c" -v m="$m" -v o="$off" 'BEGIN { printf "| %s | %.1f (%.1f) | %.2f |\n", c, m, 1000 / m, m / o }'
done

# Quality: mean error against a 1024-step march, over the smoke's pixels.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
declare -A err=()
for target in srgb8 rgba32f; do
  still() { "$build/demos/polygon" --size "$errsize" "${look[@]}" --color-target "$target" "$@" >/dev/null; }
  still --out "$tmp/off.png"
  still --smoke --volume-steps 1024 --out "$tmp/ref.png"
  for c in "${quality[@]}"; do
    # shellcheck disable=SC2086
    still ${args[$c]} --out "$tmp/mode.png"
    err[$c,$target]=$(python3 "$(dirname "$0")/png_error.py" "$tmp/mode.png" "$tmp/ref.png" "$tmp/off.png" | field mean_error)
  done
done
echo
echo "| $errsize, vs 1024 steps | mean error, 8-bit sRGB target | mean error, RGBA32F target |"
echo "|---|---|---|"
for c in "${quality[@]}"; do
  echo "| $c | ${err[$c,srgb8]} | ${err[$c,rgba32f]} |"
done

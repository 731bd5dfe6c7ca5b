#!/usr/bin/env bash
# What issue 25's material features cost on the proving ground at 1280x720 (or SIZE), interleaved:
# each round runs every configuration once, ROUNDS rounds; per configuration the median of its
# per-round ratio to the round's plain frame (a ratio of medians swings with a noisy machine).
#   none        the proving ground, no effects (sgfx-bench)
#   env         the sky's image-based light instead of the flat ambient light
#   windscreen  a transmissive glass pane 1.5 m ahead of the eye filling the view (the copy of the
#               opaque scene with its mip chain, and every pixel through the transmission shader)
#   lamps N     polygon --bench at dusk with N street lamps (0, 8, 200); ratio to 0 lamps
# Usage: bench/materials_table.sh [BUILD_DIR] [ROUNDS] [FRAMES] [SIZE]   (default build 5 20 1280x720)
set -euo pipefail
source "$(dirname "$0")/common.sh"
build=${1:-build}; rounds=${2:-5}; frames=${3:-20}; size=${4:-1280x720}
bench() { # CONFIG: median ms/frame of sgfx-bench's row
  "$build/demos/sgfx-bench" --sizes "$size" --frames "$frames" --warmup 3 --effects "$1" |
    awk -F'|' -v c="$1" '$2 ~ "^ *"c" *$" { gsub(/ /, "", $3); print $3; exit }'
}
lamps() { "$build/demos/polygon" --bench "$frames" --size "$size" --fog off --lamps "$1" | grep '^BENCH' | field median_ms; }
declare -A runs=() ratios=()
configs=(none env windscreen lamps0 lamps8 lamps200)
for ((r = 0; r < rounds; ++r)); do
  declare -A ms=()
  for c in "${configs[@]}"; do
    case $c in
      lamps*) ms[$c]=$(lamps "${c#lamps}") ;;
      *) ms[$c]=$(bench "$c") ;;
    esac
    runs[$c]+=" ${ms[$c]}"
  done
  for c in "${configs[@]}"; do
    case $c in lamps*) base=${ms[lamps0]} ;; *) base=${ms[none]} ;; esac
    ratios[$c]+=" $(awk -v a="${ms[$c]}" -v b="$base" 'BEGIN { printf "%.4f", a / b }')"
  done
done
for c in "${configs[@]}"; do echo "# $size $c ms:${runs[$c]} ratio:${ratios[$c]}" >&2; done
stamp "$build"
echo
echo "| configuration ($size, $frames frames, $rounds interleaved rounds) | median ms/frame | median of per-round ratios |"
echo "|---|---:|---:|"
for c in "${configs[@]}"; do
  case $c in
    none) label="proving ground, no effects" ;;
    env) label="+ image-based light (sky)" ;;
    windscreen) label="+ transmissive windscreen filling the view" ;;
    lamps0) label="dusk, 0 lamps (polygon --lamps 0)" ;;
    lamps8) label="dusk, 8 lamps (9 lights: light list)" ;;
    lamps200) label="dusk, 200 lamps (light list)" ;;
  esac
  case $c in lamps*) of="x 0 lamps" ;; *) of="x none" ;; esac
  printf '| %s | %.1f | %.2f %s |\n' "$label" "$(median ${runs[$c]})" "$(median ${ratios[$c]})" "$of"
done

#!/usr/bin/env bash
# Many lights on the proving ground: alternates `polygon --bench` at dusk with --lamps 0, 7, 8 and
# 200 (spot lights with a range, plus the low sun: 7 lamps are 8 lights, the most the unrolled loop
# takes; 8 and more use the light list) and the day scene (one sun, the unrolled loop), ROUNDS
# times, interleaved; prints median ms/frame and the ratio to 0 lamps.
# Fog off, so only the lights differ. BASELINE=path/to/polygon adds the day scene rendered by
# another build (the code before the light list) to every round, to show the unrolled path kept
# its speed.
# Usage: bench/lights_table.sh [BUILD_DIR] [ROUNDS] [FRAMES] [SIZE]   (default build 3 20 1280x720)
set -euo pipefail
source "$(dirname "$0")/common.sh"
build=${1:-build}; rounds=${2:-3}; frames=${3:-20}; size=${4:-1280x720}
configs=(day lamps0 lamps7 lamps8 lamps200)
[ -n "${BASELINE:-}" ] && configs+=(baseline)
run() {
  case $1 in
    day) "$build/demos/polygon" --bench "$frames" --size "$size" --fog off ;;
    baseline) "$BASELINE" --bench "$frames" --size "$size" --fog off ;;
    lamps*) "$build/demos/polygon" --bench "$frames" --size "$size" --fog off --lamps "${1#lamps}" ;;
  esac | grep '^BENCH' | field median_ms
}
declare -A runs=()
for ((r = 0; r < rounds; ++r)); do
  for c in "${configs[@]}"; do runs[$c]+=" $(run "$c")"; done
done
for c in "${configs[@]}"; do echo "# $size $c: ${runs[$c]}" >&2; done
base=$(median ${runs[lamps0]})
stamp "$build"
echo
echo "| scene ($size, $frames frames, median of $rounds) | ms/frame | FPS | x 0 lamps |"
echo "|---|---:|---:|---:|"
for c in "${configs[@]}"; do
  m=$(median ${runs[$c]})
  case $c in
    day) label="day: sun + sky ambient (unrolled loop, 1 light)" ;;
    baseline) label="day, baseline build (BASELINE)" ;;
    lamps0) label="dusk, 0 lamps (low sun + ambient)" ;;
    lamps7) label="dusk, 7 lamps + sun (8 lights: unrolled loop, attenuated)" ;;
    lamps8) label="dusk, 8 lamps + sun (9 lights: light list)" ;;
    lamps200) label="dusk, 200 lamps + sun (light list)" ;;
  esac
  awk -v l="$label" -v m="$m" -v b="$base" 'BEGIN { printf "| %s | %.1f | %.1f | %.2f |\n", l, m, 1000 / m, m / b }'
done

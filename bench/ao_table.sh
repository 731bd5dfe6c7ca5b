#!/usr/bin/env bash
# Ambient occlusion cost on the proving ground: alternates `polygon --bench` with AO off and on
# for m = 16, 32, 64 samples at full and half resolution, ROUNDS times (interleaved), at each
# size; prints median ms/frame, the ratio to AO off, and the GPU time of each AO pass (timer
# queries; on llvmpipe "GPU" time is the rasterizer threads' time).
# Usage: bench/ao_table.sh [BUILD_DIR] [ROUNDS] [SIZE:FRAMES ...]   (default 1280x720:24 1920x1080:16)
set -euo pipefail
source "$(dirname "$0")/common.sh"
build=${1:-build}; rounds=${2:-3}; shift $(( $# < 2 ? $# : 2 ))
sizes=("$@"); [ ${#sizes[@]} -gt 0 ] || sizes=(1280x720:24 1920x1080:16)
configs=(off "16" "32" "64" "16h" "32h" "64h")
stamp "$build"
echo
echo "| size | AO | ms/frame (FPS) | vs off | G-buffer ms | occlusion ms | blur ms |"
echo "|---|---|---|---|---|---|---|"
for entry in "${sizes[@]}"; do
  size=${entry%%:*}; frames=${entry##*:}
  declare -A ms=() gb=() oc=() bl=()
  for ((r = 0; r < rounds; ++r)); do
    for c in "${configs[@]}"; do
      args=(--fog off --ao off)
      if [ "$c" != off ]; then
        args=(--fog off --ao on --ao-samples "${c%h}"); [[ "$c" == *h ]] && args+=(--ao-half)
      fi
      out=$("$build/demos/polygon" --bench "$frames" --size "$size" "${args[@]}")
      ms[$c]+=" $(grep '^BENCH' <<<"$out" | field ms_per_frame)"
      passes=$(grep '^PASSES' <<<"$out")
      gb[$c]+=" $(field ao_g-buffer <<<"$passes")"; oc[$c]+=" $(field ao_occlusion <<<"$passes")"; bl[$c]+=" $(field ao_blur <<<"$passes")"
    done
  done
  off=$(median ${ms[off]})
  for c in "${configs[@]}"; do
    m=$(median ${ms[$c]})
    label="off"; [ "$c" != off ] && label="m=${c%h}$([[ "$c" == *h ]] && echo ', half' || echo ', full')"
    if [ "$c" = off ]; then
      printf '| %s | %s | %.1f (%.1f) | 1.00 | - | - | - |\n' "$size" "$label" "$m" "$(awk -v m="$m" 'BEGIN{print 1000/m}')"
    else
      printf '| %s | %s | %.1f (%.1f) | %.2f | %.1f | %.1f | %.1f |\n' "$size" "$label" "$m" \
        "$(awk -v m="$m" 'BEGIN{print 1000/m}')" "$(awk -v m="$m" -v o="$off" 'BEGIN{print m/o}')" \
        "$(median ${gb[$c]})" "$(median ${oc[$c]})" "$(median ${bl[$c]})"
    fi
    echo "# $size $c: ${ms[$c]}" >&2
  done
  unset ms gb oc bl
done

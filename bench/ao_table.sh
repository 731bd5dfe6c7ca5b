#!/usr/bin/env bash
# Ambient occlusion cost on the proving ground: alternates `polygon --bench` with AO off and with
# each AO configuration, ROUNDS times (interleaved), at each size; prints the median ms/frame,
# AO/plain as the median of the per-round ratios (each AO run against the AO-off run of its own
# round: the machine is shared and noisy), and the GPU time of each AO pass (timer queries; on
# llvmpipe "GPU" time is the rasterizer threads' time).
# Configurations: m = 16, 32, 64 at full and half resolution (G-buffer normals, bilateral blur:
# today's path), m = 32 full resolution with normals from depth ("32, depth"), and temporal
# (half resolution, 8 taps a frame, accumulated) with normals from depth or from the G-buffer;
# "floor" (`polygon --ao floor`, not in the default list): what any AO reading a depth pre-pass
# pays before it computes anything, its half-size pass in the occlusion column.
# Usage: bench/ao_table.sh [BUILD_DIR] [ROUNDS] [SIZE:FRAMES ...]   (default 1280x720:24 1920x1080:16)
# AO_CONFIGS="off 32 td" picks configurations (off first; default all).
set -euo pipefail
source "$(dirname "$0")/common.sh"
build=${1:-build}; rounds=${2:-3}; shift $(( $# < 2 ? $# : 2 ))
sizes=("$@"); [ ${#sizes[@]} -gt 0 ] || sizes=(1280x720:24 1920x1080:16)
read -r -a configs <<<"${AO_CONFIGS:-off 16 32 64 16h 32h 64h 32d td tg}"
stamp "$build"
echo
echo "| size | AO | ms/frame (FPS) | AO/plain | depth pre-pass ms | normals ms | occlusion ms | blur or accumulate ms |"
echo "|---|---|---|---|---|---|---|---|"
args_of() { # the polygon arguments of configuration $1
  case $1 in
    off) echo --fog off --ao off ;;
    floor) echo --fog off --ao floor ;;
    td) echo --fog off --ao on --ao-temporal --ao-normals depth ;;
    tg) echo --fog off --ao on --ao-temporal --ao-normals gbuffer ;;
    *d) echo --fog off --ao on --ao-samples "${1%d}" --ao-normals depth ;;
    *h) echo --fog off --ao on --ao-samples "${1%h}" --ao-half ;;
    *) echo --fog off --ao on --ao-samples "$1" ;;
  esac
}
label_of() {
  case $1 in
    off) echo off ;; floor) echo "floor: pre-pass, a half-size pass, one read" ;; td) echo "temporal, depth normals" ;; tg) echo "temporal, G-buffer normals" ;;
    *d) echo "m=${1%d}, full, depth normals" ;; *h) echo "m=${1%h}, half" ;; *) echo "m=$1, full" ;;
  esac
}
sum() { awk '{s = 0; for (i = 1; i <= NF; ++i) s += $i; print s}' <<<"$*"; }
for entry in "${sizes[@]}"; do
  size=${entry%%:*}; frames=${entry##*:}
  declare -A ms=() ratio=() gb=() nm=() oc=() bl=()
  for ((r = 0; r < rounds; ++r)); do
    offms=
    for c in "${configs[@]}"; do
      # shellcheck disable=SC2046
      out=$("$build/demos/polygon" --bench "$frames" --size "$size" $(args_of "$c"))
      m=$(grep '^BENCH' <<<"$out" | field ms_per_frame)
      ms[$c]+=" $m"
      [ "$c" = off ] && offms=$m
      ratio[$c]+=" $(awk -v m="$m" -v o="$offms" 'BEGIN{print m/o}')"
      passes=$(grep '^PASSES' <<<"$out")
      gb[$c]+=" $(field scene_depth <<<"$passes" | head -1)"; nm[$c]+=" $(field ao_normals <<<"$passes")"
      oc[$c]+=" $(field ao_occlusion <<<"$passes") $(field ao_floor <<<"$passes")"
      bl[$c]+=" $(sum "$(field ao_blur_x <<<"$passes") $(field ao_blur_y <<<"$passes") $(field ao_accumulate <<<"$passes")")"
    done
  done
  for c in "${configs[@]}"; do
    m=$(median ${ms[$c]})
    med() { [ -n "${1// /}" ] && median $1 || echo 0; }
    printf '| %s | %s | %.1f (%.1f) | %.2f | %.1f | %.1f | %.1f | %.1f |\n' "$size" "$(label_of "$c")" "$m" \
      "$(awk -v m="$m" 'BEGIN{print 1000/m}')" "$(median ${ratio[$c]})" \
      "$(med "${gb[$c]}")" "$(med "${nm[$c]}")" "$(med "${oc[$c]}")" "$(med "${bl[$c]}")"
    echo "# $size $c: ms${ms[$c]}; ratio${ratio[$c]}" >&2
  done
  unset ms ratio gb nm oc bl
done

#!/usr/bin/env bash
# Cost of the glass's transparency mode on the proving ground at one size: alternates
# `polygon --bench` with --transparency sorted and oit, ROUNDS times (interleaved, so machine
# drift hits both), along the camera path and from a fixed view onto the glass (two panes and the
# closed cabin fill much of the frame), then prints median ms/frame and the OIT/sorted ratio.
# Usage: bench/transparency_table.sh [BUILD_DIR] [ROUNDS] [SIZE] [FRAMES]
set -euo pipefail
source "$(dirname "$0")/common.sh"
build=${1:-build}; rounds=${2:-3}; size=${3:-1280x720}; frames=${4:-40}
glass_view=(--look 22,8,3.5,30,22,2)
stamp "$build"
echo
echo "| view ($size, fog off) | sorted ms (FPS) | OIT ms (FPS) | OIT / sorted |"
echo "|---|---|---|---|"
for view in path glass; do
  declare -A runs=()
  extra=(); [ "$view" = glass ] && extra=("${glass_view[@]}")
  for ((r = 0; r < rounds; ++r)); do
    for m in sorted oit; do
      runs[$m]+=" $("$build/demos/polygon" --bench "$frames" --size "$size" --fog off --transparency "$m" "${extra[@]}" | grep '^BENCH' | field ms_per_frame)"
    done
  done
  for k in sorted oit; do echo "# $view $k: ${runs[$k]}" >&2; done
  s=$(median ${runs[sorted]}); o=$(median ${runs[oit]})
  awk -v v="$view" -v s="$s" -v o="$o" 'BEGIN { printf "| %s | %.1f (%.1f) | %.1f (%.1f) | %.3f |\n", (v == "path" ? "camera path" : "looking at the glass"), s, 1000 / s, o, 1000 / o, o / s }'
  unset runs
done

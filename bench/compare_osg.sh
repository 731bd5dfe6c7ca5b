#!/usr/bin/env bash
# sgfx vs OpenSceneGraph 3.6 on the same proving-ground geometry, measured in one run:
# exports the scene to OBJ, then alternates `polygon --bench` and `osg_polygon` ROUNDS times
# (interleaved, so machine drift hits both) with common.sh's malloc pins, and prints the median
# of each run's median ms/frame and the median of the per-round ratios sgfx / OSG.
# Usage: bench/compare_osg.sh [BUILD_DIR] [SIZE] [FRAMES] [ROUNDS] [extra polygon options...]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh" # malloc pins, field, median, median_ratio, stamp
build=${1:-build}; size=${2:-1280x720}; frames=${3:-60}; rounds=${4:-5}
shift $(( $# < 4 ? $# : 4 ))
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
obj=$tmp/polygon.obj
"$build/demos/polygon" --export-obj "$obj" "$@" >/dev/null
sg=(); og=()
for ((i = 0; i < rounds; ++i)); do
  sg+=("$("$build/demos/polygon" --bench "$frames" --size "$size" --fog off "$@" | grep '^BENCH' | field median_ms)")
  og+=("$("$build/bench/osg_polygon" "$obj" --frames "$frames" --size "$size" 2>/dev/null | grep '^BENCH' | field median_ms)")
done
stamp "$build"
echo "sgfx median ms/frame per round: ${sg[*]}"
echo "osg  median ms/frame per round: ${og[*]}"
awk -v s="$(median "${sg[@]}")" -v o="$(median "${og[@]}")" -v q="$(median_ratio sg og)" -v sz="$size" -v r="$rounds" \
  'BEGIN { printf "COMPARE size=%s rounds=%d sgfx_median_ms=%.2f osg_median_ms=%.2f ratio_sgfx_over_osg=%.3f (median of per-round ratios)\n", sz, r, s, o, q }'

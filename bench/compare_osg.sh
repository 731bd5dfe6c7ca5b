#!/usr/bin/env bash
# sgfx vs OpenSceneGraph 3.6 on the same proving-ground geometry, measured in one run:
# exports the scene to OBJ, then alternates `polygon --bench` and `osg_polygon` ROUNDS times
# (interleaved, so machine drift hits both) and prints the median ms/frame of each and the ratio.
# Usage: bench/compare_osg.sh [BUILD_DIR] [SIZE] [FRAMES] [ROUNDS] [extra polygon options...]
set -euo pipefail
build=${1:-build}; size=${2:-1280x720}; frames=${3:-60}; rounds=${4:-5}
shift $(( $# < 4 ? $# : 4 ))
# llvmpipe timings swing with malloc history: pin glibc's mmap threshold for both programs.
export MALLOC_MMAP_THRESHOLD_=131072
obj=$(mktemp -d)/polygon.obj
"$build/demos/polygon" --export-obj "$obj" "$@" >/dev/null
field() { sed -n "s/.*$1=\([0-9.]*\).*/\1/p"; }
sg=(); og=()
for ((i = 0; i < rounds; ++i)); do
  sg+=("$("$build/demos/polygon" --bench "$frames" --size "$size" --fog off "$@" | grep '^BENCH' | field ms_per_frame)")
  og+=("$("$build/bench/osg_polygon" "$obj" --frames "$frames" --size "$size" | grep '^BENCH' | field ms_per_frame)")
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
ms=$(median "${sg[@]}"); mo=$(median "${og[@]}")
echo "sgfx ms/frame: ${sg[*]}"
echo "osg  ms/frame: ${og[*]}"
awk -v s="$ms" -v o="$mo" -v sz="$size" 'BEGIN { printf "COMPARE size=%s sgfx_median_ms=%.2f osg_median_ms=%.2f ratio_sgfx_over_osg=%.3f\n", sz, s, o, s / o }'
rm -rf "$(dirname "$obj")"

#!/usr/bin/env bash
# Gaussian splats sorted and drawn per second at 10^5 and 10^6 (headless), GPU radix sort against
# the CPU sort: whole frames (sort + draw) and the sort alone, medians of FRAMES frames.
# Usage: bench/splat_table.sh [BUILD_DIR] [SIZE] [FRAMES]   (default build 320x240 5)
set -euo pipefail
source "$(dirname "$0")/common.sh"
build=${1:-build}; size=${2:-320x240}; frames=${3:-5}
stamp "$build"
echo
echo "| splats | sort | ms/frame | splats drawn/s | sort ms | splats sorted/s |"
echo "|---|---|---|---|---|---|"
for n in 100000 1000000; do
  out=$("$build/bench/splat_bench" --count "$n" --frames "$frames" --size "$size")
  while read -r line; do
    awk -v n="$n" -v s="$(sed -n "s/.* sort=\([a-z]*\).*/\1/p" <<<"$line")" -v m="$(field ms_per_frame <<<"$line")" \
        -v sm="$(field sort_ms <<<"$line")" -v d="$(field splats_per_s <<<"$line")" \
        -v q="$(field sorted_per_s <<<"$line")" \
        'BEGIN { printf "| %d | %s | %.1f | %.3g | %.1f | %.3g |\n", n, s, m, d, sm, q }'
  done < <(grep '^SPLATS' <<<"$out")
done

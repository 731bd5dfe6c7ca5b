#!/usr/bin/env bash
# The paged terrain (bench/paged_terrain.cpp) flown at 640x360, the loader instant and then
# sleeping 200 ms per file (a slow disk), malloc pinned as for every table. Each figure is the
# median of RUNS runs (3 by default). Prints Markdown.
# Usage: bench/paged_table.sh [BUILD_DIR] [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/common.sh
build=${1:-build}
runs=${2:-3}
bin="$build/bench/paged_terrain"
"$bin" --frames 2 --size 8x8 --grid 1 | grep -q 'returned=yes' || { echo "paged_terrain failed its smoke run" >&2; exit 1; }
# m LINES NAME: the median of NAME over the PAGED lines.
m() { median $(echo "$1" | field "$2"); }
stamp "$build"
echo
echo "| loader delay | frames streaming / idle | streaming ms median / p95 / max | idle ms median / p95 / max | attach frames, max ms | largest streaming frame / median (/ 31 around it) | files loaded / expired | RSS MB start / peak / end | heap MB start / peak / end | GL buffers, VAOs, textures start / peak / end |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for delay in 0 200; do
  lines=""
  for ((i = 0; i < runs; ++i)); do
    line=$("$bin" --size 640x360 --load-delay "$delay" | grep '^PAGED')
    case $line in *returned=yes*) ;; *) echo "run $i with --load-delay $delay: memory not returned: $line" >&2 ;; esac
    lines+="$line"$'\n'
  done
  printf '| %s ms | %s / %s | %s / %s / %s | %s / %s / %s | %s | %s (%s) | %s / %s | %s / %s / %s | %s / %s / %s | %s, %s, %s / %s, %s, %s / %s, %s, %s |\n' \
    "$delay" "$(m "$lines" stream_frames)" "$(m "$lines" idle_frames)" \
    "$(m "$lines" stream_median_ms)" "$(m "$lines" stream_p95_ms)" "$(m "$lines" stream_max_ms)" \
    "$(m "$lines" idle_median_ms)" "$(m "$lines" idle_p95_ms)" "$(m "$lines" idle_max_ms)" \
    "$(m "$lines" attach_max_ms)" "$(m "$lines" max_stream_ratio)" "$(m "$lines" local_ratio)" \
    "$(m "$lines" loaded)" "$(m "$lines" expired)" \
    "$(m "$lines" rss_start_mb)" "$(m "$lines" rss_peak_mb)" "$(m "$lines" rss_end_mb)" \
    "$(m "$lines" heap_start_mb)" "$(m "$lines" heap_peak_mb)" "$(m "$lines" heap_end_mb)" \
    "$(m "$lines" buffers_start)" "$(m "$lines" vaos_start)" "$(m "$lines" textures_start)" \
    "$(m "$lines" buffers_peak)" "$(m "$lines" vaos_peak)" "$(m "$lines" textures_peak)" \
    "$(m "$lines" buffers_end)" "$(m "$lines" vaos_end)" "$(m "$lines" textures_end)"
done

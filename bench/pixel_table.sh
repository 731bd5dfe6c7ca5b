#!/bin/bash
# Per-pixel cost ladder (docs/performance.md, "Per-pixel cost on foreign content"): for each
# profiling toggle of bench/pixel_cost, the frame at 1280×720 minus the frame at 320×180, every
# toggle and size interleaved frame by frame in one process per file (pixel_cost --ladder), so a
# busy machine slows every toggle of a round alike. Ratios are medians of per-round ratios.
#   bench/pixel_table.sh [BUILD_DIR] [ROUNDS] [FILE.glb] [FILE.obj]
# The files come from `polygon --export-gltf FILE.glb` and `--export-obj FILE.obj`.
# PIXEL_FLAGS=--cpu-time times by CPU time (steadier on a shared machine).
set -euo pipefail
field2() { sed -n "s/.*[ ^]$1=\([^ ]*\).*/\1/p"; }
here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh"
build=${1:-build}
rounds=${2:-20}
glb=${3:-/tmp/city.glb}
obj=${4:-/tmp/city.obj}
echo "pixel_table $(date -u +%F), $rounds rounds, $(nproc) cores"
printf '| file | toggle | 1280×720 ms | 320×180 ms | per-pixel ms | per-pixel / default |\n'
printf '|---|---|---|---|---|---|\n'
for file in "$glb" "$obj"; do
    "$build/bench/pixel_cost" "$file" --ladder "$rounds" ${PIXEL_FLAGS:-} | while read -r line; do
        printf '| %s | %s | %s | %s | %s | %s |\n' "${file##*.}" "$(field2 config <<<"$line")" \
            "$(field2 big_ms <<<"$line")" "$(field2 small_ms <<<"$line")" \
            "$(field2 per_pixel_ms <<<"$line")" "$(field2 ratio <<<"$line")"
    done
done

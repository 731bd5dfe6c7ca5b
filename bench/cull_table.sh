#!/usr/bin/env bash
# Cull traversal, sgfx vs OpenSceneGraph 3.6, on the scene of bench/cull_scene.h: runs sgfx_cull
# and osg_cull interleaved (ROUNDS rounds, so machine drift hits both) at 10^4, 10^5 and 10^6
# leaves with glibc's mmap threshold pinned, and prints a Markdown table of the medians (OSG/sgfx:
# the median of the per-round ratios). Three scenes:
#   translated    translated leaves, one box; OSG as usually built (MatrixTransform > Geode >
#                 Geometry) with its default culling (small-feature culling on: it drops none here);
#   no Geode      the same, OSG's leanest: the Geometry straight under the MatrixTransform and
#                 small-feature culling off (osg_cull --no-geode);
#   mixed state   rotated and non-uniformly scaled leaves over 8 boxes with their own materials
#                 (both sides' --mixed).
# Both sides must queue the same leaves: a mismatch prints the table, then exits 1.
# Usage: bench/cull_table.sh [BUILD_DIR] [ROUNDS] [SIZES...]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh" # MALLOC_MMAP_THRESHOLD_, field, median
build=${1:-build}; rounds=${2:-3}
shift $(( $# < 2 ? $# : 2 ))
sizes=("$@"); [ ${#sizes[@]} -gt 0 ] || sizes=(10000 100000 1000000)
for exe in sgfx_cull osg_cull; do
  [ -x "$build/bench/$exe" ] || { echo "cull_table: $build/bench/$exe not built" >&2; exit 1; }
done

# last LINE NAME: the value of NAME= in LINE.
val() { echo "$1" | field "$2"; }

stamp "$build"
echo
status=0
echo "| scene | leaves | groups | sgfx ms | OSG ms | OSG/sgfx | sgfx nodes/s | OSG nodes/s | queued | sgfx peak RSS MB | OSG peak RSS MB | sgfx B/Group | OSG B/Group | sgfx B/Transform | OSG B/Transform | sgfx heap B/leaf | OSG heap B/leaf |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
scenes=("translated::" "no Geode::--no-geode" "mixed state:--mixed:--mixed")
for sc in "${scenes[@]}"; do
IFS=: read -r label sflag oflag <<<"$sc"
for n in "${sizes[@]}"; do
  sg=(); og=(); sline=; oline=
  for ((r = 0; r < rounds; ++r)); do
    sline=$("$build/bench/sgfx_cull" --n "$n" $sflag | grep '^CULL')
    oline=$("$build/bench/osg_cull" --n "$n" $oflag | grep '^CULL')
    sg+=("$(val "$sline" ms_median)"); og+=("$(val "$oline" ms_median)")
    echo "n=$n round $r: sgfx $(val "$sline" ms_median) ms, osg $(val "$oline" ms_median) ms" >&2
  done
  ms=$(median "${sg[@]}"); mo=$(median "${og[@]}"); ratio=$(median_ratio og sg)
  nodes=$(( $(val "$sline" groups) + $(val "$sline" n) ))
  if [ "$(val "$sline" queued)" != "$(val "$oline" queued)" ] || [ "$(val "$sline" groups)" != "$(val "$oline" groups)" ]; then
    echo "cull_table: $label, n=$n: the two sides culled different scenes (queued $(val "$sline" queued) vs $(val "$oline" queued), groups $(val "$sline" groups) vs $(val "$oline" groups))" >&2
    status=1
  fi
  awk -v sc="$label" -v ratio="$ratio" -v n="$(val "$sline" n)" -v g="$(val "$sline" groups)" -v s="$ms" -v o="$mo" -v nodes="$nodes" \
      -v q="$(val "$sline" queued)" -v f="$(val "$sline" fraction)" \
      -v rs="$(val "$sline" peak_rss_mb)" -v ro="$(val "$oline" peak_rss_mb)" \
      -v gs="$(val "$sline" group_bytes)" -v go="$(val "$oline" group_bytes)" \
      -v ts="$(val "$sline" transform_bytes)" -v to="$(val "$oline" transform_bytes)" \
      -v hs="$(val "$sline" scene_bytes_per_leaf)" -v ho="$(val "$oline" scene_bytes_per_leaf)" \
      'BEGIN { printf "| %s | %d | %d | %.3f | %.3f | %.2f× | %.3g | %.3g | %d (%.1f%%) | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f |\n",
               sc, n, g, s, o, ratio, nodes / (s * 1e-3), nodes / (o * 1e-3), q, 100 * f, rs, ro, gs, go, ts, to, hs, ho }'
done
done
exit $status

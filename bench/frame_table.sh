#!/usr/bin/env bash
# Frame time, sgfx vs OpenSceneGraph 3.6 on the same geometry (issue: core performance): the
# default proving ground ("plain frame") and its many-drawables variant (every window its own
# drawable), both exported to OBJ with full detail for osg_polygon. Runs every program ROUNDS
# times interleaved (so machine drift hits all of them) along the same camera path with glibc's
# mmap threshold pinned, and prints a Markdown table of the medians of the per-run median frame
# times, with the ratios. sgfx runs with fog off, once as shipped (levels of detail, automatic
# instancing, a submission every 20000 triangles), once without levels of detail, once with
# per-vertex lighting like OSG's fixed function, and once submitting once per frame; the
# many-drawables scene also without levels of detail. × OSG is the median of the per-round ratios.
# Usage: bench/frame_table.sh [BUILD_DIR] [ROUNDS] [FRAMES] [SIZE] [polygon flags, e.g. --egl]
# (the flags go to sgfx's polygon only: osg_polygon always renders on OSMesa/llvmpipe).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh" # MALLOC_MMAP_THRESHOLD_, field, median
build=${1:-build}; rounds=${2:-3}; frames=${3:-30}; size=${4:-1280x720}
shift $(($# < 4 ? $# : 4))
extra=("$@")
for exe in demos/polygon bench/osg_polygon; do
  [ -x "$build/$exe" ] || { echo "frame_table: $build/$exe not built" >&2; exit 1; }
done
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$build/demos/polygon" --export-obj "$tmp/plain.obj" >/dev/null
"$build/demos/polygon" --export-obj "$tmp/many.obj" --many-drawables >/dev/null

# run NAME COMMAND...: one run; appends its median ms to the array NAME and keeps its BENCH line.
declare -A line
run() {
  local name=$1; shift
  local out; out=$("$@" 2>/dev/null | grep '^BENCH') # OSG's OBJ plugin warns a lot on stderr
  line[$name]=$out
  eval "$name+=(\"$(echo "$out" | field median_ms)\")"
  echo "  $name: $(echo "$out" | field median_ms) ms" >&2
}
plain_sgfx=(); plain_nolod=(); plain_vertex=(); plain_onesub=(); plain_osg=(); many_sgfx=(); many_noinst=(); many_nolod=(); many_osg=()
poly=("$build/demos/polygon" --bench "$frames" --size "$size" --fog off "${extra[@]}")
osg=("$build/bench/osg_polygon" --frames "$frames" --size "$size" --osg-stats)
for ((r = 0; r < rounds; ++r)); do
  echo "round $((r + 1)) of $rounds" >&2
  run plain_sgfx "${poly[@]}"
  run plain_nolod "${poly[@]}" --no-lod
  run plain_vertex "${poly[@]}" --lighting vertex
  run plain_onesub "${poly[@]}" --submit-triangles 0
  run plain_osg "${osg[@]}" "$tmp/plain.obj"
  run many_sgfx "${poly[@]}" --many-drawables
  run many_noinst "${poly[@]}" --many-drawables --no-instancing
  run many_nolod "${poly[@]}" --many-drawables --no-lod
  run many_osg "${osg[@]}" "$tmp/many.obj"
done
renderer=$("$build/bench/osg_polygon" --frames 1 --size 64x64 "$tmp/plain.obj" | sed -n 's/^GL_RENDERER: //p')
stamp "$build" "${extra[@]}"
echo
echo "Frame time at $size, median of $rounds interleaved runs of $frames frames each (fog off; sgfx flags: ${extra[*]:-none}; OSG's renderer: $renderer, OSMesa)."
echo
echo "| scene | program | ms/frame | × OSG | draw calls | triangles drawn | cull ms |"
echo "|---|---|---:|---:|---:|---:|---:|"
row() { # SCENE LABEL NAME OSGNAME
  local -n a=$3 o=$4
  local m; m=$(median "${a[@]}"); local q; q=$(median_ratio "$3" "$4")
  local l=${line[$3]}
  if [[ $3 == *osg ]]; then
    awk -v s="$1" -v p="$2" -v m="$m" -v d="$(echo "$l" | field drawables)" -v t="$(echo "$l" | field triangles)" \
        -v c="$(echo "$l" | field cull_ms)" 'BEGIN { printf "| %s | %s | %.1f | 1 | %d | %d | %.2f |\n", s, p, m, d, t, c }'
  else
    awk -v s="$1" -v p="$2" -v m="$m" -v q="$q" -v d="$(echo "$l" | field draw_calls)" \
        -v t="$(echo "$l" | field triangles)" -v c="$(echo "$l" | field cull_ms)" \
        'BEGIN { printf "| %s | %s | %.1f | %.2f | %d | %d | %.2f |\n", s, p, m, q, d, t, c }'
  fi
}
row "plain frame" "sgfx (LOD, auto-instancing)" plain_sgfx plain_osg
row "plain frame" "sgfx, no LOD" plain_nolod plain_osg
row "plain frame" "sgfx, per-vertex lighting" plain_vertex plain_osg
row "plain frame" "sgfx, one submission per frame" plain_onesub plain_osg
row "plain frame" "OpenSceneGraph 3.6" plain_osg plain_osg
row "many drawables" "sgfx (auto-instancing)" many_sgfx many_osg
row "many drawables" "sgfx, no auto-instancing" many_noinst many_osg
row "many drawables" "sgfx, no LOD" many_nolod many_osg
row "many drawables" "OpenSceneGraph 3.6" many_osg many_osg

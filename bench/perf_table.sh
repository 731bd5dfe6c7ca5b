#!/usr/bin/env bash
# Every performance table in one command, each starting with common.sh's stamp (date, git
# revision, renderer): the cull traversal (cull_table.sh), the frame time (frame_table.sh), the
# foreign-content orbit (foreign_table.sh, issue 24's yardstick), the scene queries
# (query_table.sh), particles (particles_table.sh) and their step's floor (particle_floor_table.sh),
# ambient occlusion (ao_table.sh), fog
# (fog_table.sh) and the one-line frame comparison (compare_osg.sh at 1280x720). Every figure
# comes from interleaved runs with the same malloc pins on both sides.
#
# Each table goes to OUT_DIR/NAME.md and, with --write, into its docs page between the lines
# `<!-- perf_table:NAME -->` and `<!-- /perf_table:NAME -->` (a page without those markers is left
# alone and named on stderr). A failing table (e.g. cull_table.sh's queued-count check) is
# reported and makes the script exit 1 after the others ran.
# Usage: bench/perf_table.sh [--write] [BUILD_DIR] [ROUNDS] [FRAMES] [TABLES...]
#   TABLES: any of cull frame foreign query particles floor ao fog compare (default all); OUT_DIR:
#   $PERF_OUT, or a fresh temporary folder (named on stderr).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
write=0; [ "${1:-}" = --write ] && { write=1; shift; }
build=${1:-build}; rounds=${2:-3}; frames=${3:-30}
shift $(($# < 3 ? $# : 3))
tables=("$@"); [ ${#tables[@]} -gt 0 ] || tables=(cull frame foreign query particles floor ao fog compare)
out=${PERF_OUT:-$(mktemp -d -t perf-tables.XXXXXX)}; mkdir -p "$out"
echo "perf_table: tables in $out" >&2
declare -A page=([cull]=docs/performance.md [frame]=docs/performance.md [foreign]=docs/performance.md
  [query]=docs/benchmark-queries.md [particles]=docs/effects/particles.md
  [floor]=docs/effects/particles.md [ao]=docs/effects/ao.md
  [fog]=docs/effects/fog.md [compare]=docs/performance.md)
# table NAME: runs the table's script with this command's rounds and frames.
table() {
  case $1 in
    cull) "$here/cull_table.sh" "$build" "$rounds" ;;
    frame) "$here/frame_table.sh" "$build" "$rounds" "$frames" ;;
    foreign) "$here/foreign_table.sh" "$build" "$rounds" "$frames" ;;
    query) "$here/query_table.sh" "$build" "$rounds" ;;
    particles) "$here/particles_table.sh" "$build" "$rounds" ;;
    floor) "$here/particle_floor_table.sh" "$build" "$rounds" ;;
    ao) "$here/ao_table.sh" "$build" "$rounds" ;;
    fog) "$here/fog_table.sh" "$build" "$rounds" ;;
    compare) "$here/compare_osg.sh" "$build" 1280x720 "$frames" "$rounds" ;;
    *) echo "perf_table: unknown table '$1' (cull frame foreign query particles floor ao fog compare)" >&2; return 2 ;;
  esac
}
# splice NAME FILE: puts FILE between NAME's markers in its page.
splice() {
  local doc=$root/${page[$1]} begin="<!-- perf_table:$1 -->" end="<!-- /perf_table:$1 -->"
  if ! grep -qF "$begin" "$doc" || ! grep -qF "$end" "$doc"; then
    echo "perf_table: ${page[$1]} has no $begin ... $end markers: $out/$1.md not written there" >&2
    return 0
  fi
  awk -v b="$begin" -v e="$end" -v f="$2" '
    $0 == b { print; while ((getline l < f) > 0) print l; skip = 1; next }
    $0 == e { skip = 0 }
    !skip' "$doc" >"$doc.new" && mv "$doc.new" "$doc"
  echo "perf_table: wrote $1 into ${page[$1]}" >&2
}
status=0
for t in "${tables[@]}"; do
  echo "## $t" >&2
  if table "$t" >"$out/$t.md"; then
    cat "$out/$t.md"; echo
    [ $write = 1 ] && splice "$t" "$out/$t.md"
  else
    echo "perf_table: $t failed (partial output in $out/$t.md)" >&2
    status=1
  fi
done
exit $status

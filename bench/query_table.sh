#!/usr/bin/env bash
# Scene queries, sgfx vs OpenSceneGraph 3.6 (docs/benchmark-queries.md): exports the proving
# ground once at full detail, then runs query_bench and osg_query on it interleaved ROUNDS times
# (the order alternating, so machine drift hits both) and prints a Markdown table of the medians
# and of the per-round ratios. Fails when the two sides asked different questions or their hit
# counts differ by more than 0.1% of the rays.
# Usage: bench/query_table.sh [BUILD_DIR] [ROUNDS] [TERRAIN_RAYS] [SIGHT_RAYS]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh" # malloc pins, field, median
build=${1:-build}; rounds=${2:-5}; terrain=${3:-100000}; sight=${4:-10000}
for exe in demos/polygon bench/query_bench bench/osg_query; do
  [ -x "$build/$exe" ] || { echo "query_table: $build/$exe not built" >&2; exit 1; }
done
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
# Exports always hold the full detail; --no-lod says so once more.
"$build/demos/polygon" --no-lod --export-obj "$tmp/polygon.obj" >/dev/null

val() { echo "$1" | field "$2"; }
# line OUTPUT KIND WORKLOAD: the KIND line (QUERY, BUILD) of WORKLOAD in OUTPUT.
line() { echo "$1" | grep "^$2 " | grep -- "${3:-}" | head -n 1; }
queries() { echo "$1" | sed -n 's/.* queries=\([0-9a-f]*\).*/\1/p'; }
ratios() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.4f", a / b }'; }

workloads=(terrain sight)
declare -A srate orate ratio
sbuild=(); obuild=(); bratio=()
fail=0
for ((r = 0; r < rounds; ++r)); do
  run_s() { "$build/bench/query_bench" "$tmp/polygon.obj" --terrain "$terrain" --sight "$sight"; }
  run_o() { "$build/bench/osg_query" "$tmp/polygon.obj" --terrain "$terrain" --sight "$sight"; }
  if (( r % 2 == 0 )); then s=$(run_s); o=$(run_o); else o=$(run_o); s=$(run_s); fi
  sb=$(line "$s" BUILD); ob=$(line "$o" BUILD)
  sbuild+=("$(val "$sb" seconds)"); obuild+=("$(val "$ob" seconds)")
  bratio+=("$(ratios "$(val "$ob" seconds)" "$(val "$sb" seconds)")")
  for w in "${workloads[@]}"; do
    sl=$(line "$s" QUERY "workload=$w "); ol=$(line "$o" QUERY "workload=$w ")
    srate[$w]+="$(val "$sl" rays_per_s) "; orate[$w]+="$(val "$ol" rays_per_s) "
    ratio[$w]+="$(ratios "$(val "$sl" rays_per_s)" "$(val "$ol" rays_per_s)") "
    echo "round $r $w: sgfx $(val "$sl" rays_per_s) rays/s, osg $(val "$ol" rays_per_s) rays/s;" \
         "hits $(val "$sl" hits) / $(val "$ol" hits)" >&2
    if [ "$(queries "$sl")" != "$(queries "$ol")" ]; then
      echo "query_table: $w: the two sides asked different questions ($(queries "$sl") vs $(queries "$ol"))" >&2
      fail=1
    fi
    if ! awk -v a="$(val "$sl" hits)" -v b="$(val "$ol" hits)" -v n="$(val "$sl" rays)" \
         'BEGIN { d = a - b; exit !((d < 0 ? -d : d) <= 0.001 * n) }'; then
      echo "query_table: $w: hit counts disagree: sgfx $(val "$sl" hits), osg $(val "$ol" hits)" >&2
      fail=1
    fi
    # The last round's results for the table (the same every round: the queries are fixed).
    eval "last_s_$w=\$sl; last_o_$w=\$ol"
  done
done

echo "| workload | rays | sgfx rays/s | OSG rays/s | sgfx/OSG (median of rounds) | range | sgfx hits | OSG hits | sgfx mean hit z | OSG mean hit z |"
echo "|---|---:|---:|---:|---:|---|---:|---:|---:|---:|"
for w in "${workloads[@]}"; do
  eval "sl=\$last_s_$w; ol=\$last_o_$w"
  read -ra sr <<<"${srate[$w]}"; read -ra orr <<<"${orate[$w]}"; read -ra rr <<<"${ratio[$w]}"
  ms=$(median "${sr[@]}"); mo=$(median "${orr[@]}"); mr=$(median "${rr[@]}")
  lo=$(printf '%s\n' "${rr[@]}" | sort -g | head -n 1); hi=$(printf '%s\n' "${rr[@]}" | sort -g | tail -n 1)
  awk -v w="$w" -v n="$(val "$sl" rays)" -v s="$ms" -v o="$mo" -v r="$mr" -v lo="$lo" -v hi="$hi" \
      -v hs="$(val "$sl" hits)" -v ho="$(val "$ol" hits)" \
      -v zs="$(val "$sl" hit_z_sum)" -v zo="$(val "$ol" hit_z_sum)" \
      'function mz(z, h) { return (w == "terrain" && h > 0) ? sprintf("%.4f", z / h) : "—" }
       BEGIN { printf "| %s | %d | %.0f | %.0f | %.2f× | %.2f–%.2f | %d | %d | %s | %s |\n",
               w, n, s, o, r, lo, hi, hs, ho, mz(zs, hs), mz(zo, ho) }'
done
echo
echo "| BVH | build ms | bytes/triangle | triangles | indexed triangles | trees | tree nodes |"
echo "|---|---:|---:|---:|---:|---:|---:|"
for side in sgfx osg; do
  if [ "$side" = sgfx ]; then b=$sb; t=$(median "${sbuild[@]}"); name="sgfx (prepareForQueries)"
  else b=$ob; t=$(median "${obuild[@]}"); name="OSG (KdTreeBuilder)"; fi
  awk -v name="$name" -v t="$t" -v bpt="$(val "$b" bytes_per_triangle)" -v tri="$(val "$b" triangles)" \
      -v ix="$(val "$b" indexed_triangles)" -v trees="$(val "$b" trees)" \
      -v nodes="$(val "$b" tree_nodes)" \
      'BEGIN { printf "| %s | %.1f | %.1f | %d | %d | %d | %d |\n", name, 1000 * t, bpt, tri, ix,
               trees, nodes }'
done
echo
echo "Build time OSG/sgfx, median of rounds: $(median "${bratio[@]}")×."
exit "$fail"

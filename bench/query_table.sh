#!/usr/bin/env bash
# Scene queries, sgfx vs OpenSceneGraph 3.6 (docs/benchmark-queries.md): exports the proving
# ground once at full detail, then runs query_bench and osg_query on it interleaved ROUNDS times
# (the order rotating, so machine drift hits every program alike) and prints Markdown tables of
# the medians and of the per-round ratios to OSG. Fails when the programs asked different
# questions or their hit counts differ by more than 0.1% of the rays.
# QUERY_VARIANTS=1 adds three rows that separate the scene's structure from the search: sgfx on
# the glTF export (4336 geometries, like OSG's OBJ plugin makes, where sgfx's OBJ loader merges
# them into one per material), the same walked node by node (no subtree index), and OSG with its
# geometries merged by osgUtil::Optimizer.
# Rates and build times are per CPU second of the process (the wall-clock figures are in the
# programs' lines on stderr): this 2-core machine is shared with builds.
# Usage: bench/query_table.sh [BUILD_DIR] [ROUNDS] [TERRAIN_RAYS] [SIGHT_RAYS]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh" # malloc pins, field, median
build=${1:-build}; rounds=${2:-5}; terrain=${3:-100000}; sight=${4:-10000}
for exe in demos/polygon bench/query_bench bench/osg_query; do
  [ -x "$build/$exe" ] || { echo "query_table: $build/$exe not built" >&2; exit 1; }
done
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
obj=$tmp/polygon.obj
# Exports always hold the full detail; --no-lod says so once more.
"$build/demos/polygon" --no-lod --export-obj "$obj" >/dev/null

# Programs: label, then the command. The first two are the comparison; OSG is the reference.
labels=("sgfx" "OSG 3.6")
cmds=("$build/bench/query_bench $obj" "$build/bench/osg_query $obj")
if [ "${QUERY_VARIANTS:-0}" = 1 ]; then
  "$build/demos/polygon" --no-lod --export-gltf "$tmp/polygon.glb" >/dev/null
  labels+=("sgfx, glTF export" "sgfx, glTF export, no subtree index" "OSG 3.6, geometries merged")
  cmds+=("$build/bench/query_bench $obj --model $tmp/polygon.glb"
         "$build/bench/query_bench $obj --model $tmp/polygon.glb --no-subtree-index"
         "$build/bench/osg_query $obj --merge")
fi
n=${#labels[@]}
ref=1                                   # OSG as loaded
ref2=$(( n > 2 ? n - 1 : -1 ))          # OSG merged, with the variants

val() { echo "$1" | field "$2"; }
# line OUTPUT KIND [PATTERN]: the first KIND line (QUERY, BUILD) of OUTPUT matching PATTERN.
line() { echo "$1" | grep "^$2 " | grep -- "${3:-}" | head -n 1; }
queries() { echo "$1" | sed -n 's/.* queries=\([0-9a-f]*\).*/\1/p'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.4f", a / b }'; }

workloads=(terrain sight)
declare -A rate ratios ratios2 bsec bratios out
fail=0
for ((r = 0; r < rounds; ++r)); do
  for ((k = 0; k < n; ++k)); do
    p=$(( (k + r) % n ))
    # shellcheck disable=SC2086 # the command is split into words on purpose (no spaces in paths)
    out[$p]=$(${cmds[$p]} --terrain "$terrain" --sight "$sight")
  done
  o=${out[$ref]}
  for ((p = 0; p < n; ++p)); do
    s=${out[$p]}
    b=$(line "$s" BUILD)
    bsec[$p]+="$(val "$b" cpu_seconds) "
    bratios[$p]+="$(ratio "$(val "$b" cpu_seconds)" "$(val "$(line "$o" BUILD)" cpu_seconds)") "
    for w in "${workloads[@]}"; do
      sl=$(line "$s" QUERY "workload=$w "); ol=$(line "$o" QUERY "workload=$w ")
      rate[$p,$w]+="$(val "$sl" rays_per_cpu_s) "
      ratios[$p,$w]+="$(ratio "$(val "$sl" rays_per_cpu_s)" "$(val "$ol" rays_per_cpu_s)") "
      if (( ref2 >= 0 )); then
        ml=$(line "${out[$ref2]}" QUERY "workload=$w ")
        ratios2[$p,$w]+="$(ratio "$(val "$sl" rays_per_cpu_s)" "$(val "$ml" rays_per_cpu_s)") "
      fi
      echo "round $r $w ${labels[$p]}: $(val "$sl" rays_per_cpu_s) rays/CPU s ($(val "$sl" rays_per_s) rays/s)," \
           "hits $(val "$sl" hits)" >&2
      if [ "$(queries "$sl")" != "$(queries "$ol")" ]; then
        echo "query_table: $w: ${labels[$p]} asked other questions than OSG ($(queries "$sl") vs $(queries "$ol"))" >&2
        fail=1
      fi
      if ! awk -v a="$(val "$sl" hits)" -v b="$(val "$ol" hits)" -v n="$(val "$sl" rays)" \
           'BEGIN { d = a - b; exit !((d < 0 ? -d : d) <= 0.001 * n) }'; then
        echo "query_table: $w: hit counts disagree: ${labels[$p]} $(val "$sl" hits), OSG $(val "$ol" hits)" >&2
        fail=1
      fi
    done
  done
done

# stats LIST: median, minimum and maximum of a space-separated list.
stats() {
  local a; read -ra a <<<"$1"
  echo "$(median "${a[@]}") $(printf '%s\n' "${a[@]}" | sort -g | head -n 1) $(printf '%s\n' "${a[@]}" | sort -g | tail -n 1)"
}

m1="× OSG (median of rounds)"; m2=""; sep="|---|---|---:|---:|---:|---:|---|"
if (( ref2 >= 0 )); then m2=" × OSG merged | range |"; sep+="---:|---|"; fi
stamp "$build"
echo
echo "| workload | program | geometries | rays | rays per CPU s | $m1 | range |$m2 hits | mean hit z |"
echo "$sep---:|---:|"
for w in "${workloads[@]}"; do
  for ((p = 0; p < n; ++p)); do
    sl=$(line "${out[$p]}" QUERY "workload=$w "); b=$(line "${out[$p]}" BUILD)
    read -r rm _ _ <<<"$(stats "${rate[$p,$w]}")"
    read -r qm qlo qhi <<<"$(stats "${ratios[$p,$w]}")"
    q2="-"; q2lo=0; q2hi=0
    if (( ref2 >= 0 )); then read -r q2 q2lo q2hi <<<"$(stats "${ratios2[$p,$w]}")"; fi
    # rf: which reference this row is (1: OSG, 2: OSG merged), so its own ratio column stays empty.
    awk -v w="$w" -v l="${labels[$p]}" -v g="$(val "$b" geometries)" -v n="$(val "$sl" rays)" -v s="$rm" \
        -v q="$qm" -v lo="$qlo" -v hi="$qhi" -v q2="$q2" -v lo2="$q2lo" -v hi2="$q2hi" \
        -v h="$(val "$sl" hits)" -v z="$(val "$sl" hit_z_sum)" \
        -v rf="$(( p == ref ? 1 : (p == ref2 ? 2 : 0) ))" -v two="$(( ref2 >= 0 ))" \
        'function r(x, a, b, self) { return self ? "1 | " : sprintf("%.2f× | %.2f–%.2f", x, a, b) }
         BEGIN { printf "| %s | %s | %d | %d | %.0f | %s |%s %d | %s |\n", w, l, g, n, s,
                 r(q, lo, hi, rf == 1), two ? " " r(q2, lo2, hi2, rf == 2) " |" : "", h,
                 (w == "terrain" && h > 0) ? sprintf("%.4f", z / h) : "—" }'
  done
done
echo
echo "| program | BVH build CPU ms | × OSG (median of rounds) | bytes/triangle | triangles | indexed triangles | trees | tree nodes |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
for ((p = 0; p < n; ++p)); do
  b=$(line "${out[$p]}" BUILD)
  read -r bm _ _ <<<"$(stats "${bsec[$p]}")"
  read -r qm _ _ <<<"$(stats "${bratios[$p]}")"
  awk -v l="${labels[$p]}" -v t="$bm" -v q="$qm" -v ref="$(( p == ref ))" \
      -v bpt="$(val "$b" bytes_per_triangle)" -v tri="$(val "$b" triangles)" \
      -v ix="$(val "$b" indexed_triangles)" -v trees="$(val "$b" trees)" -v nodes="$(val "$b" tree_nodes)" \
      'BEGIN { printf "| %s | %.1f | %s | %.1f | %d | %d | %d | %d |\n", l, 1000 * t,
               ref ? "1" : sprintf("%.2f×", q), bpt, tri, ix, trees, nodes }'
done
exit "$fail"

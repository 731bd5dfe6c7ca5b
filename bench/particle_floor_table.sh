#!/usr/bin/env bash
# The particle step's floor on this driver (issue 24, Must 5): `particle_floor` (every GL path's
# copy of the 52-byte records and its real update, no sgfx) interleaved with osgParticle's
# simulation alone (`osg_particles N --no-draw`), ROUNDS times, as a Markdown table. The last
# column is osgParticle's ms over the path's, the median of per-round ratios; the goal is 3.
# Usage: bench/particle_floor_table.sh [BUILD_DIR] [ROUNDS] [COUNT]   (default build 3 1000000)
set -euo pipefail
source "$(dirname "$0")/common.sh"
export MALLOC_MMAP_THRESHOLD_=1073741824 MALLOC_TRIM_THRESHOLD_=1073741824 # as particles_table.sh
build=${1:-build}; rounds=${2:-3}; n=${3:-1000000}
stamp "$build"
echo
declare -A ms=()
osg=()
for ((r = 0; r < rounds; ++r)); do
  echo "particle floor: round $((r + 1))/$rounds" >&2
  out=$("$build/bench/particle_floor" --count "$n" --rounds 1 --steps 4)
  while read -r path op v; do ms[$path:$op]+=" $v"; done < <(
    sed -n 's/^FLOOR path=\([a-z0-9-]*\) op=\([a-z]*\) ms=\([0-9.]*\).*/\1 \2 \3/p' <<<"$out")
  osg+=("$("$build/bench/osg_particles" "$n" --no-draw | grep '^OSG_PARTICLES' | field frame_ms)")
done
echo "$n particles; osgParticle's simulation: $(median "${osg[@]}") ms a step (median)."
echo
echo "| path | copy ms (floor) | update ms | osgParticle / copy | osgParticle / update |"
echo "|---|---:|---:|---:|---:|"
for path in fragment-mrt compute-vec4 compute-tbo compute-ssbo feedback; do
  read -ra c <<<"${ms[$path:copy]}"; read -ra u <<<"${ms[$path:update]}"
  printf '| %s | %.1f | %.1f | %.2f | %.2f |\n' "$path" "$(median "${c[@]}")" "$(median "${u[@]}")" \
    "$(median_ratio osg c)" "$(median_ratio osg u)"
done

#!/usr/bin/env bash
# Particle cost, sgfx vs OpenSceneGraph's osgParticle (CPU) on the same scene in one run: for
# 10^4, 10^5 and 10^6 sprites at SIZE, alternates `particles --bench` over every draw path and
# buffer layout with `osg_particles` (drawn, and simulation alone), ROUNDS times (interleaved),
# and prints the medians as a Markdown table with the ratio osgParticle / sgfx.
# Usage: bench/particles_table.sh [BUILD_DIR] [ROUNDS] [SIZE]   (default build 2 1280x720)
set -euo pipefail
source "$(dirname "$0")/common.sh"
# Pinned higher than common.sh's 128 kB, for both programs alike: at 10^5..10^6 primitives
# llvmpipe's per-frame scene memory would otherwise be mmapped afresh every frame, and the page
# faults (a third of the time under perf) would swamp what is being compared.
export MALLOC_MMAP_THRESHOLD_=1073741824 MALLOC_TRIM_THRESHOLD_=1073741824
build=${1:-build}; rounds=${2:-2}; size=${3:-1280x720}
configs=(points:interleaved pulled:interleaved pulled:split instanced:interleaved instanced:split gs:interleaved)
"$build/demos/particles" --bench 1 --count 1000 --size 64x64 | grep GL_RENDERER >&2
echo "| particles | sgfx path, layout | sgfx ms/frame | sgfx simulation ms | osgParticle ms/frame | osgParticle simulation ms | osgParticle / sgfx (frame) |"
echo "|---|---|---|---|---|---|---|"
for n in 10000 100000 1000000; do
  frames=$(( n >= 1000000 ? 5 : (n >= 100000 ? 10 : 30) ))
  declare -A fr=() up=()
  osg=(); osgsim=()
  for ((r = 0; r < rounds; ++r)); do
    for c in "${configs[@]}"; do
      echo "n=$n round $((r + 1))/$rounds $c" >&2
      out=$("$build/demos/particles" --bench "$frames" --count "$n" --size "$size" --path "${c%%:*}" --layout "${c##*:}" | grep '^PARTICLES')
      fr[$c]+=" $(field frame_ms <<<"$out")"; up[$c]+=" $(field sim_ms <<<"$out")"
    done
    osg+=("$("$build/bench/osg_particles" "$n" --frames "$frames" --size "$size" | grep '^OSG_PARTICLES' | field frame_ms)")
    osgsim+=("$("$build/bench/osg_particles" "$n" --frames "$frames" --size "$size" --no-draw | grep '^OSG_PARTICLES' | field frame_ms)")
  done
  o=$(median "${osg[@]}"); os=$(median "${osgsim[@]}")
  for c in "${configs[@]}"; do
    f=$(median ${fr[$c]}); u=$(median ${up[$c]})
    awk -v n="$n" -v c="$c" -v f="$f" -v u="$u" -v o="$o" -v os="$os" 'BEGIN {
      sub(":", ", ", c); printf "| %d | %s | %.1f | %.2f | %.1f | %.1f | %.2f |\n", n, c, f, u, o, os, o / f }'
  done
  unset fr up
done

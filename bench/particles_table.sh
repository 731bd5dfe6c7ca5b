#!/usr/bin/env bash
# Particle cost, sgfx vs OpenSceneGraph's osgParticle (CPU) on the same scene in one run: for
# 10^4, 10^5 and 10^6 sprites at SIZE, alternates `particles --bench` over every draw path and
# buffer layout with `osg_particles` (points, quads, and simulation alone), ROUNDS times
# (interleaved), and prints the medians as a Markdown table. Like for like: sgfx's points path is
# paired with osgParticle's POINT shape (GL_POINTS), every other sgfx path (quads built by a
# geometry shader, instanced or pulled from the buffer) with osgParticle's QUAD shape; the ratio
# osgParticle / sgfx is the median of the per-round ratios against that peer.
# Usage: bench/particles_table.sh [BUILD_DIR] [ROUNDS] [SIZE]   (default build 2 1280x720)
# PARTICLE_COUNTS="1000" overrides the counts (a quick check of the script); PARTICLE_UPDATES="tf
# compute" runs every path with each simulation update (`particles --update`; default: auto, the
# demo's own pick), the update column naming what ran.
set -euo pipefail
source "$(dirname "$0")/common.sh"
# Pinned higher than common.sh's 128 kB, for both programs alike: at 10^5..10^6 primitives
# llvmpipe's per-frame scene memory would otherwise be mmapped afresh every frame, and the page
# faults (a third of the time under perf) would swamp what is being compared.
export MALLOC_MMAP_THRESHOLD_=1073741824 MALLOC_TRIM_THRESHOLD_=1073741824
build=${1:-build}; rounds=${2:-2}; size=${3:-1280x720}
paths=(points:interleaved pulled:interleaved pulled:split instanced:interleaved instanced:split gs:interleaved)
read -ra updates <<<"${PARTICLE_UPDATES:-auto}"
configs=(); for c in "${paths[@]}"; do for u in "${updates[@]}"; do configs+=("$c:$u"); done; done
stamp "$build"
echo
echo "| particles | sgfx path, layout | update | sgfx ms/frame | sgfx simulation ms | osgParticle peer | osgParticle ms/frame | osgParticle simulation ms | osgParticle / sgfx (frame) |"
echo "|---|---|---|---|---|---|---|---|---|"
osgrun() { "$build/bench/osg_particles" "$@" --frames "$frames" --size "$size" | grep '^OSG_PARTICLES' | field frame_ms; }
for n in ${PARTICLE_COUNTS:-10000 100000 1000000}; do
  frames=$(( n >= 1000000 ? 5 : (n >= 100000 ? 10 : 30) ))
  declare -A fr=() up=() ran=()
  osg_point=(); osg_quad=(); osgsim=()
  for ((r = 0; r < rounds; ++r)); do
    for c in "${configs[@]}"; do
      echo "n=$n round $((r + 1))/$rounds $c" >&2
      IFS=: read -r path layout update <<<"$c"
      flags=(--path "$path" --layout "$layout"); [ "$update" = auto ] || flags+=(--update "$update")
      out=$("$build/demos/particles" --bench "$frames" --count "$n" --size "$size" "${flags[@]}" | grep '^PARTICLES')
      fr[$c]+=" $(field frame_ms <<<"$out")"; up[$c]+=" $(field sim_ms <<<"$out")"
      ran[$c]=$(sed -n 's/.* update=\([a-z]*\).*/\1/p' <<<"$out")
    done
    osg_point+=("$(osgrun "$n" --shape point)")
    osg_quad+=("$(osgrun "$n" --shape quad)")
    osgsim+=("$(osgrun "$n" --no-draw)")
  done
  os=$(median "${osgsim[@]}")
  for c in "${configs[@]}"; do
    read -ra sg <<<"${fr[$c]}"
    peer=quad; [ "${c%%:*}" = points ] && peer=point
    if [ $peer = point ]; then o=$(median "${osg_point[@]}"); q=$(median_ratio osg_point sg)
    else o=$(median "${osg_quad[@]}"); q=$(median_ratio osg_quad sg); fi
    f=$(median ${fr[$c]}); u=$(median ${up[$c]})
    IFS=: read -r path layout update <<<"$c"
    awk -v n="$n" -v c="$path:$layout" -v upd="${ran[$c]:-$update}" -v f="$f" -v u="$u" -v p="$peer" -v o="$o" -v os="$os" -v q="$q" 'BEGIN {
      sub(":", ", ", c); printf "| %d | %s | %s | %.1f | %.2f | %s | %.1f | %.1f | %.2f |\n", n, c, upd, f, u, p, o, os, q }'
  done
  unset fr up ran
done

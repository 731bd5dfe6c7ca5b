#!/usr/bin/env bash
# Fog cost on the proving ground, shaped like the seed paper's Table 1 (resolution x fog off / on):
# for each size, alternates `polygon --bench` with --fog off, forward, deferred, split and post, and
# osg_polygon without and with osg::Fog, ROUNDS times (interleaved, so machine drift hits every
# column), then prints median ms/frame, FPS and the overhead of each mode over fog off (the median
# of per-round ratios), and on stderr whether `deferred` really ran its "fog opaque" pass.
# Usage: bench/fog_table.sh [BUILD_DIR] [ROUNDS] [SIZE:FRAMES ...]
#   default sizes: 1280x720:40 1920x1080:24 3840x2160:8
set -euo pipefail
source "$(dirname "$0")/common.sh"
build=${1:-build}; rounds=${2:-3}; shift $(( $# < 2 ? $# : 2 ))
sizes=("$@"); [ ${#sizes[@]} -gt 0 ] || sizes=(1280x720:40 1920x1080:24 3840x2160:8)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$build/demos/polygon" --export-obj "$tmp/polygon.obj" >/dev/null
have_osg=0; [ -x "$build/bench/osg_polygon" ] && have_osg=1
modes=(off forward deferred split post)
echo "| resolution | fog off ms (FPS) | Forward | Forward, deferred opaque | ForwardSplit | PostProcess | OSG off ms | OSG + osg::Fog |"
echo "|---|---|---|---|---|---|---|---|"
for entry in "${sizes[@]}"; do
  size=${entry%%:*}; frames=${entry##*:}
  declare -A runs=()
  for ((r = 0; r < rounds; ++r)); do
    for m in "${modes[@]}"; do
      out=$("$build/demos/polygon" --bench "$frames" --size "$size" --fog "$m")
      runs[$m]+=" $(grep '^BENCH' <<<"$out" | field ms_per_frame)"
      # Deferred fogs the opaque items in one pass after them when that is exact (FogNode docs).
      [ "$m" = deferred ] && echo "# $size deferred ran=$(grep -q ' fog_opaque=' <<<"$(grep '^PASSES' <<<"$out")" && echo 1 || echo 0)" >&2
    done
    if ((have_osg)); then
      runs[osg]+=" $("$build/bench/osg_polygon" "$tmp/polygon.obj" --frames "$frames" --size "$size" | grep '^BENCH' | field ms_per_frame)"
      runs[osgfog]+=" $("$build/bench/osg_polygon" "$tmp/polygon.obj" --frames "$frames" --size "$size" --fog 0.001 | grep '^BENCH' | field ms_per_frame)"
    fi
  done
  declare -A med=()
  for k in "${!runs[@]}"; do med[$k]=$(median ${runs[$k]}); echo "# $size $k: ${runs[$k]}" >&2; done
  # The overhead is the median of the per-round ratios (mode / off of the same round): drift on a
  # shared machine cancels within a round.
  ratio() { median $(paste -d' ' <(tr ' ' '\n' <<<"${runs[$1]# }") <(tr ' ' '\n' <<<"${runs[off]# }") | awk '{ print $1 / $2 }'); }
  cell() { awk -v m="$1" -v r="$2" 'BEGIN { printf "%.1f ms (%.1f), %+.1f %%", m, 1000 / m, 100 * (r - 1) }'; }
  row="| $size | $(awk -v m="${med[off]}" 'BEGIN { printf "%.1f (%.1f)", m, 1000 / m }')"
  for m in forward deferred split post; do row+=" | $(cell "${med[$m]}" "$(ratio "$m")")"; done
  if ((have_osg)); then
    row+=" | $(awk -v m="${med[osg]}" 'BEGIN { printf "%.1f", m }') | $(cell "${med[osgfog]}" "${med[osg]}")"
  else
    row+=" | n/a | n/a"
  fi
  echo "$row |"
  unset runs med
done

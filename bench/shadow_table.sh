#!/usr/bin/env bash
# Sun shadow cost on the proving ground (docs/plans/shadows.md §9), shaped like fog_table.sh: for
# each size, alternates `polygon --bench` with --shadows off and on (1, 2 and 4 cascades, each with
# the hard and the PCF filter) and osg_polygon without and with osgShadow's ViewDependentShadowMap
# (1 and 2 maps: OSG 3.6 renders at most 2), ROUNDS times (interleaved, so machine drift hits every
# row), fog off, the same map size and shadow distance on both sides. Prints the median ms/frame
# (FPS), Δ over the shadows-off frame (the median of the per-round differences, and of the
# per-round ratios as a percentage), the GPU ms of the shadow passes and of `main: opaque` (sgfx's
# PASSES line), then Δsgfx(hard, N)/ΔOSG(N) for N = 1, 2, each the median of its per-round ratios
# (the plan's goal: at most 0.8), with PCF beside it. What casts differs: in polygon the terrain only
# receives while the sun is above 30° (the demo's lever); in OSG everything casts.
# Usage: bench/shadow_table.sh [BUILD_DIR] [ROUNDS] [SIZE:FRAMES ...]   (default build 3 1280x720:24)
#   SHADOW_MAP (default 2048) and SHADOW_DISTANCE (default 200 m) set both programs' maps.
set -euo pipefail
source "$(dirname "$0")/common.sh"
build=${1:-build}; rounds=${2:-3}; shift $(( $# < 2 ? $# : 2 ))
sizes=("$@"); [ ${#sizes[@]} -gt 0 ] || sizes=(1280x720:24)
map=${SHADOW_MAP:-2048}; distance=${SHADOW_DISTANCE:-200}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$build/demos/polygon" --export-obj "$tmp/polygon.obj" >/dev/null
have_osg=0; [ -x "$build/bench/osg_polygon" ] && have_osg=1
configs=(off 1:hard 1:pcf 2:hard 2:pcf 2:pcss 4:hard 4:pcf)
osg_configs=(); ((have_osg)) && osg_configs=(osg0 osg1 osg2)
# ratio A B: A / B, or "inf" when B is not positive (a difference lost in the noise): it sorts
# last, so such a round raises a median rather than lowering it.
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (b > 0) printf "%.4f", a / b; else print "inf" }'; }
# minus A B: A - B.
minus() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", a - b }'; }
# sum of the shadow passes' GPU ms on a PASSES line.
shadow_ms() { tr ' ' '\n' | awk -F= '/^shadow__cascade_/ { s += $2 } END { printf "%.3f", s }'; }
echo "Shadow maps ${map}x${map}, ${distance} m; fog off; $rounds interleaved round(s)."
echo
stamp "$build"
echo
echo "| size | renderer | shadows | ms/frame (FPS) | Δ over off | shadow passes GPU ms | main: opaque GPU ms |"
echo "|---|---|---|---|---|---|---|"
ratio_rows=()
for entry in "${sizes[@]}"; do
  size=${entry%%:*}; frames=${entry##*:}
  declare -A ms=() deltas=() ratios=() smap=() opaque=() per=()
  for ((r = 0; r < rounds; ++r)); do
    declare -A now=()
    for c in "${configs[@]}"; do
      args=(--fog off --shadows off)
      [ "$c" != off ] && args=(--fog off --shadows on --shadow-cascades "${c%%:*}" --shadow-filter "${c##*:}"
                               --shadow-map "$map" --shadow-distance "$distance")
      echo "# round $((r + 1))/$rounds $size sgfx $c" >&2
      out=$("$build/demos/polygon" --bench "$frames" --size "$size" "${args[@]}")
      now[$c]=$(grep '^BENCH' <<<"$out" | field ms_per_frame)
      passes=$(grep '^PASSES' <<<"$out")
      smap[$c]+=" $(shadow_ms <<<"$passes")"; opaque[$c]+=" $(field main__opaque <<<"$passes")"
    done
    for c in "${osg_configs[@]}"; do
      echo "# round $((r + 1))/$rounds $size OSG ${c#osg}" >&2
      now[$c]=$("$build/bench/osg_polygon" "$tmp/polygon.obj" --frames "$frames" --size "$size" --shadows "${c#osg}" \
                  --shadow-map "$map" --shadow-distance "$distance" | grep '^BENCH' | field ms_per_frame)
    done
    for c in "${configs[@]}" "${osg_configs[@]}"; do
      base=${now[off]}; [[ $c == osg* ]] && base=${now[osg0]}
      ms[$c]+=" ${now[$c]}"; deltas[$c]+=" $(minus "${now[$c]}" "$base")"; ratios[$c]+=" $(ratio "${now[$c]}" "$base")"
    done
    if ((have_osg)); then
      for n in 1 2; do
        for f in hard pcf; do
          per[$n:$f]+=" $(ratio "$(minus "${now[$n:$f]}" "${now[off]}")" "$(minus "${now[osg$n]}" "${now[osg0]}")")"
        done
      done
    fi
    unset now
  done
  for c in "${configs[@]}" "${osg_configs[@]}"; do
    echo "# $size $c ms:${ms[$c]} delta:${deltas[$c]}" >&2
    m=$(median ${ms[$c]})
    if [[ $c == osg* ]]; then renderer=OSG; label=${c#osg}; [ "$label" = 0 ] && label=off || label="$label map(s), VDSM"
    else renderer=sgfx; label=$c; [ "$c" != off ] && label="${c%%:*} cascade(s), ${c##*:}"; fi
    if [ "$c" = off ] || [ "$c" = osg0 ]; then delta="-"
    else delta=$(awk -v d="$(median ${deltas[$c]})" -v q="$(median ${ratios[$c]})" 'BEGIN { printf "%+.1f ms (%+.0f %%)", d, 100 * (q - 1) }'); fi
    passes="-"; main="-"
    if [[ $c != osg* ]]; then
      main=$(median ${opaque[$c]} | xargs printf '%.1f'); [ "$c" != off ] && passes=$(median ${smap[$c]} | xargs printf '%.1f')
    fi
    printf '| %s | %s | %s | %.1f (%.1f) | %s | %s | %s |\n' "$size" "$renderer" "$label" "$m" \
      "$(awk -v m="$m" 'BEGIN { print 1000 / m }')" "$delta" "$passes" "$main"
  done
  if ((have_osg)); then
    for n in 1 2; do
      ratio_rows+=("| $size | $n | $(median ${per[$n:hard]} | xargs printf '%.2f') | $(median ${per[$n:pcf]} | xargs printf '%.2f') |")
      echo "# $size ratio N=$n hard:${per[$n:hard]} pcf:${per[$n:pcf]}" >&2
    done
  fi
  unset ms deltas ratios smap opaque per
done
echo
if ((have_osg)); then
  echo "| size | N | Δsgfx(hard, N) / ΔOSG(N) | Δsgfx(pcf, N) / ΔOSG(N) |"
  echo "|---|---|---|---|"
  printf '%s\n' "${ratio_rows[@]}"
else
  echo "(no $build/bench/osg_polygon: no OSG rows or ratios)"
fi

#!/usr/bin/env bash
# Two builds of the proving ground compared row by row in one interleaved run: the frame graph's
# effect of sharing one scene depth (issue 22). Each round runs every row with both builds, in
# alternating order; a row's figure is the median over rounds of the per-round ratio new/old.
#   bench/frame_graph_compare.sh OLD_BUILD NEW_BUILD [FRAMES] [ROUNDS] [SIZE]
# Then each row's still image (polygon's default time) from both builds, and how many pixels differ.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
old=$1/demos/polygon
new=$2/demos/polygon
frames=${3:-10}
rounds=${4:-3}
size=${5:-1280x720}
source "$here/common.sh"
for b in "$old" "$new"; do [ -x "$b" ] || { echo "frame_graph_compare: $b not built" >&2; exit 1; }; done
rows=("none:--fog off" "fog split:--fog split" "ao:--fog off --ao on" "rain:--fog off --rain"
      "smoke:--fog off --smoke" "oit:--fog off --transparency oit"
      "all:--fog split --ao on --rain --smoke --transparency oit --aa fxaa")
ms() { "$1" --bench "$frames" --size "$size" $2 2>/dev/null | grep '^BENCH' | field median_ms; }
declare -A ratios olds news
for ((r = 0; r < rounds; ++r)); do
    for row in "${rows[@]}"; do
        name=${row%%:*} args=${row#*:}
        if ((r % 2 == 0)); then a=$(ms "$old" "$args"); b=$(ms "$new" "$args")
        else b=$(ms "$new" "$args"); a=$(ms "$old" "$args"); fi
        olds[$name]+="$a " news[$name]+="$b "
        ratios[$name]+="$(awk -v a="$a" -v b="$b" 'BEGIN {printf "%.4f", b / a}') "
        echo "round $((r + 1)) $name: old $a ms, new $b ms" >&2
    done
done
echo "| row | old median ms | new median ms | new/old (median of rounds) | range |"
echo "|---|---:|---:|---:|---|"
for row in "${rows[@]}"; do
    name=${row%%:*}
    # shellcheck disable=SC2086
    printf '| %s | %s | %s | %s | %s–%s |\n' "$name" "$(median ${olds[$name]})" "$(median ${news[$name]})" \
        "$(median ${ratios[$name]})" "$(printf '%s\n' ${ratios[$name]} | sort -g | head -1)" \
        "$(printf '%s\n' ${ratios[$name]} | sort -g | tail -1)"
done

echo
echo "| row | pixels that differ (old vs new still image, $size) | by more than 8/255 |"
echo "|---|---:|---:|"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for row in "${rows[@]}"; do
    name=${row%%:*} args=${row#*:}
    # shellcheck disable=SC2086
    "$old" $args --size "$size" --out "$tmp/old.png" > /dev/null
    # shellcheck disable=SC2086
    "$new" $args --size "$size" --out "$tmp/new.png" > /dev/null
    /usr/bin/python3 - "$name" "$tmp/old.png" "$tmp/new.png" <<'PY'
import sys
from PIL import Image, ImageChops
a, b = (Image.open(f).convert("RGB") for f in sys.argv[2:4])
d = [max(p) for p in ImageChops.difference(a, b).getdata()]
print(f"| {sys.argv[1]} | {sum(1 for v in d if v)} of {len(d)} | {sum(1 for v in d if v > 8)} |")
PY
done

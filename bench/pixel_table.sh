#!/bin/bash
# Per-pixel cost ladder (docs/performance.md, "Per-pixel cost on foreign content"): for each
# profiling toggle of bench/pixel_cost, the frame at 1280×720 minus the frame at 320×180, in
# interleaved rounds; prints per config the medians over rounds of both frames and of their
# difference, and the median of per-round ratios of that difference to the first config's.
#   bench/pixel_table.sh [BUILD_DIR] [ROUNDS] [FILE.glb] [FILE.obj]
# The files come from `polygon --export-gltf FILE.glb` and `--export-obj FILE.obj`.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh"
build=${1:-build}
rounds=${2:-3}
glb=${3:-/tmp/city.glb}
obj=${4:-/tmp/city.obj}
frames=${FRAMES:-15}
bin="$build/bench/pixel_cost"
configs=(
    "gltf|$glb|"
    "gltf unorm8|$glb|--target unorm8"
    "gltf submit 0|$glb|--submit-triangles 0"
    "gltf per-vertex|$glb|--lighting vertex"
    "gltf constant|$glb|--shading constant"
    "gltf constant unorm8 submit 0|$glb|--shading constant --target unorm8 --submit-triangles 0"
    "obj|$obj|"
    "obj unorm8|$obj|--target unorm8"
    "obj constant|$obj|--shading constant"
)
declare -A big small
for ((r = 0; r < rounds; ++r)); do
    for i in "${!configs[@]}"; do
        IFS='|' read -r name file args <<<"${configs[$i]}"
        # shellcheck disable=SC2086
        big[$i,$r]=$("$bin" "$file" --frames "$frames" --size 1280x720 $args | field median_ms)
        # shellcheck disable=SC2086
        small[$i,$r]=$("$bin" "$file" --frames "$frames" --size 320x180 $args | field median_ms)
    done
done
printf '| config | 1280×720 ms | 320×180 ms | per-pixel ms | per-pixel / first |\n|---|---|---|---|---|\n'
for i in "${!configs[@]}"; do
    IFS='|' read -r name file args <<<"${configs[$i]}"
    b=() s=() d=() q=()
    for ((r = 0; r < rounds; ++r)); do
        b+=("${big[$i,$r]}") s+=("${small[$i,$r]}")
        d+=("$(echo "${big[$i,$r]} - ${small[$i,$r]}" | bc -l)")
        q+=("$(echo "(${big[$i,$r]} - ${small[$i,$r]}) / (${big[0,$r]} - ${small[0,$r]})" | bc -l)")
    done
    printf '| %s | %.1f | %.1f | %.1f | %.2f |\n' "$name" "$(median "${b[@]}")" "$(median "${s[@]}")" \
        "$(median "${d[@]}")" "$(median "${q[@]}")"
done

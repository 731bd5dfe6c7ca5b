#!/usr/bin/env bash
# Core performance against OpenSceneGraph 3.6 in one command (docs/performance.md): the cull
# traversal table (bench/cull_table.sh: 10^4..10^6 leaves, memory per node, peak RSS), the
# frame-time table (bench/frame_table.sh: the plain proving ground and its many-drawables
# variant) and the scene-query table (bench/query_table.sh, docs/benchmark-queries.md), every
# figure a ratio of interleaved runs with the same malloc settings on both sides.
# Usage: bench/perf_table.sh [BUILD_DIR] [ROUNDS] [FRAMES]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}; rounds=${2:-3}; frames=${3:-30}
echo "## Cull traversal"
echo
"$here/cull_table.sh" "$build" "$rounds"
echo
echo "## Frame time"
echo
"$here/frame_table.sh" "$build" "$rounds" "$frames"
echo
echo "## Scene queries"
echo
"$here/query_table.sh" "$build" "$rounds"

#!/bin/sh
# sgfx-cluster's figures on this machine (docs/cluster.md): frame time against the number of ranks
# (1, 2, 4; one channel of the 2x2 wall each), packet bytes and frame-lock wait per frame, the
# gather of the channels to rank 0, and the single-process reference of the whole wall.
# usage: bench/cluster_table.sh [BUILD_DIR (build)] [SCALE (0.25)] [FRAMES (120)]
set -e
build=${1:-build}
scale=${2:-0.25}
frames=${3:-120}
root=$(cd "$(dirname "$0")/.." && pwd)
config=$root/demos/cluster/configs/wall-2x2.json
cluster=$build/demos/sgfx-cluster
common="--config $config --scale $scale --frames $frames --stats"
echo "| ranks | llvmpipe threads/rank | channel | frame ms | frame-lock wait ms (rank 0) | least wait ms (any rank) | packet bytes/frame | gather ms (once) |"
echo "|---|---|---|---|---|---|---|---|"
for threads in default 1; do
  for ranks in 1 2 4; do
    env=""
    [ "$threads" = default ] || env="-x LP_NUM_THREADS=$threads"
    line=$(mpirun --allow-run-as-root --oversubscribe $env -np $ranks "$cluster" $common --channels $ranks |
      grep '^cluster:')
    get() { echo "$line" | sed -n "s/.* $1=\([^ ]*\).*/\1/p"; }
    echo "| $ranks | $threads | $(get channel) | $(get frame_ms) | $(get barrier_ms) | $(get barrier_least_ms) |" \
      "$(get packet_bytes) |" \
      "$(get gather_ms) |"
  done
done
echo
echo "Messaging alone (--sync-only: packet and frame lock, nothing drawn), 1000 frames:"
echo
echo "| ranks | frame ms | frame-lock wait ms (rank 0) | least wait ms (any rank) |"
echo "|---|---|---|---|"
for ranks in 2 4; do
  line=$(mpirun --allow-run-as-root --oversubscribe -np $ranks "$cluster" --config "$config" --frames 1000 --stats \
    --sync-only --channels $ranks | grep '^cluster:')
  echo "| $ranks | $(get frame_ms) | $(get barrier_ms) | $(get barrier_least_ms) |"
done
line=$("$cluster" $common --reference | grep '^reference:')
echo
echo "Reference (one process, the whole wall in one view): $(echo "$line" | sed 's/^reference: //')"
echo "Load average while measured: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "Machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), llvmpipe (OSMesa)"

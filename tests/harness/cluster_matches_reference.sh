#!/bin/sh
# The 2x2 wall under mpirun (4 ranks, oversubscribed) against the single-process reference of the
# wall's overall frustum; composite_compare.py fails the test past 1/255 on any pixel.
# usage: cluster_matches_reference.sh MPIRUN SGFX_CLUSTER CONFIG WORKDIR [sgfx-cluster options]
set -e
mpirun=$1 cluster=$2 config=$3 work=$4
shift 4
here=$(dirname "$0")
mkdir -p "$work"
"$mpirun" --allow-run-as-root --oversubscribe -np 4 "$cluster" --config "$config" --out "$work/wall.png" --stats "$@"
"$cluster" --config "$config" --reference --out "$work/reference.png" "$@"
# Triangle-edge pixels (a surface edge on the other side of a pixel centre under the channel's own
# projection) may differ more, up to 0.1 % of the pixels: docs/cluster.md has the measured counts
# (at most 3 of 57600 over 14 camera positions and two sizes).
python3 "$here/composite_compare.py" "$work/wall.png" "$work/reference.png" --tolerance 1 --allow-fraction 0.001

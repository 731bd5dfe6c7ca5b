#!/usr/bin/env bash
# Load time and resident memory of OSG sample files: OpenSceneGraph's own load (osgDB::readNodeFile)
# against sgfx::loadOsg with isolateReader on and off (bench/osg_load.cpp), as the markdown table of
# docs/coming-from-osg.md. Usage: bench/osg_load_table.sh [BUILD_DIR] [ROUNDS] [FILES...]
# (default build, 21 rounds, cessna.osgt and lz.osgt from ../shared/assets/osg).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/common.sh" # the malloc pin
build=${1:-$here/../build}
rounds=${2:-21}
assets=${OSG_ASSETS:-$here/../../shared/assets/osg}
shift $(($# > 2 ? 2 : $#))
files=("$@")
((${#files[@]})) || files=("$assets/cessna.osgt" "$assets/lz.osgt")
export OSG_FILE_PATH=${OSG_FILE_PATH:-$assets}
stamp "$build"
echo
echo "| file | loader | median ms | ratio to OSG (median of rounds) | resident growth MiB |"
echo "|---|---|---:|---:|---:|"
for f in "${files[@]}"; do
  "$build/bench/osg_load" "$f" --rounds "$rounds" --memory-runs 5 | grep '^OSG_LOAD' |
    sed -n 's/.*file=\([^ ]*\) loader=[0-9] name="\([^"]*\)" median_ms=\([0-9.]*\) min_ms=[0-9.]* ratio_to_osg=\([0-9.]*\) rss_growth_mib=\([0-9.]*\).*/| \1 | \2 | \3 | \4 | \5 |/p'
done

#!/usr/bin/env bash
# The same OpenSceneGraph files rendered by OSG itself (bench/osg_view) and by sgfx (sgfx-view),
# plain and with height fog and ambient occlusion, same camera, into docs/images/osg/ for
# docs/coming-from-osg.md. Needs a build with OpenSceneGraph and CLI11 (osg_view) and sgfx-view.
# Usage: scripts/osg-figures.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
assets=${OSG_ASSETS:-../shared/assets/osg} # used by path, never copied (their licence)
export OSG_FILE_PATH=$assets                # so Images/... resolve
out=docs/images/osg
size=384x256
mkdir -p "$out"
for name in lz glsl_simple; do
  file=$assets/$name.osgt
  "$build/bench/osg_view" "$file" --size $size --out "$out/${name}_osg.png"
  "$build/demos/sgfx-view" "$file" --size $size --out "$out/${name}_sgfx.png"
  "$build/demos/sgfx-view" "$file" --size $size --fog auto --ao --out "$out/${name}_sgfx_fog_ao.png"
done
du -ch "$out"/*.png | tail -1

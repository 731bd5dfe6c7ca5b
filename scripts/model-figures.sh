#!/usr/bin/env bash
# Renders every shared glTF model with sgfx-view into docs/images/models/: four panels each,
# plain | height fog | ambient occlusion | both. Usage: scripts/model-figures.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
assets=../shared/assets/gltf
out=docs/images/models
mkdir -p "$out"
view() { # NAME FILE [sgfx-view options]
  local name=$1 file=$2
  shift 2
  "$build/demos/sgfx-view" --compare --size 200x150 --out "$out/$name.png" "$@" "$assets/$file"
}
view Box Box/glTF-Binary/Box.glb
view BoxTextured BoxTextured/glTF-Binary/BoxTextured.glb
view Duck Duck/glTF-Binary/Duck.glb
view AlphaBlendModeTest AlphaBlendModeTest/glTF/AlphaBlendModeTest.gltf --yaw 0 --pitch 15
view NormalTangentMirrorTest NormalTangentMirrorTest/glTF/NormalTangentMirrorTest.gltf --yaw 0 --pitch 0 --no-ground
view TextureCoordinateTest TextureCoordinateTest/glTF/TextureCoordinateTest.gltf --yaw 0 --pitch 0 --no-ground
view OrientationTest OrientationTest/glTF/OrientationTest.gltf --yaw 20 --pitch 20
view SimpleSparseAccessor SimpleSparseAccessor/glTF/SimpleSparseAccessor.gltf --yaw 0 --pitch 0 --no-ground
view MetalRoughSpheresNoTextures MetalRoughSpheresNoTextures/glTF/MetalRoughSpheresNoTextures.gltf --yaw 0 --pitch 10

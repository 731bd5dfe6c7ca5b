#!/usr/bin/env bash
# Regenerates the effect pages' images (docs/images/) from the demos: before/after pairs for
# every effect, each pair from one view so only the effect differs.
#   scripts/effect-figures.sh [BUILD_DIR] [OUT_DIR]      (defaults: build, docs/images)
# About two minutes on two cores (the proving ground is built once per image).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-docs/images}
mkdir -p "$out"
for demo in polygon particles ao_figure volume_sky; do
  [ -x "$build/demos/$demo" ] || { echo "effect-figures: $build/demos/$demo not built" >&2; exit 1; }
done
polygon() { "$build/demos/polygon" "$@" > /dev/null; echo "effect-figures: ${*: -1}"; }

# Fog (docs/effects/fog.md): none, the seed's figure 1 solid and ground presets, one view.
polygon --size 640x360 --fog off --out "$out/fog_off.png"
polygon --size 640x360 --fog-preset solid --out "$out/fog_solid.png"
polygon --size 640x360 --fog-preset ground --out "$out/fog_ground.png"
# Fog behind a glass pane in each mode, denser than the presets so it shows within 100 m:
# forward fogs what is behind the pane, post-process leaves it clear (the seed's figure 2).
for mode in forward:forward split:split post:postprocess; do
  polygon --size 640x360 --look 21,20,3,27,45,4 --fog "${mode%%:*}" --fog-density 0.006 --fog-falloff 0.01 \
    --out "$out/fog_glass_${mode##*:}.png"
done

# Transparency (docs/effects/transparency.md): the crossing panes sorted and order-independent.
for mode in sorted oit; do
  polygon --size 480x270 --fog off --look 14,4,5,30,22,2 --transparency $mode --out "$out/glass_crossing_$mode.png"
done

# Ambient occlusion (docs/effects/ao.md): the seed's figures 1, 5, 7 and 8.
"$build/demos/ao_figure" --out-dir "$out" > /dev/null && echo "effect-figures: ao_robot_*.png, ao_map_*.png"

# Anti-aliasing (docs/effects/antialiasing.md): a 120x80 crop of a 1280x720 view (building
# edges, leaves) per mode, each pixel shown 3x3.
for aa in none msaa4 ssaa2 fxaa taa; do
  polygon --fog off --aa $aa --look 22,8,3.5,30,22,2 --crop 560,250,120,80,3 --out "$out/aa_crop_$aa.png"
done

# Particles (docs/effects/particles.md): the same view without and with 200,000 raindrops, and
# the presets' showcase.
polygon --size 640x360 --out "$out/rain_off.png"
polygon --size 640x360 --rain --out "$out/rain.png"
"$build/demos/particles" --size 640x360 --out "$out/particles.png" > /dev/null && echo "effect-figures: particles.png"

# Volumes and sky (docs/effects/volume-sky.md): the proving ground at 18:30 without and with the
# sky and the smoke cloud, and the showcase over a day without and with them.
polygon --size 640x360 --out "$out/sky_smoke_off.png"
polygon --size 640x360 --sky 18.5 --smoke --out "$out/sky_smoke.png"
"$build/demos/volume_sky" --no-volume --no-sky --size 240x135 --out "$out/volume_sky_off.png" > /dev/null
"$build/demos/volume_sky" --size 240x135 --out "$out/volume_sky.png" > /dev/null && echo "effect-figures: volume_sky*.png"

# Shadows (docs/effects/shadows.md): the default view without and with the sun's shadows
# (PCF), and with each cascade tinted.
polygon --size 640x360 --out "$out/shadows_off.png"
polygon --size 640x360 --shadows on --out "$out/shadows_pcf.png"
polygon --size 640x360 --shadows on --shadow-debug cascades --out "$out/shadows_cascades.png"
# The leaves' cut-out shadows: a tree's crossed cards (no levels of detail) at 17:00.
polygon --size 480x270 --shadows on --no-lod --sky 17 --look 86,16,12,79,27,0 --out "$out/shadows_leaves.png"

#version 450 core
// The sky behind everything: each pixel's view ray through the atmosphere, plus the sun's disc.
// Drawn on the far plane after the opaque items, only where none of them drew. It has no colour
// hook: fog does not apply to the sky (it is its own aerial perspective).
#include "sky_scattering.glsl"

in vec2 v_uv;
layout(location = 0) out vec4 sgfx_fragColor;
uniform float u_sunCosRadius; // cos of the sun's angular radius
uniform float u_sunDiscRadiance;

// @sgfx:fragment_decl

void main() {
    vec4 w = sgfx_invViewProjection * vec4(v_uv * 2.0 - 1.0, 1.0, 1.0);
    vec3 dir = normalize(w.xyz / w.w - sgfx_eye.xyz);
    vec3 sunT;
    vec3 c = skyRadiance(dir, sunT);
    if (dot(dir, u_sunDirection) > u_sunCosRadius) c += u_sunDiscRadiance * sunT;
    sgfx_fragColor = vec4(c, 1.0);
}

#version 450 core
// The sky behind everything: each pixel's view ray through the atmosphere, plus the sun's disc.
// Drawn on the far plane after the opaque items, only where none of them drew. It has no colour
// hook: fog does not apply to the sky (it is its own aerial perspective).
#include "sky_scattering.glsl"

in vec2 v_uv;
layout(location = 0) out vec4 sgfx_fragColor;
uniform float u_sunCosRadius; // cos of the sun's angular radius
uniform float u_sunDiscRadiance;
#ifdef SGFX_SKY_LUT
// The sky-view table (sky_lut.frag), and the sun's transmittance computed on the CPU.
uniform sampler2D u_skyLut;
uniform vec3 u_sunTransmittance;
#endif

// @sgfx:fragment_decl

void main() {
    vec4 w = sgfx_invViewProjection * vec4(v_uv * 2.0 - 1.0, 1.0, 1.0);
    vec3 dir = normalize(w.xyz / w.w - sgfx_eye.xyz);
#ifdef SGFX_SKY_LUT
    // SkyMath.h: lutCoordinates. A normalised z may round above 1, outside asin's domain.
    vec3 level = skyDirection(dir);
    float elevation = asin(clamp(level.z, 0.0, 1.0));
    vec2 uv = vec2(atan(level.y, level.x) / 6.283185307179586 + 0.5, sqrt(elevation / 1.5707963267948966));
    vec3 c = texture(u_skyLut, uv).rgb;
    vec3 sunT = dir.z >= 0.0 ? u_sunTransmittance : vec3(0.0);
#else
    vec3 sunT;
    vec3 c = skyRadiance(dir, sunT);
#endif
    if (dot(dir, u_sunDirection) > u_sunCosRadius) c += u_sunDiscRadiance * sunT;
    sgfx_fragColor = vec4(c, 1.0);
}

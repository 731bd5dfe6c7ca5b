#version 450 core
// One splat (lecture 12, "Volume rendering: splatting"): the eye ray through this fragment
// passes the kernel's centre at distance r; the 3D Gaussian integrated along it is the 2D one,
// so the ray crosses ℓ = h³·G2(r) metres' worth of the centre's medium (VolumeMath.h). Opacity
// 1 − e^(−σℓ) and the emission of that homogeneous stretch, premultiplied, blended back to front.
#include "volume_phase.glsl"

in vec3 v_worldPos;
flat in vec3 v_centre;
flat in float v_sigma;
flat in vec3 v_source;
flat in vec3 v_sunSource;
layout(location = 0) out vec4 sgfx_fragColor;

uniform vec3 u_lightDirection;
uniform float u_splatRadius;   // R
uniform float u_splatSigma;    // s
uniform float u_splatWeight;   // h³ / (2π s² · (1 − e^(−R²/2s²))): ℓ at r = 0
uniform sampler2D u_sceneDepth; // the scene depth, on a unit the renderer picks
uniform int u_hasSceneDepth;

// @sgfx:fragment_decl

void main() {
    if (u_hasSceneDepth != 0 && gl_FragCoord.z > texelFetch(u_sceneDepth, ivec2(gl_FragCoord.xy), 0).r) discard;
    vec3 eye = sgfx_eye.xyz;
    vec3 d = normalize(v_worldPos - eye);
    vec3 toCentre = v_centre - eye;
    float along = dot(toCentre, d);
    float r2 = max(dot(toCentre, toCentre) - along * along, 0.0);
    if (r2 >= u_splatRadius * u_splatRadius) discard;
    float len = u_splatWeight * exp(-r2 / (2.0 * u_splatSigma * u_splatSigma));
    vec3 sun = v_sunSource;
#ifdef SGFX_SHADOW_SUN
    sun *= sgfx_sunVisibility(v_centre, vec3(0.0)); // a ShadowNode above: the sun's visibility
#endif
    vec3 source = v_source + sun * volumePhase(dot(u_lightDirection, -d));
    float y = v_sigma * len;
    float alpha = 1.0 - exp(-y);
    vec3 radiance = source * len * (y < 1e-3 ? 1.0 - y * (0.5 - y / 6.0) : alpha / y);
    vec4 sgfx_color = vec4(radiance, alpha);
    vec3 sgfx_worldPos = v_centre; // fog up to the kernel
    vec3 sgfx_eyePos = eye;
    // @sgfx:color
    sgfx_fragColor = sgfx_color;
}

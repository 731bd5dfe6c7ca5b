#version 450 core
// One slice of the medium: the eye ray spends u_spacing / |cos| metres between this slice and
// the next, so its opacity is 1 − e^(−σ·that) and it adds the emission and in-scattered light of
// that stretch (exact for a homogeneous stretch). Blended back to front, premultiplied.
#include "volume_phase.glsl"
#include "volume_density.glsl"

in vec3 v_worldPos;
in vec3 v_boxPos;
layout(location = 0) out vec4 sgfx_fragColor;

uniform mat4 u_worldToBox;
uniform vec3 u_boxSize;
uniform float u_absorption;
uniform float u_scattering;
uniform vec3 u_emission;
uniform vec3 u_lightColor;
uniform float u_ambient; // scales the scene's ambient light scattered by the medium
uniform vec3 u_lightDirection;
uniform int u_lightSteps;
uniform vec3 u_sliceNormal; // world, the view direction the slices face
uniform float u_spacing;    // metres between slices along it
uniform sampler2D u_sceneDepth; // the scene depth, on a unit the renderer picks
uniform int u_hasSceneDepth;

// @sgfx:fragment_decl

vec2 boxInterval(vec3 o, vec3 d, vec3 lo, vec3 hi) {
    vec3 inv = vec3(abs(d.x) > 1e-12 ? 1.0 / d.x : 1e30, abs(d.y) > 1e-12 ? 1.0 / d.y : 1e30,
                    abs(d.z) > 1e-12 ? 1.0 / d.z : 1e30);
    vec3 t0 = (lo - o) * inv, t1 = (hi - o) * inv;
    vec3 tn = min(t0, t1), tf = max(t0, t1);
    return vec2(max(max(tn.x, tn.y), tn.z), min(min(tf.x, tf.y), tf.z));
}

void main() {
    if (u_hasSceneDepth != 0 && gl_FragCoord.z > texelFetch(u_sceneDepth, ivec2(gl_FragCoord.xy), 0).r) discard;
    vec3 eye = sgfx_eye.xyz;
    vec3 dirW = normalize(v_worldPos - eye);
    float along = u_spacing / max(abs(dot(dirW, u_sliceNormal)), 1e-3);
    vec3 h = 0.5 * u_boxSize;
    float rho = densityAt(v_boxPos / u_boxSize + 0.5);
    float sigma = (u_absorption + u_scattering) * rho;
    vec3 source = u_emission * rho + u_ambient * sgfx_ambientLight.rgb * (u_scattering * rho);
    if (u_scattering > 0.0 && rho > 0.0) {
        vec3 dl = mat3(u_worldToBox) * -u_lightDirection;
        float sMax = max(boxInterval(v_boxPos, dl, -h, h).y, 0.0);
        float ds = sMax / float(u_lightSteps);
        float lightDepth = 0.0;
        for (int j = 0; j < u_lightSteps; ++j)
            lightDepth += (u_absorption + u_scattering) * densityAt((v_boxPos + (float(j) + 0.5) * ds * dl) / u_boxSize + 0.5) * ds;
        vec3 sunlit = u_lightColor * exp(-lightDepth);
#ifdef SGFX_SHADOW_SUN
        sunlit *= sgfx_sunVisibility(v_worldPos, vec3(0.0)); // a ShadowNode above: the sun's visibility
#endif
        source += sunlit * (u_scattering * rho) * volumePhase(dot(u_lightDirection, -dirW));
    }
    float y = sigma * along;
    float alpha = 1.0 - exp(-y);
    vec3 radiance = source * along * (y < 1e-3 ? 1.0 - y * (0.5 - y / 6.0) : alpha / y);
    vec4 sgfx_color = vec4(radiance, alpha);
    vec3 sgfx_worldPos = v_worldPos;
    vec3 sgfx_eyePos = eye;
    // @sgfx:color
    sgfx_fragColor = sgfx_color;
}

#version 450 core
// FXAA's edge test alone (its step 1): pixels whose luma neighbourhood has too little contrast
// are discarded, the others mark the stencil, so the filter itself runs on edge pixels only.
in vec2 v_uv;
layout(binding = 1) uniform sampler2D sgfx_aaLuma;
uniform vec3 sgfx_fxaa; // edge threshold, minimum threshold, sub-pixel amount

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy), last = textureSize(sgfx_aaLuma, 0) - 1;
    float M = texelFetch(sgfx_aaLuma, p, 0).r;
    float N = texelFetch(sgfx_aaLuma, min(p + ivec2(0, 1), last), 0).r;
    float S = texelFetch(sgfx_aaLuma, max(p - ivec2(0, 1), ivec2(0)), 0).r;
    float E = texelFetch(sgfx_aaLuma, min(p + ivec2(1, 0), last), 0).r;
    float W = texelFetch(sgfx_aaLuma, max(p - ivec2(1, 0), ivec2(0)), 0).r;
    float lo = min(M, min(min(N, S), min(E, W))), hi = max(M, max(max(N, S), max(E, W)));
    if (hi - lo < max(sgfx_fxaa.y, hi * sgfx_fxaa.x)) discard;
}

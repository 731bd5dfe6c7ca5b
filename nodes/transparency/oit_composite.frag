#version 450 core
// Weighted blended OIT, resolve: the weighted average colour over the opaque image with coverage
// 1 − Π(1 − α) (McGuire & Bavoil 2013, eq. 6), blended as straight alpha.
in vec2 v_uv;
layout(binding = SGFX_OIT_ACCUM_UNIT) uniform sampler2D sgfx_oitAccum;
layout(binding = SGFX_OIT_REVEAL_UNIT) uniform sampler2D sgfx_oitReveal;
layout(location = 0) out vec4 sgfx_fragColor;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float revealage = texelFetch(sgfx_oitReveal, p, 0).r;
    if (revealage >= 1.0) discard; // nothing transparent here
    // Half floats overflow to infinity under many heavy layers: keep the quotient finite.
    vec4 accum = min(texelFetch(sgfx_oitAccum, p, 0), vec4(65504.0));
    sgfx_fragColor = vec4(accum.rgb / max(accum.a, 1e-5), 1.0 - clamp(revealage, 0.0, 1.0));
}

#version 450 core
// Weighted blended OIT, resolve: the weighted average colour over the opaque image with coverage
// 1 − Π(1 − α) (McGuire & Bavoil 2013, eq. 6), blended as straight alpha.
in vec2 v_uv;
#ifdef SGFX_OIT_MULTISAMPLE
// Per sample (reading gl_SampleID runs this once per sample of the multisampled view).
uniform sampler2DMS sgfx_oitAccum;
uniform sampler2DMS sgfx_oitReveal;
#define SGFX_OIT_SAMPLE gl_SampleID
#else
uniform sampler2D sgfx_oitAccum;
uniform sampler2D sgfx_oitReveal;
#define SGFX_OIT_SAMPLE 0
#endif
layout(location = 0) out vec4 sgfx_fragColor;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float revealage = texelFetch(sgfx_oitReveal, p, SGFX_OIT_SAMPLE).r;
    if (revealage >= 1.0) discard; // nothing transparent here
    // Half floats overflow to infinity under many heavy layers: keep the quotient finite.
    vec4 accum = min(texelFetch(sgfx_oitAccum, p, SGFX_OIT_SAMPLE), vec4(65504.0));
    sgfx_fragColor = vec4(accum.rgb / max(accum.a, 1e-5), 1.0 - clamp(revealage, 0.0, 1.0));
}

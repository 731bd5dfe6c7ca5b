#version 450 core
// SMAA neighbourhood blending (Jimenez et al. 2012, sec. 5): each pixel mixes in its neighbours
// across the edges around it by the weights the weights pass left on both sides of each edge,
// along the stronger direction only (horizontal lines or vertical ones), in linear colour.
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_fragColor;
layout(binding = 0) uniform sampler2D sgfx_aaSource;     // the finished image, linear on fetch
layout(binding = 1) uniform sampler2D sgfx_smaaWeightsTex; // smaa_weights.frag

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy), last = textureSize(sgfx_aaSource, 0) - 1;
    vec4 here = texelFetch(sgfx_smaaWeightsTex, p, 0);
    float up = here.r, left = here.b;
    float down = texelFetch(sgfx_smaaWeightsTex, max(p - ivec2(0, 1), ivec2(0)), 0).g;
    float right = texelFetch(sgfx_smaaWeightsTex, min(p + ivec2(1, 0), last), 0).a;
    if (p.y == 0) down = 0.0;
    if (p.x == last.x) right = 0.0;
    vec4 c = texelFetch(sgfx_aaSource, p, 0);
    if (max(max(up, down), max(left, right)) == 0.0) { // no edge around: most pixels
        sgfx_fragColor = vec4(c.rgb, 1.0);
        return;
    }
    bool vertical = max(up, down) > max(left, right);
    vec2 w = vertical ? vec2(up, down) : vec2(left, right);
    ivec2 a = vertical ? ivec2(0, 1) : ivec2(-1, 0), b = -a;
    vec4 ca = texelFetch(sgfx_aaSource, clamp(p + a, ivec2(0), last), 0);
    vec4 cb = texelFetch(sgfx_aaSource, clamp(p + b, ivec2(0), last), 0);
    sgfx_fragColor = vec4((c * (1.0 - w.x - w.y) + ca * w.x + cb * w.y).rgb, 1.0);
}

#version 450 core
// Temporal accumulation of the half-resolution occlusion (AmbientOcclusionParameters::temporal):
// each texel's point is carried into last frame's view; where last frame's texel there saw the
// same depth (within 2 %), k = mix(k_history, k_now, max(1/8, 1/(age + 1))), else the history
// starts again from this frame. History texel: (k, linear depth, age).
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_aoOut; // (k, linear depth) for the materials
layout(rgba32f) uniform writeonly image2D sgfx_aoHistoryOut;
uniform sampler2D sgfx_aoRaw;     // (k, linear depth) of this frame
uniform sampler2D sgfx_aoHistory; // last frame's (k, depth, age)
uniform mat4 sgfx_aoReproject;    // this view's space to last frame's view space
uniform mat4 sgfx_aoPreviousProjection;
uniform vec4 sgfx_aoTemporal; // draw size (x, y), draw pixels per texel, reset (0/1)

#include_ao_view_position

vec4 sgfx_aoBlend(vec2 now, ivec2 q) {
    vec2 size = sgfx_aoTemporal.xy;
    int scale = int(sgfx_aoTemporal.z);
    vec4 fresh = vec4(now, 1.0, 0.0);
    if (now.y <= 0.0 || sgfx_aoTemporal.w > 0.5) return fresh;
    vec4 before = sgfx_aoReproject * vec4(sgfx_aoPosition(q * scale, now.y, size), 1.0);
    vec4 clip = sgfx_aoPreviousProjection * before;
    if (clip.w <= 0.0) return fresh;
    vec2 at = (clip.xy / clip.w * 0.5 + 0.5) * size; // in last frame's draw pixels
    if (any(lessThan(at, vec2(0.0))) || any(greaterThanEqual(at, size))) return fresh;
    // Of the four history texels around that point, bilinear weights over those at its depth:
    // one nearest texel on a slanted floor can be a pixel off, and 2 % away, where these are not.
    vec2 t = (at - 0.5) / float(scale); // texel q holds draw pixel q·scale
    ivec2 b = ivec2(floor(t)), last = textureSize(sgfx_aoHistory, 0) - 1;
    vec2 f = t - vec2(b);
    float expected = -before.z, sum = 0.0, weight = 0.0, age = 64.0;
    for (int i = 0; i < 4; ++i) {
        ivec2 o = ivec2(i & 1, i >> 1);
        vec4 h = texelFetch(sgfx_aoHistory, clamp(b + o, ivec2(0), last), 0);
        float w = (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y) + 1e-4;
        if (!(h.y > 0.0) || abs(h.y - expected) > 0.02 * expected || isnan(h.x)) continue;
        sum += h.x * w;
        weight += w;
        age = min(age, h.z);
    }
    if (weight <= 0.0) return fresh;
    vec4 h = vec4(sum / weight, 0.0, age, 0.0);
    float alpha = max(1.0 / 8.0, 1.0 / (h.z + 1.0));
    return vec4(mix(h.x, now.x, alpha), now.y, min(h.z + 1.0, 64.0), 0.0);
}

void main() {
    ivec2 q = ivec2(gl_FragCoord.xy);
    vec2 now = texelFetch(sgfx_aoRaw, q, 0).rg;
    vec4 next = sgfx_aoBlend(now, q);
    imageStore(sgfx_aoHistoryOut, q, next);
    sgfx_aoOut = vec4(next.x, now.y, 0.0, 0.0);
}

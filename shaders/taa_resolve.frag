#version 450 core
// TAA: this frame's (jittered) pixel blended into the history, which is reprojected with the
// previous frame's view-projection and clamped to this frame's 3×3 neighbourhood so what has
// moved or been uncovered does not ghost. Writes the image and the next history.
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_fragColor;
layout(location = 1) out vec4 sgfx_taaHistoryOut;
layout(binding = 0) uniform sampler2D sgfx_taaCurrent; // linear on fetch
layout(binding = 1) uniform sampler2D sgfx_taaDepth;
layout(binding = 2) uniform sampler2D sgfx_taaHistory; // linear, RGBA16F
uniform mat4 sgfx_taaReprojection; // previous view-projection × inverse of this one (no jitter)
uniform float sgfx_taaAlpha;       // weight of this frame
uniform int sgfx_taaKeepCurrent;   // SMAA T2x: the history keeps this frame alone, not the blend

// The history at uv through a Catmull-Rom spline (nine bilinear taps, after Jimenez's
// "Filmic SMAA", SIGGRAPH 2016): a bilinear fetch blurs the history a little on every frame the
// camera moves by a fraction of a pixel, and those blurs add up over the history's 16 frames.
vec4 historyCatmullRom(vec2 uv, vec2 size) {
    vec2 pos = uv * size;
    vec2 centre = floor(pos - 0.5) + 0.5;
    vec2 f = pos - centre;
    vec2 w0 = f * (-0.5 + f * (1.0 - 0.5 * f));
    vec2 w1 = 1.0 + f * f * (-2.5 + 1.5 * f);
    vec2 w2 = f * (0.5 + f * (2.0 - 1.5 * f));
    vec2 w3 = f * f * (-0.5 + 0.5 * f);
    vec2 w12 = w1 + w2;
    vec2 t0 = (centre - 1.0) / size, t3 = (centre + 2.0) / size;
    vec2 t12 = (centre + w2 / w12) / size;
    vec4 sum = vec4(0.0);
    sum += textureLod(sgfx_taaHistory, vec2(t0.x, t0.y), 0.0) * (w0.x * w0.y);
    sum += textureLod(sgfx_taaHistory, vec2(t12.x, t0.y), 0.0) * (w12.x * w0.y);
    sum += textureLod(sgfx_taaHistory, vec2(t3.x, t0.y), 0.0) * (w3.x * w0.y);
    sum += textureLod(sgfx_taaHistory, vec2(t0.x, t12.y), 0.0) * (w0.x * w12.y);
    sum += textureLod(sgfx_taaHistory, vec2(t12.x, t12.y), 0.0) * (w12.x * w12.y);
    sum += textureLod(sgfx_taaHistory, vec2(t3.x, t12.y), 0.0) * (w3.x * w12.y);
    sum += textureLod(sgfx_taaHistory, vec2(t0.x, t3.y), 0.0) * (w0.x * w3.y);
    sum += textureLod(sgfx_taaHistory, vec2(t12.x, t3.y), 0.0) * (w12.x * w3.y);
    sum += textureLod(sgfx_taaHistory, vec2(t3.x, t3.y), 0.0) * (w3.x * w3.y);
    return sum;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 last = textureSize(sgfx_taaCurrent, 0) - 1;
    vec4 current = texelFetch(sgfx_taaCurrent, p, 0);
    vec4 lo = current, hi = current;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x) {
            vec4 c = texelFetch(sgfx_taaCurrent, clamp(p + ivec2(x, y), ivec2(0), last), 0);
            lo = min(lo, c);
            hi = max(hi, c);
        }
    vec2 size = vec2(last + 1);
    float d = texelFetch(sgfx_taaDepth, p, 0).r;
    vec4 ndc = vec4((vec2(p) + 0.5) / size * 2.0 - 1.0, d * 2.0 - 1.0, 1.0);
    vec4 prev = sgfx_taaReprojection * ndc;
    vec2 prevUv = prev.xy / prev.w * 0.5 + 0.5;
    vec4 history = current;
    if (sgfx_taaAlpha < 1.0 && all(greaterThanEqual(prevUv, vec2(0.0))) && all(lessThanEqual(prevUv, vec2(1.0))))
        history = clamp(historyCatmullRom(prevUv, size), lo, hi);
    vec4 result = mix(history, current, sgfx_taaAlpha);
    sgfx_fragColor = result;
    sgfx_taaHistoryOut = sgfx_taaKeepCurrent != 0 ? current : result;
}

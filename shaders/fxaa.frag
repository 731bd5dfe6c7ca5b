#version 450 core
// FXAA, written from Lottes' description of FXAA 3.11 (quality path): find pixels on a luma
// edge, decide whether the edge runs horizontally or vertically, walk along it both ways to its
// ends, and resample the pixel shifted across the edge by how far it is from the nearer end;
// a sub-pixel term softens single-pixel features.
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_fragColor;
layout(binding = 0) uniform sampler2D sgfx_aaSource; // the finished image (linear on fetch)
layout(binding = 1) uniform sampler2D sgfx_aaLuma;   // its perceptual luma (fxaa_luma.frag)
uniform vec3 sgfx_fxaa; // edge threshold, minimum threshold, sub-pixel amount
// SGFX_FXAA_STEPS (the preset's search length) is compiled in, so the walk unrolls.

ivec2 sgfx_last; // set first thing in main
float lumaAt(vec2 uv) {
    return textureLod(sgfx_aaLuma, uv, 0.0).r;
}
float lumaOff(ivec2 p, ivec2 o) {
    return texelFetch(sgfx_aaLuma, clamp(p + o, ivec2(0), sgfx_last), 0).r;
}

// Step lengths along the edge, in pixels (FXAA 3.11's quality ladder).
float stepLengthAt(int i) {
    return i < 5 ? 1.0 : i == 5 ? 1.5 : i < 10 ? 2.0 : i == 10 ? 4.0 : 8.0;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    sgfx_last = textureSize(sgfx_aaLuma, 0) - 1;
    vec2 texel = 1.0 / vec2(sgfx_last + 1);
    vec2 uv = (vec2(p) + 0.5) * texel;
    float M = texelFetch(sgfx_aaLuma, p, 0).r;
    float N = lumaOff(p, ivec2(0, 1)), S = lumaOff(p, ivec2(0, -1));
    float E = lumaOff(p, ivec2(1, 0)), W = lumaOff(p, ivec2(-1, 0));
    float lo = min(M, min(min(N, S), min(E, W))), hi = max(M, max(max(N, S), max(E, W)));
    float range = hi - lo;
    // 1. Not on an edge: keep the pixel.
    if (range < max(sgfx_fxaa.y, hi * sgfx_fxaa.x)) {
        sgfx_fragColor = texelFetch(sgfx_aaSource, p, 0);
        return;
    }
    float NW = lumaOff(p, ivec2(-1, 1)), NE = lumaOff(p, ivec2(1, 1));
    float SW = lumaOff(p, ivec2(-1, -1)), SE = lumaOff(p, ivec2(1, -1));
    // 2. Edge orientation from second differences across rows and columns.
    float edgeH = abs(-2.0 * W + NW + SW) + 2.0 * abs(-2.0 * M + N + S) + abs(-2.0 * E + NE + SE);
    float edgeV = abs(-2.0 * N + NW + NE) + 2.0 * abs(-2.0 * M + W + E) + abs(-2.0 * S + SW + SE);
    bool horizontal = edgeH >= edgeV;
    // 3. Which side of the pixel the edge lies on: the steeper gradient.
    float l1 = horizontal ? S : W, l2 = horizontal ? N : E;
    float g1 = l1 - M, g2 = l2 - M;
    bool steepest1 = abs(g1) >= abs(g2);
    float gradientScaled = 0.25 * max(abs(g1), abs(g2));
    float stepLength = horizontal ? texel.y : texel.x;
    float localAverage;
    if (steepest1) {
        stepLength = -stepLength;
        localAverage = 0.5 * (l1 + M);
    } else {
        localAverage = 0.5 * (l2 + M);
    }
    vec2 edgeUv = uv;
    if (horizontal)
        edgeUv.y += stepLength * 0.5;
    else
        edgeUv.x += stepLength * 0.5;
    // 4. Walk along the edge both ways until the luma leaves the edge's average.
    vec2 dir = horizontal ? vec2(texel.x, 0.0) : vec2(0.0, texel.y);
    vec2 uv1 = edgeUv - dir, uv2 = edgeUv + dir;
    float end1 = lumaAt(uv1) - localAverage, end2 = lumaAt(uv2) - localAverage;
    bool done1 = abs(end1) >= gradientScaled, done2 = abs(end2) >= gradientScaled;
    for (int i = 1; i < SGFX_FXAA_STEPS && !(done1 && done2); ++i) {
        if (!done1) {
            uv1 -= dir * stepLengthAt(i);
            end1 = lumaAt(uv1) - localAverage;
            done1 = abs(end1) >= gradientScaled;
        }
        if (!done2) {
            uv2 += dir * stepLengthAt(i);
            end2 = lumaAt(uv2) - localAverage;
            done2 = abs(end2) >= gradientScaled;
        }
    }
    // 5. Offset across the edge from the distance to the nearer end, if that end turns the way
    //    the pixel does.
    float d1 = horizontal ? uv.x - uv1.x : uv.y - uv1.y;
    float d2 = horizontal ? uv2.x - uv.x : uv2.y - uv.y;
    bool nearer1 = d1 < d2;
    float dist = min(d1, d2);
    bool centreSmaller = M < localAverage;
    bool turnsBack = ((nearer1 ? end1 : end2) < 0.0) != centreSmaller;
    float pixelOffset = turnsBack ? -dist / (d1 + d2) + 0.5 : 0.0;
    // 6. Sub-pixel aliasing: how far the pixel stands out from its 3×3 neighbourhood.
    float average = (2.0 * (N + S + E + W) + NW + NE + SW + SE) / 12.0;
    float sub = clamp(abs(average - M) / range, 0.0, 1.0);
    sub = (-2.0 * sub + 3.0) * sub * sub;
    float subOffset = sub * sub * sgfx_fxaa.z;
    float offset = max(pixelOffset, subOffset);
    vec2 finalUv = uv;
    if (horizontal)
        finalUv.y += offset * stepLength;
    else
        finalUv.x += offset * stepLength;
    sgfx_fragColor = vec4(textureLod(sgfx_aaSource, finalUv, 0.0).rgb, 1.0);
}

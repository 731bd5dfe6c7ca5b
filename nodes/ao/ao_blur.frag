#version 450 core
// Blur of the occlusion map (SSAO seed §3): the N×N mean (SGFX_AO_BOX), or by default the same
// window weighted by depth similarity, so occlusion does not bleed across depth edges. Run twice,
// along x then along y (the box is separable exactly, the bilateral weights nearly): 2N taps per
// pixel instead of N².
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_aoOut;
uniform sampler2D sgfx_aoRaw; // (k, linear depth)
uniform vec4 sgfx_aoBlur;                         // N, R, direction (1, 0) or (0, 1)

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 last = textureSize(sgfx_aoRaw, 0) - 1;
    vec2 centre = texelFetch(sgfx_aoRaw, p, 0).rg;
    if (centre.g <= 0.0) {
        sgfx_aoOut = vec4(0.0);
        return;
    }
    int r = int(sgfx_aoBlur.x) / 2;
    // Depth tolerance: half the kernel radius plus 2 % of the distance.
    float sigma = 0.5 * sgfx_aoBlur.y + 0.02 * centre.g;
    ivec2 step = ivec2(sgfx_aoBlur.zw);
    float sum = 0.0, weight = 0.0;
    for (int i = -r; i <= r; ++i) {
        vec2 s = texelFetch(sgfx_aoRaw, clamp(p + i * step, ivec2(0), last), 0).rg;
#ifdef SGFX_AO_BOX
        float w = 1.0; // seed §3: every texel of the window, 1/N² each (over both passes)
#else
        float dz = (s.g - centre.g) / sigma;
        float w = s.g > 0.0 ? exp(-dz * dz) : 0.0;
#endif
        if (isnan(s.r) || isinf(s.r)) w = 0.0; // one bad texel must not spread to the window
        sum += s.r * w;
        weight += w;
    }
    sgfx_aoOut = vec4(sum / max(weight, 1e-6), centre.g, 0.0, 0.0);
}

#version 450 core
// Blur of the occlusion map (SSAO seed §3): the N×N mean (SGFX_AO_BOX), or by default the same
// window weighted by depth similarity, so occlusion does not bleed across depth edges.
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_aoOut;
layout(binding = 0) uniform sampler2D sgfx_aoRaw; // (k, linear depth)
uniform vec2 sgfx_aoBlur;                         // N, R

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
    float sum = 0.0, weight = 0.0;
    for (int y = -r; y <= r; ++y)
        for (int x = -r; x <= r; ++x) {
            vec2 s = texelFetch(sgfx_aoRaw, clamp(p + ivec2(x, y), ivec2(0), last), 0).rg;
#ifdef SGFX_AO_BOX
            float w = 1.0; // seed §3: every texel of the window, 1/N² each
#else
            float dz = (s.g - centre.g) / sigma;
            float w = s.g > 0.0 ? exp(-dz * dz) : 0.0;
#endif
            sum += s.r * w;
            weight += w;
        }
    sgfx_aoOut = vec4(sum / max(weight, 1e-6), centre.g, 0.0, 0.0);
}

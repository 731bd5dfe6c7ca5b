// The occlusion k at this fragment (SSAO seed §4), after intensity and power; read at
// gl_FragCoord, upsampled by depth from a half-size map. Callable from foreign shaders too.
uniform sampler2D sgfx_aoMap; // (k, linear depth)
uniform vec2 sgfx_aoApply;                                    // intensity, power

float sgfx_ambientOcclusion() {
    ivec2 size = textureSize(sgfx_aoMap, 0);
    ivec2 p = ivec2(gl_FragCoord.xy);
    float k;
    if (size.x * 2 > int(sgfx_viewport.z) + 1) { // full size
        k = texelFetch(sgfx_aoMap, min(p, size - 1), 0).r;
    } else {
        // Half size: of the four nearest texels, those at this fragment's depth count.
        float ndcZ = gl_FragCoord.z * 2.0 - 1.0;
        float d = sgfx_projection[2][3] != 0.0 ? sgfx_projection[3][2] / (ndcZ + sgfx_projection[2][2])
                                               : (sgfx_projection[3][2] - ndcZ) / sgfx_projection[2][2];
        vec2 h = (vec2(p) + 0.5) * 0.5 - 0.5;
        ivec2 b = ivec2(floor(h));
        vec2 f = h - vec2(b);
        float sum = 0.0, weight = 0.0;
        for (int i = 0; i < 4; ++i) {
            ivec2 o = ivec2(i & 1, i >> 1);
            vec2 s = texelFetch(sgfx_aoMap, clamp(b + o, ivec2(0), size - 1), 0).rg;
            float bilinear = (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y);
            float w = (bilinear + 1e-3) / (1e-3 + abs(s.g - d) / max(d, 1e-3));
            sum += s.r * w;
            weight += w;
        }
        k = sum / weight;
    }
    return pow(clamp(k * sgfx_aoApply.x, 0.0, 1.0), sgfx_aoApply.y);
}

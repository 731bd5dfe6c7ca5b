#version 450 core
// Half-resolution volumes (and, with SGFX_VOLUME_SAME_SIZE, full-size splats texel for texel,
// composited over the view premultiplied): each pixel takes the four nearest half-size samples, weighted
// bilinearly and by how close the depth where their rays stopped is to this pixel's scene depth,
// so a wall's edge in front of the medium does not bleed (depth-aware upsampling).
in vec2 v_uv;
layout(location = 0) out vec4 fragColor;
layout(binding = SGFX_VOLUME_HALF_UNIT) uniform sampler2D u_halfColor;     // premultiplied
layout(binding = SGFX_VOLUME_HALF_UNIT + 1) uniform sampler2D u_halfDepth; // where rays stopped
uniform sampler2D u_sceneDepth; // the scene depth, on a unit the renderer picks

float linearDepth(float windowZ) {
    float ndcZ = windowZ * 2.0 - 1.0;
    return sgfx_projection[2][3] != 0.0 ? sgfx_projection[3][2] / (ndcZ + sgfx_projection[2][2])
                                        : (sgfx_projection[3][2] - ndcZ) / sgfx_projection[2][2];
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
#ifdef SGFX_VOLUME_SAME_SIZE
    // Splats: drawn at this size, each fragment already hidden behind the scene's depth.
    fragColor = texelFetch(u_halfColor, p, 0);
#else
    float z = texelFetch(u_sceneDepth, p, 0).r;
    ivec2 size = textureSize(u_halfColor, 0);
    vec2 h = (vec2(p) + 0.5) * 0.5 - 0.5;
    ivec2 b = ivec2(floor(h));
    vec2 f = h - vec2(b);
    vec4 sum = vec4(0.0);
    float weight = 0.0;
    for (int i = 0; i < 4; ++i) {
        ivec2 o = ivec2(i & 1, i >> 1);
        ivec2 q = clamp(b + o, ivec2(0), size - 1);
        float bilinear = (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y);
        float w = bilinear + 1e-3;
        if (z < 1.0) {
            float d = linearDepth(z), dq = texelFetch(u_halfDepth, q, 0).r;
            // Rays stopped before this pixel's surface still apply; past it, they must not.
            if (dq > 0.0 && dq - d > 0.02 * d) w *= 1e-4;
        }
        sum += texelFetch(u_halfColor, q, 0) * w;
        weight += w;
    }
    fragColor = sum / weight;
#endif
}

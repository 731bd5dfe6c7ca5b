#version 450 core
// Occlusion map (SSAO seed §2): for the surface point P of each pixel, m points A = P + R·TBN·S
// around it; k = (1/m)·Σ F, F = 1 where the surface seen at A's pixel lies in front of A by δ.
// Output (k, linear depth of P) for the blur and the upsampling.
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_aoOut;

uniform sampler2D sgfx_aoNoise; // 4×4 rotation vectors V_r

uniform vec3 sgfx_aoKernel[64];
uniform int sgfx_aoSamples;
uniform vec4 sgfx_aoShape;  // R, δ, range check (0/1), tangent-plane compare (0/1)
uniform vec4 sgfx_aoShape2; // draw pixels per map pixel (1 or 2), fade unresolved (0/1)
uniform vec4 sgfx_aoGrid;   // draw size (x, y), draw pixels per G-buffer texel (1, or 2 from depth)

#include_ao_view_position

void main() {
    int scale = int(sgfx_aoShape2.x), gs = int(sgfx_aoGrid.z);
    ivec2 gp = ivec2(gl_FragCoord.xy) * scale; // in draw pixels
    float d = texelFetch(sgfx_aoGDepth, gp / gs, 0).r;
    if (d <= 0.0) { // nothing drawn here
        sgfx_aoOut = vec4(0.0);
        return;
    }
    float R = sgfx_aoShape.x, delta = sgfx_aoShape.y;
    bool rangeCheck = sgfx_aoShape.z > 0.5, plane = sgfx_aoShape.w > 0.5;
    vec2 gsize = sgfx_aoGrid.xy;
    vec3 P = sgfx_aoPosition(gp, d, gsize);
    vec3 gN = texelFetch(sgfx_aoGNormal, gp / gs, 0).xyz;
    if (!(dot(gN, gN) > 1e-12)) { // no usable normal (zero or NaN from a foreign shader): unoccluded
        sgfx_aoOut = vec4(0.0, d, 0.0, 0.0);
        return;
    }
    vec3 N = normalize(gN);
    // Seed §2: TBN by Gram–Schmidt from a per-pixel random vector, B = N × T.
    vec3 Vr = vec3(texelFetch(sgfx_aoNoise, ivec2(gl_FragCoord.xy) & 3, 0).xy, 0.0);
    vec3 T = Vr - N * dot(Vr, N);
    T = dot(T, T) > 1e-8 ? normalize(T) : normalize(abs(N.x) < 0.9 ? cross(N, vec3(1, 0, 0)) : cross(N, vec3(0, 1, 0)));
    mat3 tbn = mat3(T, cross(N, T), N);
    float occlusion = 0.0;
    for (int i = 0; i < sgfx_aoSamples; ++i) {
        vec3 A = P + R * (tbn * sgfx_aoKernel[i]);
        vec4 clip = sgfx_projection * vec4(A, 1.0);
        if (clip.w <= 0.0) continue;
        vec2 uv = clip.xy / clip.w * 0.5 + 0.5; // seed §2: A_scr
        if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) continue;
        ivec2 tp = ivec2(uv * gsize) / gs; // the G-buffer texel, holding draw pixel tp·gs
        float dt = texelFetch(sgfx_aoGDepth, tp, 0).r;
        if (dt <= 0.0) continue; // background: open
        vec3 Pt = sgfx_aoPosition(tp * gs, dt, gsize);
        float zt = plane ? sgfx_aoPlaneDepth(Pt, normalize(texelFetch(sgfx_aoGNormal, tp, 0).xyz), A) : Pt.z;
        if (zt >= A.z + delta) // seed §2: F(z_A, z_t)
            occlusion += rangeCheck ? smoothstep(0.0, 1.0, R / abs(P.z - zt)) : 1.0;
    }
    float k = occlusion / float(sgfx_aoSamples);
    if (sgfx_aoShape2.y > 0.5) {
        // A kernel under about a pixel cannot resolve any occluder, only noise: fade it out.
        float pixels = sgfx_aoPerspective() ? R * sgfx_projection[1][1] * 0.5 * gsize.y / d
                                            : R * sgfx_projection[1][1] * 0.5 * gsize.y;
        k *= smoothstep(1.0, 3.0, pixels);
    }
    sgfx_aoOut = vec4(k, d, 0.0, 0.0);
}

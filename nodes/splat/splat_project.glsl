// The EWA projection of one Gaussian (Zwicker et al. 2001 eq. 31; Kerbl et al. 2023 eq. 5):
// Σ = R S Sᵀ Rᵀ, Σ' = J W Σ Wᵀ Jᵀ + 0.3 I (the low-pass), conic = Σ'⁻¹, radius = 3σ of the major
// axis, in window pixels. SplatMath.h's project() is the CPU mirror.
mat3 splatCovariance(vec3 scale, vec4 q) { // q = (w, x, y, z), unit
    float w = q.x, x = q.y, y = q.z, z = q.w;
    mat3 r = mat3(1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + w * z), 2.0 * (x * z - w * y),
                  2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x),
                  2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y));
    mat3 m = r * mat3(scale.x, 0.0, 0.0, 0.0, scale.y, 0.0, 0.0, 0.0, scale.z);
    return m * transpose(m);
}

// Returns false for a degenerate conic; `t` is the centre in view space.
bool splatConic(mat3 sigma, mat3 modelView, vec4 t, out vec3 conic, out float radius) {
    vec2 f = vec2(sgfx_projection[0][0], sgfx_projection[1][1]) * 0.5 * sgfx_viewport.zw;
    mat3 j = mat3(0.0);
    if (sgfx_projection[3][3] == 0.0) {
        float d = -t.z;
        vec2 lim = 1.3 / vec2(sgfx_projection[0][0], sgfx_projection[1][1]);
        vec2 txy = clamp(t.xy / d, -lim, lim) * d;
        j[0][0] = f.x / d;
        j[2][0] = f.x * txy.x / (d * d);
        j[1][1] = f.y / d;
        j[2][1] = f.y * txy.y / (d * d);
    } else {
        j[0][0] = f.x;
        j[1][1] = f.y;
    }
    mat3 c = j * modelView * sigma * transpose(modelView) * transpose(j);
    float a = c[0][0] + 0.3, b = c[1][0], cc = c[1][1] + 0.3;
    float det = a * cc - b * b;
    if (!(det > 0.0)) return false;
    conic = vec3(cc, -b, a) / det;
    float mid = 0.5 * (a + cc);
    radius = 3.0 * sqrt(mid + sqrt(max(0.1, mid * mid - det)));
    return true;
}

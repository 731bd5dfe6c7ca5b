// Colour of a splat seen along `dir` (unit, camera → splat, the splat's frame): 0.5 plus the real
// spherical harmonics of degree u_shDegree (0..3) with the reference's constants and signs (its
// SH_C0..SH_C3), clamped at 0. SplatMath.h's shColour is the CPU mirror.
const float SH_C0 = 0.28209479177387814;
const float SH_C1 = 0.4886025119029199;
const float SH_C2[5] = float[5](1.0925484305920792, -1.0925484305920792, 0.31539156525252005,
                                -1.0925484305920792, 0.5462742152960396);
const float SH_C3[7] = float[7](-0.5900435899266435, 2.890611442640554, -0.4570457994644658,
                                0.3731763325901154, -0.4570457994644658, 1.445305721320277,
                                -0.5900435899266435);

vec3 splatCoefficient(uint splat, int k) {
    uint base = (splat * uint((u_shDegree + 1) * (u_shDegree + 1)) + uint(k)) * 3u;
    return vec3(sgfx_splatSh[base], sgfx_splatSh[base + 1u], sgfx_splatSh[base + 2u]);
}

vec3 splatColour(uint s, vec3 dir) {
    vec3 r = SH_C0 * splatCoefficient(s, 0);
    if (u_shDegree > 0) {
        float x = dir.x, y = dir.y, z = dir.z;
        r += -SH_C1 * y * splatCoefficient(s, 1) + SH_C1 * z * splatCoefficient(s, 2) -
             SH_C1 * x * splatCoefficient(s, 3);
        if (u_shDegree > 1) {
            float xx = x * x, yy = y * y, zz = z * z, xy = x * y, yz = y * z, xz = x * z;
            r += SH_C2[0] * xy * splatCoefficient(s, 4) + SH_C2[1] * yz * splatCoefficient(s, 5) +
                 SH_C2[2] * (2.0 * zz - xx - yy) * splatCoefficient(s, 6) +
                 SH_C2[3] * xz * splatCoefficient(s, 7) + SH_C2[4] * (xx - yy) * splatCoefficient(s, 8);
            if (u_shDegree > 2)
                r += SH_C3[0] * y * (3.0 * xx - yy) * splatCoefficient(s, 9) +
                     SH_C3[1] * xy * z * splatCoefficient(s, 10) +
                     SH_C3[2] * y * (4.0 * zz - xx - yy) * splatCoefficient(s, 11) +
                     SH_C3[3] * z * (2.0 * zz - 3.0 * xx - 3.0 * yy) * splatCoefficient(s, 12) +
                     SH_C3[4] * x * (4.0 * zz - xx - yy) * splatCoefficient(s, 13) +
                     SH_C3[5] * z * (xx - yy) * splatCoefficient(s, 14) +
                     SH_C3[6] * x * (xx - 3.0 * yy) * splatCoefficient(s, 15);
        }
    }
    return max(r + 0.5, vec3(0.0));
}

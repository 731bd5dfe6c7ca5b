#pragma once
/// @file
/// The CPU mirror of the splat shaders' equations (3D Gaussian splatting, Kerbl et al. 2023):
/// spherical-harmonics colour, the 3D covariance, its EWA projection (Zwicker et al. 2001) with
/// the 0.3-pixel low-pass, the conic and the 3σ footprint, and the per-pixel alpha. Used by the
/// CPU sort, the tests' reference renderer and the docs; splat_project.glsl is the same in GLSL.
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>

namespace sgfx::splat {

/// Real spherical-harmonics constants of the reference implementation (its SH_C0..SH_C3).
inline constexpr float kC0 = 0.28209479177387814f;
inline constexpr float kC1 = 0.4886025119029199f;
inline constexpr float kC2[5] = {1.0925484305920792f, -1.0925484305920792f, 0.31539156525252005f,
                                 -1.0925484305920792f, 0.5462742152960396f};
inline constexpr float kC3[7] = {-0.5900435899266435f, 2.890611442640554f,   -0.4570457994644658f,
                                 0.3731763325901154f,  -0.4570457994644658f, 1.445305721320277f,
                                 -0.5900435899266435f};

/// Coefficients per colour channel for an SH degree (0..3): (degree + 1)².
inline constexpr int coefficientCount(int degree) {
    return (degree + 1) * (degree + 1);
}

/// Colour seen along unit direction `dir` (camera → splat, the splat's own frame): 0.5 + Σ c_k Y_k(dir),
/// clamped at 0. `sh` holds coefficientCount(degree) RGB triples, coefficient-major.
inline glm::vec3 shColour(int degree, const glm::vec3* sh, glm::vec3 dir) {
    glm::vec3 r = kC0 * sh[0];
    if (degree > 0) {
        const float x = dir.x, y = dir.y, z = dir.z;
        r += -kC1 * y * sh[1] + kC1 * z * sh[2] - kC1 * x * sh[3];
        if (degree > 1) {
            const float xx = x * x, yy = y * y, zz = z * z, xy = x * y, yz = y * z, xz = x * z;
            r += kC2[0] * xy * sh[4] + kC2[1] * yz * sh[5] + kC2[2] * (2.0f * zz - xx - yy) * sh[6] +
                 kC2[3] * xz * sh[7] + kC2[4] * (xx - yy) * sh[8];
            if (degree > 2)
                r += kC3[0] * y * (3.0f * xx - yy) * sh[9] + kC3[1] * xy * z * sh[10] +
                     kC3[2] * y * (4.0f * zz - xx - yy) * sh[11] +
                     kC3[3] * z * (2.0f * zz - 3.0f * xx - 3.0f * yy) * sh[12] +
                     kC3[4] * x * (4.0f * zz - xx - yy) * sh[13] + kC3[5] * z * (xx - yy) * sh[14] +
                     kC3[6] * x * (xx - 3.0f * yy) * sh[15];
        }
    }
    return glm::max(r + 0.5f, glm::vec3(0.0f));
}

/// Σ = R S Sᵀ Rᵀ (Kerbl et al. eq. 6) for scales `scale` (metres, already exp'd) and the unit
/// quaternion `rotation` (w, x, y, z).
inline glm::mat3 covariance(glm::vec3 scale, glm::vec4 rotation) {
    const glm::mat3 r = glm::mat3_cast(glm::quat(rotation.x, rotation.y, rotation.z, rotation.w));
    const glm::mat3 m = r * glm::mat3(scale.x, 0, 0, 0, scale.y, 0, 0, 0, scale.z);
    return m * glm::transpose(m);
}

/// One splat on screen: window-pixel centre (gl_FragCoord's frame), conic (the inverse 2D
/// covariance: a, b, c of [[a b][b c]]), 3σ radius in pixels, view depth (metres in front).
struct Footprint {
    glm::vec2 centre{0.0f};
    glm::vec3 conic{0.0f};
    float radius = 0.0f;
    float depth = 0.0f;
    bool visible = false;
};

/// The EWA projection (Zwicker et al. 2001, eq. 31; Kerbl et al. eq. 5): Σ' = J W Σ Wᵀ Jᵀ with W
/// the linear part of `modelView` and J the Jacobian of the perspective divide at the centre
/// (x, y clamped to 1.3× the field of view, as the reference does), plus 0.3 px² on the diagonal
/// (the low-pass filter). `viewport` is the target's size in pixels. Orthographic projections have
/// a constant J. Not visible: behind the near plane or a degenerate conic.
inline Footprint project(glm::vec3 position, const glm::mat3& sigma, const glm::mat4& modelView,
                         const glm::mat4& projection, glm::vec2 viewport) {
    Footprint f;
    const glm::vec4 t = modelView * glm::vec4(position, 1.0f);
    const glm::vec4 clip = projection * t;
    if (!(clip.w > 0.0f) || clip.z < -clip.w) return f;
    f.depth = -t.z;
    f.centre = (glm::vec2(clip) / clip.w * 0.5f + 0.5f) * viewport;
    const float fx = projection[0][0] * 0.5f * viewport.x, fy = projection[1][1] * 0.5f * viewport.y;
    glm::mat3 j(0.0f); // column-major: j[col][row]; the third row stays 0
    if (projection[3][3] == 0.0f) {
        const float d = -t.z, limX = 1.3f / projection[0][0], limY = 1.3f / projection[1][1];
        const float tx = std::clamp(t.x / d, -limX, limX) * d, ty = std::clamp(t.y / d, -limY, limY) * d;
        j[0][0] = fx / d;
        j[2][0] = fx * tx / (d * d);
        j[1][1] = fy / d;
        j[2][1] = fy * ty / (d * d);
    } else {
        j[0][0] = fx;
        j[1][1] = fy;
    }
    const glm::mat3 w(modelView);
    const glm::mat3 c = j * w * sigma * glm::transpose(w) * glm::transpose(j);
    const float a = c[0][0] + 0.3f, b = c[1][0], cc = c[1][1] + 0.3f;
    const float det = a * cc - b * b;
    if (!(det > 0.0f)) return f;
    f.conic = glm::vec3(cc / det, -b / det, a / det);
    const float mid = 0.5f * (a + cc);
    f.radius = 3.0f * std::sqrt(mid + std::sqrt(std::max(0.1f, mid * mid - det)));
    f.visible = true;
    return f;
}

/// alpha = opacity · exp(−½ dᵀ conic d) for `d` = pixel − centre, 0 below 1/255 and outside the
/// 3σ square the quad covers.
inline float alphaAt(const Footprint& f, float opacity, glm::vec2 pixel) {
    const glm::vec2 d = pixel - f.centre;
    if (std::abs(d.x) > f.radius || std::abs(d.y) > f.radius) return 0.0f;
    const float power = -0.5f * (f.conic.x * d.x * d.x + f.conic.z * d.y * d.y) - f.conic.y * d.x * d.y;
    if (power > 0.0f) return 0.0f;
    const float a = opacity * std::exp(power);
    return a < 1.0f / 255.0f ? 0.0f : a;
}

inline float sigmoid(float x) {
    return 1.0f / (1.0f + std::exp(-x));
}

} // namespace sgfx::splat

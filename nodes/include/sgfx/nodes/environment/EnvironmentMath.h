#pragma once
/// @file
/// CPU side of image-based lighting: cube-map addressing (OpenGL's convention), the split-sum
/// prefilter of Karis 2013 ("Real Shading in Unreal Engine 4") for the GGX lobe of
/// brdf_metallic_roughness.glsl, and order-2 spherical harmonics for diffuse irradiance
/// (Ramamoorthi and Hanrahan 2001, "An Efficient Representation for Irradiance Environment
/// Maps"). The shader (env_light.glsl) reads what these functions make.
#include "sgfx/Export.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace sgfx::env {

/// A cube map of linear RGB radiance, faces in OpenGL's order (+X, -X, +Y, -Y, +Z, -Z), each
/// `size` × `size` texels, row t = 0 first (the first row glTexImage reads).
struct SGFX_API CubeImage {
    int size = 0;
    std::array<std::vector<glm::vec3>, 6> faces;

    static CubeImage filled(int size, glm::vec3 radiance);
    glm::vec3& texel(int face, int s, int t) { return faces[std::size_t(face)][std::size_t(t) * size + s]; }
    const glm::vec3& texel(int face, int s, int t) const {
        return faces[std::size_t(face)][std::size_t(t) * size + s];
    }
    /// Bilinear within the face the direction hits (edges clamp to the face).
    glm::vec3 sample(glm::vec3 direction) const;
    /// Half the size, each texel the mean of four (size must be even).
    CubeImage downsampled() const;
};

/// Where a direction meets the cube: face and (s, t) in [0, 1] (OpenGL 4.6 §8.13, table 8.19).
struct CubeCoord {
    int face;
    glm::vec2 st;
};
SGFX_API CubeCoord cubeCoord(glm::vec3 direction);
/// The (unnormalised) direction through (s, t) of a face: the inverse of cubeCoord.
SGFX_API glm::vec3 cubeDirection(int face, glm::vec2 st);
/// Solid angle of texel (s, t) of a size² face (exact: the area formula of the projected square).
SGFX_API float texelSolidAngle(int size, int s, int t);

/// A latitude-longitude image (rows top to bottom, linear RGB) as a cube: Z is up, the top row
/// looks straight up, the centre column looks along +X and +Y is a quarter of the width to the
/// left of it (the view from inside, as panoramas are made).
SGFX_API CubeImage cubeFromEquirect(const std::vector<glm::vec3>& pixels, int width, int height, int size);
/// The (u, v) in [0, 1] of the latitude-longitude image that a direction looks at.
SGFX_API glm::vec2 equirectCoord(glm::vec3 direction);

/// Nine RGB coefficients of order-2 spherical harmonics (bands 0..2).
using Sh9 = std::array<glm::vec3, 9>;
/// The real SH basis y_i(d) for a unit direction (Ramamoorthi and Hanrahan 2001, eq. 3).
SGFX_API std::array<float, 9> shBasis(glm::vec3 d);
/// The cosine-convolved projection of the radiance, scaled by 1/π: evaluated at a normal N it is
/// irradiance(N)/π, the light a white Lambert surface facing N reflects (the convention of sgfx's
/// light colours). Coefficients are premultiplied by Â_l (π, 2π/3, π/4; ibid., eq. 8) / π.
SGFX_API Sh9 irradianceSh(const CubeImage& radiance);
SGFX_API glm::vec3 evalSh(const Sh9& sh, glm::vec3 normal);

/// Perceptual roughness of the prefiltered mip `level` of `levels` (linear in the mip index).
inline float levelRoughness(int level, int levels) {
    return levels > 1 ? float(level) / float(levels - 1) : 0.0f;
}
/// The specular mip chain: level 0 is the radiance itself; level k is the radiance convolved
/// with the GGX lobe of roughness levelRoughness(k) around N = V = R (Karis 2013's split-sum
/// assumption), importance-sampled with `samples` directions per texel and filtered importance
/// sampling (Křivánek and Colbert 2008: each sample reads the source mip whose texel matches
/// the sample's solid angle). Level k is size >> k; levels stop at 4 × 4.
SGFX_API std::vector<CubeImage> prefilterSpecular(const CubeImage& radiance, int samples = 128);

/// Karis 2013's scale and bias (A, B) of F0 for the lobe of brdf_metallic_roughness.glsl (GGX,
/// height-correlated Smith, Schlick): ∫ f·cosθ dω = F0·A + B for a white light from everywhere.
SGFX_API glm::vec2 brdfScaleBias(float NdotV, float roughness, int samples = 512);
/// The table the shader reads: size² (A, B) pairs, row i for roughness (i + 0.5)/size, column j
/// for N·V = (j + 0.5)/size.
SGFX_API std::vector<glm::vec2> brdfTable(int size = 32, int samples = 512);

/// The i-th of n points of the Hammersley set in [0, 1)².
SGFX_API glm::vec2 hammersley(std::uint32_t i, std::uint32_t n);

/// Blinn-Phong's exponent as a GGX perceptual roughness of the same lobe width (α = √(2/(n+2)),
/// Walter et al. 2007, §5.2), so Blinn-Phong materials read the same specular mip chain.
inline float roughnessFromShininess(float shininess) {
    return glm::sqrt(glm::sqrt(2.0f / (glm::max(shininess, 0.0f) + 2.0f)));
}

} // namespace sgfx::env

#pragma once
/// @file
/// Image-based light: an environment (a panorama, a cube map, a uniform colour) lights every
/// material below the node, as glTF's reference viewers light their content. Prefiltered once
/// on the CPU by the split sum (Karis 2013) and order-2 spherical harmonics (EnvironmentMath.h).
/// See docs/effects/environment.md.
#include "sgfx/Export.h"
#include <sgfx/nodes/environment/EnvironmentMath.h>

#include <sgfx/Effect.h>
#include <sgfx/Image.h>

#include <filesystem>
#include <memory>

namespace sgfx {

class SkyNode;

/// Radiance around the scene and what the shaders read of it: the specular mip chain (GGX
/// prefiltered) and the diffuse irradiance (spherical harmonics). Immutable once made, so one
/// environment may light several nodes and viewers.
class SGFX_API Environment {
public:
    /// Cube size the panoramas are resampled to; a power of two ≥ 8.
    static constexpr int kDefaultSize = 64;

    /// The same radiance from every direction (the white furnace when 1).
    static std::shared_ptr<const Environment> uniform(glm::vec3 radiance, int size = 8);
    /// A cube map of linear radiance. Throws std::invalid_argument for a size that is not a
    /// power of two ≥ 8, missing texels, or NaN, infinite or negative radiance (naming the face
    /// and texel).
    static std::shared_ptr<const Environment> fromCube(env::CubeImage radiance);
    /// A latitude-longitude panorama of linear radiance (env::cubeFromEquirect's orientation:
    /// Z up, the centre column along +X).
    static std::shared_ptr<const Environment> fromEquirect(const FloatImage& panorama,
                                                           int size = kDefaultSize);
    /// A panorama file: Radiance `.hdr` (linear) or an 8-bit image (PNG, JPEG: sRGB decoded),
    /// twice as wide as high; a 6:1 strip is read as cube faces in OpenGL's order. Throws
    /// std::runtime_error naming the file and the reason.
    static std::shared_ptr<const Environment> load(const std::filesystem::path& file,
                                                   int size = kDefaultSize);

    const env::CubeImage& radiance() const { return specular_.front(); }
    /// Level k: the radiance convolved with the GGX lobe of roughness env::levelRoughness(k).
    const std::vector<env::CubeImage>& specular() const { return specular_; }
    const env::Sh9& irradiance() const { return irradiance_; }

    explicit Environment(env::CubeImage radiance);

private:
    std::vector<env::CubeImage> specular_;
    env::Sh9 irradiance_{};
};

/// Gives every material below it image-based light: diffuse from the irradiance, specular from
/// the prefiltered chain and the split-sum table, for metallic-roughness and Blinn-Phong alike
/// (Blinn-Phong's shininess maps to a GGX roughness of the same lobe width). Ambient occlusion
/// and glTF occlusion maps darken it. Foreign shaders opt in by declaring and calling
/// sgfx_environmentDiffuse(N) and sgfx_environmentSpecular(N, V, roughness, F0) under
/// `#ifdef SGFX_ENVIRONMENT` (docs/effects/environment.md lists the prototypes).
class SGFX_API EnvironmentLightNode : public EffectNode {
public:
    static std::shared_ptr<EnvironmentLightNode> create(std::shared_ptr<const Environment> environment,
                                                        float intensity = 1.0f);
    /// Lit by the sky (followSky).
    static std::shared_ptr<EnvironmentLightNode> create(std::shared_ptr<const SkyNode> sky,
                                                        float intensity = 1.0f);
    EnvironmentLightNode();
    ~EnvironmentLightNode() override;

    /// Lights with `environment` from now on, and stops following a sky. Throws
    /// std::invalid_argument for null and keeps the old environment.
    void setEnvironment(std::shared_ptr<const Environment> environment);
    /// The environment that lights the subtree: the sky's once rendered when following one.
    std::shared_ptr<const Environment> environment() const;
    /// The environment becomes the sky's (SkyNode::renderEnvironment: the sky without the sun's
    /// disc, `size`² faces), rendered again in compile() whenever the sky's parameters change (the
    /// sun moves). Null stops following and keeps the last environment. Throws
    /// std::invalid_argument for a size that is not a power of two from 8 to 512.
    void followSky(std::shared_ptr<const SkyNode> sky, int size = 32);
    /// Scales the environment's radiance; throws std::invalid_argument for NaN or negative values
    /// and keeps the old one.
    void setIntensity(float intensity);
    float intensity() const { return intensity_; }

    std::string_view kind() const override { return "environment"; }
    const ShaderSnippet& snippet() const override;
    void compile(Renderer&) const override;
    void applyUniforms(gl::Program& program, const DrawContext&) const override;
    unsigned texture(std::string_view resource) const override;
    void releaseGLObjects() override;

private:
    struct Gpu;
    std::shared_ptr<const Environment> environment_;
    std::shared_ptr<const SkyNode> sky_;
    int skySize_ = 32;
    float intensity_ = 1.0f;
    std::unique_ptr<Gpu> gpu_;
};

} // namespace sgfx

#pragma once
#include "sgfx/Export.h"
#include "sgfx/Texture.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>

namespace sgfx {

/// How the built-in material lights a surface. Both have the same hook points, so every effect
/// applies to either.
enum class ShadingModel : std::uint8_t {
    /// colour = emissive + ambientLight*ambient + sum_l light_l*(diffuse*max(N.L,0) +
    /// specular*max(N.H,0)^shininess)
    BlinnPhong,
    /// glTF 2.0's metallic-roughness model (spec appendix B): Lambert diffuse of
    /// mix(base, 0, metallic), GGX distribution, height-correlated Smith visibility, Schlick
    /// Fresnel with F0 = mix(0.04, base, metallic). Uses diffuse (base colour and opacity),
    /// metallic, roughness and emissive; ambient, specular and shininess are ignored. The glTF
    /// extensions KHR_materials_clearcoat and KHR_materials_specular refine it (fields below).
    MetallicRoughness,
    /// KHR_materials_unlit: colour = diffuse × base colour map × vertex colour; no light, no
    /// ambient, no emission. Effects at the colour hook (fog, ...) still apply.
    Unlit,
};

/// The textures a material may carry, indexing Material::mappings (and, inside the renderer, the
/// texture unit each is bound to).
enum class MaterialMap : std::uint8_t {
    BaseColor,
    Alpha,
    Normal,
    MetallicRoughness,
    Occlusion,
    Emissive,
    Clearcoat,          ///< KHR_materials_clearcoat: clearcoatTexture
    ClearcoatRoughness, ///< clearcoatRoughnessTexture
    ClearcoatNormal,    ///< clearcoatNormalTexture
    Specular,           ///< KHR_materials_specular: specularTexture
    SpecularColor,      ///< specularColorTexture
    Transmission,       ///< KHR_materials_transmission: transmissionTexture
    Thickness,          ///< KHR_materials_volume: thicknessTexture
};
inline constexpr std::size_t kMaterialMapCount = 13;

/// Which texture coordinates a map reads and how they are transformed first
/// (KHR_texture_transform: uv' = T(offset) * R(rotation) * S(scale) * uv).
struct SGFX_API TextureMapping {
    int texCoord = 0; ///< 0: Geometry::texcoords, 1: Geometry::texcoords1
    glm::vec2 offset{0.0f};
    float rotation = 0.0f; ///< radians; positive turns the texture counter-clockwise in uv space
    glm::vec2 scale{1.0f};

    glm::mat3 matrix() const;
    bool isIdentity() const {
        return texCoord == 0 && offset == glm::vec2(0.0f) && rotation == 0.0f && scale == glm::vec2(1.0f);
    }
};

/// The built-in material. Colours are linear RGB.
class SGFX_API Material {
public:
    static std::shared_ptr<Material> create() { return std::make_shared<Material>(); }

    ShadingModel model = ShadingModel::BlinnPhong;

    glm::vec3 ambient{0.2f};
    glm::vec4 diffuse{0.8f, 0.8f, 0.8f, 1.0f}; ///< base colour; alpha = opacity
    glm::vec3 specular{0.0f};
    float shininess = 32.0f;
    glm::vec3 emissive{0.0f};
    /// MetallicRoughness only: both in [0, 1].
    float metallic = 0.0f;
    float roughness = 0.5f;

    std::shared_ptr<Texture> baseColorTexture;         ///< multiplies ambient and diffuse (sRGB)
    std::shared_ptr<Texture> alphaTexture;             ///< red channel multiplies opacity (linear)
    std::shared_ptr<Texture> normalTexture;            ///< tangent-space normal map (linear)
    std::shared_ptr<Texture> metallicRoughnessTexture; ///< G scales roughness, B metallic (linear)
    std::shared_ptr<Texture> occlusionTexture;         ///< R darkens ambient light only (linear)
    std::shared_ptr<Texture> emissiveTexture;          ///< multiplies emissive (sRGB)
    float normalScale = 1.0f;       ///< scales the normal map's x and y (glTF normalTexture.scale)
    float occlusionStrength = 1.0f; ///< 0: no occlusion, 1: the texture's full value

    /// KHR_materials_clearcoat (MetallicRoughness only): a GGX layer with F0 = 0.04 over the
    /// surface, which it darkens by 1 - clearcoat·Fresnel(N_c·V). 0 turns the layer off.
    float clearcoat = 0.0f;                             ///< [0, 1]
    float clearcoatRoughness = 0.0f;                    ///< [0, 1], perceptual (α = roughness²)
    std::shared_ptr<Texture> clearcoatTexture;          ///< R scales clearcoat (linear)
    std::shared_ptr<Texture> clearcoatRoughnessTexture; ///< G scales clearcoatRoughness (linear)
    std::shared_ptr<Texture> clearcoatNormalTexture;    ///< the layer's own normal map (linear)
    float clearcoatNormalScale = 1.0f;                  ///< like normalScale, for the layer

    /// KHR_materials_specular (MetallicRoughness only): the dielectric part's
    /// F0 = min(0.04·specularColorFactor, 1)·specularFactor and F90 = specularFactor.
    /// Not Blinn-Phong's `specular` colour.
    float specularFactor = 1.0f;                   ///< [0, 1]; 0: no highlight on a dielectric
    glm::vec3 specularColorFactor{1.0f};           ///< finite, >= 0 (may exceed 1)
    std::shared_ptr<Texture> specularTexture;      ///< A scales specularFactor (linear)
    std::shared_ptr<Texture> specularColorTexture; ///< RGB scales specularColorFactor (sRGB)

    /// KHR_materials_ior (MetallicRoughness only): the dielectric's F0 = ((ior - 1)/(ior + 1))²
    /// (0.04 at the default 1.5) and, with transmission, how far light bends going in. 1 or
    /// more, or exactly 0 (F0 = 1, as the extension allows).
    float ior = 1.5f;
    /// KHR_materials_transmission (MetallicRoughness only): the fraction of the diffuse part that
    /// lets the scene behind through (thin glass, a canopy) instead of scattering light. The
    /// renderer draws such surfaces in the transmissive stage (docs/materials.md): after the opaque
    /// items and a copy of them, which they sample along the refracted ray, blurred by roughness.
    float transmission = 0.0f;                    ///< [0, 1]; 0: opaque as usual
    std::shared_ptr<Texture> transmissionTexture; ///< R scales transmission (linear)
    /// KHR_materials_volume: the thickness of the medium under the surface, in the mesh's own
    /// units (the model matrix scales it); 0 is a thin wall (no refraction offset, no absorption).
    float thickness = 0.0f;                    ///< >= 0
    std::shared_ptr<Texture> thicknessTexture; ///< G scales thickness (linear)
    /// The colour white light has after travelling attenuationDistance through the medium
    /// (Beer–Lambert: T = attenuationColor^(d / attenuationDistance)).
    glm::vec3 attenuationColor{1.0f};                                   ///< each in (0, 1]
    float attenuationDistance = std::numeric_limits<float>::infinity(); ///< > 0; infinity: clear
    std::array<TextureMapping, kMaterialMapCount> mappings{};
    TextureMapping& mapping(MaterialMap m) { return mappings[std::size_t(m)]; }
    const TextureMapping& mapping(MaterialMap m) const { return mappings[std::size_t(m)]; }

    /// When set, fragments whose opacity is below the cutoff are discarded (alpha mask).
    std::optional<float> alphaCutoff;

    /// Throws std::invalid_argument naming the field for NaN, negative or out-of-range values.
    void validate() const;
};

} // namespace sgfx

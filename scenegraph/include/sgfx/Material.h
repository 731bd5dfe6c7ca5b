#pragma once
#include "sgfx/Texture.h"

#include <glm/glm.hpp>

#include <memory>
#include <optional>

namespace sgfx {

// The built-in Blinn-Phong material. Colours are linear RGB.
// colour = emissive + ambientLight*ambient + sum_l light_l*(diffuse*max(N.L,0) +
// specular*max(N.H,0)^shininess)
class Material {
public:
    static std::shared_ptr<Material> create() { return std::make_shared<Material>(); }

    glm::vec3 ambient{0.2f};
    glm::vec4 diffuse{0.8f, 0.8f, 0.8f, 1.0f}; // alpha = opacity
    glm::vec3 specular{0.0f};
    float shininess = 32.0f;
    glm::vec3 emissive{0.0f};

    std::shared_ptr<Texture> baseColorTexture; // multiplies ambient and diffuse (sRGB)
    std::shared_ptr<Texture> alphaTexture;     // red channel multiplies opacity (linear)
    std::shared_ptr<Texture> normalTexture;    // tangent-space normal map (linear)
    // When set, fragments whose opacity is below the cutoff are discarded (alpha mask).
    std::optional<float> alphaCutoff;

    // Throws std::invalid_argument for NaN/negative values; used by setters in tools and tests.
    void validate() const;
};

} // namespace sgfx

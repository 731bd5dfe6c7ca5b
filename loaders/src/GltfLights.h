#pragma once
// KHR_lights_punctual for the glTF loader: the file's lights and which nodes carry them, read
// from its JSON text and checked (tinygltf 2.7 checks none of it, and refuses a spot light
// without `spot` without naming it).
#include <sgfx/Camera.h>

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace sgfx::gltf {

struct PunctualLights {
    std::vector<std::shared_ptr<Light>> lights;   ///< one node per glTF light, shared by its nodes
    std::map<std::size_t, std::size_t> nodeLight; ///< node index → index into `lights`
    /// The light node `nodes[node]` carries, or null.
    std::shared_ptr<Light> of(std::size_t node) const {
        const auto it = nodeLight.find(node);
        return it == nodeLight.end() ? nullptr : lights[it->second];
    }
};

/// Reads and checks the lights of a glTF JSON document; throws LoadError naming `path` and the
/// element. glTF units become sgfx's: E lux → intensity E / π, I candela → I / π with
/// LightFalloff::InverseSquare (sgfx light colours are irradiance over π).
PunctualLights readPunctualLights(const unsigned char* text, std::size_t size, const std::string& path);

} // namespace sgfx::gltf

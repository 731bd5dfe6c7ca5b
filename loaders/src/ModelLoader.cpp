#include "sgfx/ModelLoader.h"

#include <sgfx/MeshLoader.h>

#include <algorithm>
#include <cctype>

namespace sgfx {

std::shared_ptr<Group> loadModel(const std::filesystem::path& file, const GltfOptions& gltf) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".gltf" || ext == ".glb") return loadGltf(file, gltf);
    if (ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl") return loadMeshModel(file);
    throw LoadError("sgfx: model '" + file.string() + "': '" + ext +
                    "' is not one of the model formats: .gltf, .glb, .obj, .off, .ply, .stl");
}

} // namespace sgfx

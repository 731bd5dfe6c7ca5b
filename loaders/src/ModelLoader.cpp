#include "sgfx/ModelLoader.h"

#include <sgfx/MeshLoader.h>
#include <sgfx/MeshOptimize.h>
#include <sgfx/OsgLoader.h>

#include <algorithm>
#include <cctype>

namespace sgfx {

std::shared_ptr<Group> loadModel(const std::filesystem::path& file, const GltfOptions& gltf) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".gltf" || ext == ".glb") return loadGltf(file, gltf);
    if (ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl") {
        auto root = loadMeshModel(file);
        if (gltf.optimizeOrder) optimizeMeshes(*root);
        if (gltf.autoLod.enabled) addAutoLods(*root, gltf.autoLod);
        return root;
    }
    static const char* const osgFormats[] = {".osg", ".osgt", ".osgb", ".osgx", ".ive", ".flt"};
    const auto& osg = osgExtensions();
    if (std::find(osg.begin(), osg.end(), ext) != osg.end() ||
        std::find(std::begin(osgFormats), std::end(osgFormats), ext) != std::end(osgFormats))
        return loadOsg(file); // without the bridge: a LoadError saying how to get it
    std::string formats = ".gltf, .glb, .obj, .off, .ply, .stl";
    for (const auto& e : osg)
        formats += ", " + e;
    throw LoadError("sgfx: model '" + file.string() + "': '" + ext +
                    "' is not one of the model formats: " + formats);
}

} // namespace sgfx

#pragma once
/// @file
/// glTF 2.0 out of the scene graph, the counterpart of loadGltf: what it writes loads back
/// through loadGltf with the same triangles, positions, normals, texcoords, colours and
/// material colours.
#include "sgfx/Export.h"
#include <sgfx/Node.h>

#include <filesystem>

namespace sgfx {

/// Choices for writeGltf.
struct SGFX_API GltfWriteOptions {
    /// The scene is sgfx's Z-up: rotate it into glTF's Y-up, which loadGltf's default undoes.
    bool zUp = true;
};

/// What writeGltf wrote.
struct SGFX_API GltfWriteResult {
    std::size_t meshes = 0, vertices = 0, triangles = 0, materials = 0;
};

/// Writes every Geometry below `root` (node masks honoured, every LOD level included) as one
/// glTF mesh each, world transforms applied to the vertices, with NORMAL, TEXCOORD_0, TANGENT and
/// COLOR_0 when present, and one glTF material per distinct sgfx::Material and blending:
/// baseColorFactor = diffuse, emissiveFactor = emissive (KHR_materials_emissive_strength above 1),
/// alphaMode MASK with an alphaCutoff, BLEND for blended state or opacity below 1, else OPAQUE.
/// Textures are not written. `.glb` gives a binary file, `.gltf` JSON with the buffer embedded as
/// base64. Throws std::invalid_argument for another extension or an invalid geometry
/// (Geometry::validate), std::runtime_error naming the path when it cannot be written.
SGFX_API GltfWriteResult writeGltf(Node& root, const std::filesystem::path& path,
                                   const GltfWriteOptions& options = {});

} // namespace sgfx

#pragma once
#include "sgfx/Export.h"
#include <sgfx/Node.h>

#include <filesystem>

namespace sgfx {

/// What writeObj wrote.
struct SGFX_API ObjWriteResult {
    std::size_t objects = 0, vertices = 0, triangles = 0, textures = 0;
};

/// Writes every triangle geometry below `root` (world transforms applied, node masks honoured)
/// to a Wavefront OBJ with one `o` group per geometry and an MTL with their colours. A material's
/// base colour and alpha maps are written as one RGBA PNG beside the file (map_Kd, named
/// STEM_MATERIAL.png), with the geometry's texture coordinates. Of a LOD only the most detailed
/// level is written.
/// Throws std::runtime_error naming the path when it cannot be written.
SGFX_API ObjWriteResult writeObj(Node& root, const std::filesystem::path& path);

} // namespace sgfx

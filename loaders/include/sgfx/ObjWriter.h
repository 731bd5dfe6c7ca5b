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
/// to a Wavefront OBJ with one `o` group per geometry and an MTL with their colours (Ka, Kd, Ks, Ns,
/// d, and Ke when not black: linear values, 6 significant digits). A geometry's vertex colours are
/// written as `v x y z r g b`, clamped to [0, 1] and sRGB-encoded to 6 decimals (their alpha is
/// lost), so loadMeshModel reads them back within 2e-6. A material's
/// base colour and alpha maps are written as one RGBA PNG beside the file (map_Kd, named
/// STEM_MATERIAL.png), with the geometry's texture coordinates. Of a LOD only the most detailed
/// level is written.
/// Throws std::runtime_error naming the path when it cannot be written.
SGFX_API ObjWriteResult writeObj(Node& root, const std::filesystem::path& path);

} // namespace sgfx

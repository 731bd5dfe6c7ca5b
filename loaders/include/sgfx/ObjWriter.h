#pragma once
#include <sgfx/Node.h>

#include <filesystem>

namespace sgfx {

struct ObjWriteResult {
    std::size_t objects = 0, vertices = 0, triangles = 0;
};

// Writes every triangle geometry below `root` (world transforms applied, node masks honoured)
// to a Wavefront OBJ with one `o` group per geometry and an MTL with their diffuse colours.
// Throws std::runtime_error naming the path when it cannot be written.
ObjWriteResult writeObj(Node& root, const std::filesystem::path& path);

} // namespace sgfx

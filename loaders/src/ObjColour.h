#pragma once
// OBJ vertex colours, `v x y z r g b` (MeshLab, CloudCompare, OpenSceneGraph's tools write them):
// the file holds display values, sRGB-encoded, in 0..1 (or 0..255, taken so when any component of
// the file is above 1); Geometry::colors are linear (glTF COLOR_0's convention), so readers decode
// and writers encode. Shared by the OBJ readers (loadMeshModel, loadMesh) and writers (writeObj,
// writeMesh). Internal to sgfx_loaders.
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <vector>

namespace sgfx::obj {

/// IEC 61966-2-1 sRGB decoding of one component in [0, 1].
inline float srgbToLinear(float s) {
    const double v = s;
    return float(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
}

/// IEC 61966-2-1 sRGB encoding; the value is clamped to [0, 1] first (OBJ has no HDR colours).
inline float linearToSrgb(float c) {
    const double v = std::clamp(double(c), 0.0, 1.0);
    return float(v <= 0.0031308 ? v * 12.92 : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055);
}

/// Writes `v x y z` (6 significant digits), or `v x y z r g b` with the linear colour's RGB
/// sRGB-encoded to 6 decimals when `linear` is not null (its alpha is not written: OBJ has none).
inline void writeVertex(std::FILE* f, const glm::vec3& p, const glm::vec4* linear) {
    std::fprintf(f, "v %.6g %.6g %.6g", double(p.x), double(p.y), double(p.z));
    if (linear)
        std::fprintf(f, " %.6f %.6f %.6f", double(linearToSrgb(linear->r)), double(linearToSrgb(linear->g)),
                     double(linearToSrgb(linear->b)));
    std::fprintf(f, "\n");
}

/// The vertex colours of an OBJ file, linear with alpha 1, one per `v` line in file order; a
/// vertex without a colour in a file where others have one is white. Empty when no `v` line has
/// a colour. Throws LoadError naming file:line for a bad `v` line, as loadMeshModel does.
std::vector<glm::vec4> readVertexColours(const std::filesystem::path& file);

} // namespace sgfx::obj

#pragma once
/// @file
/// Gaussian splats as data: what a 3D Gaussian splatting `.ply` (Kerbl et al. 2023) holds, with
/// the activations applied (opacity through the sigmoid, scales through exp, unit quaternions),
/// the reader, a writer and a generator for tests, demos and benchmarks.
#include "sgfx/Export.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <vector>

namespace sgfx {

struct SGFX_API SplatCloud {
    int shDegree = 0;                 ///< 0..3
    std::vector<glm::vec3> positions; ///< metres, the node's frame
    std::vector<glm::vec3> scales;    ///< standard deviations along the rotated axes (metres)
    std::vector<glm::vec4> rotations; ///< unit quaternions (w, x, y, z)
    std::vector<float> opacities;     ///< [0, 1]
    /// (shDegree + 1)² RGB triples per splat, coefficient-major (all of splat i's coefficient 0,
    /// then 1, ...); coefficient 0 is f_dc.
    std::vector<glm::vec3> sh;

    std::size_t size() const { return positions.size(); }
    int coefficients() const { return (shDegree + 1) * (shDegree + 1); }
    /// Throws std::invalid_argument naming the array or the splat: sizes that disagree, a degree
    /// outside 0..3, non-finite values, scales ≤ 0, opacities outside [0, 1], zero quaternions.
    void validate() const;

    /// `count` random splats in a ball of radius `radius` (deterministic for a seed): sizes
    /// around `size` metres, random rotations and colours, SH of `degree`.
    static SplatCloud random(std::size_t count, std::uint32_t seed = 1, float radius = 1.0f,
                             float size = 0.02f, int degree = 1);
};

namespace splat {

/// Whether the file is a PLY whose vertex element has the splat properties (f_dc_0, opacity,
/// scale_0, rot_0); false for other PLY meshes and unreadable files.
SGFX_API bool isSplatPly(const std::filesystem::path& file);

/// Reads a 3D Gaussian splatting PLY (binary_little_endian or ascii 1.0; vertex properties x y z,
/// optional nx ny nz, f_dc_0..2, f_rest_0..3(K−1) channel-major, opacity (a logit), scale_0..2
/// (logs), rot_0..3 (w x y z)). Throws LoadError naming the file and the property, the element
/// count or the splat: a missing property or one that is not float, an f_rest count that is not
/// 0, 9, 24 or 45, a declared count the file is too short for (checked before allocating), a
/// truncated body, non-finite values.
SGFX_API SplatCloud loadPly(const std::filesystem::path& file);

/// Writes the cloud as a binary PLY that loadPly reads back (activations inverted).
SGFX_API void savePly(const SplatCloud& cloud, const std::filesystem::path& file);

} // namespace splat
} // namespace sgfx

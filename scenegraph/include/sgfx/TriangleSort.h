#pragma once
#include "sgfx/Export.h"
#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace sgfx {

class Geometry;

/// Back-to-front order of one mesh's triangles for one view (TransparencyDetails::sortTriangles):
/// a self-overlapping transparent mesh (a canopy, a terrain overlay, a cluster of tree cards)
/// blends correctly only if its far triangles are drawn first. The key is each centroid's
/// view-space depth, which depends only on the view axis in the mesh's own frame, so the order
/// is exact until that axis turns; it is re-sorted when it has turned by more than a threshold.
class SGFX_API TriangleDepthSort {
public:
    /// Triangle list of any triangle mode (strips and fans unrolled, non-indexed numbered);
    /// empty for points and lines. The geometry must be valid (Geometry::validate()).
    explicit TriangleDepthSort(const Geometry& geometry);

    /// Re-sorts when the view axis in model space has turned by more than `thresholdDegrees`
    /// since the last sort (always the first time). Returns whether it re-sorted.
    bool update(const glm::mat4& modelView, float thresholdDegrees);

    /// Sorted triangle list, far to near, three indices per triangle.
    std::span<const std::uint32_t> indices() const { return sorted_; }
    std::size_t triangleCount() const { return centroids_.size(); }
    std::uint64_t sorts() const { return sorts_; }

private:
    std::vector<std::uint32_t> triangles_; ///< three per triangle, original order
    std::vector<glm::vec3> centroids_;
    std::vector<std::uint32_t> sorted_;
    std::vector<std::uint64_t> keys_, scratch_; ///< (depth key << 32) | triangle
    glm::vec3 axis_{0.0f};
    std::uint64_t sorts_ = 0;
};

} // namespace sgfx

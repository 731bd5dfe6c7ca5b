#pragma once
/// @file
/// A bounding-volume hierarchy over a Geometry's triangles, for scene queries (Intersection.h).
#include "sgfx/Export.h"
#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace sgfx {

class Geometry;

/// An axis-aligned box in double precision (query frames, the subtree index).
struct SGFX_API QueryBox {
    glm::dvec3 min{std::numeric_limits<double>::max()};
    glm::dvec3 max{-std::numeric_limits<double>::max()};
    bool valid() const { return min.x <= max.x; }
    void expandBy(const glm::dvec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void expandBy(const QueryBox& b) {
        min = glm::min(min, b.min);
        max = glm::max(max, b.max);
    }
    glm::dvec3 center() const { return (min + max) * 0.5; }
    /// Surface area (the SAH's cost of entering the box); 0 for an empty box.
    double area() const;
};

/// A binary BVH built with the surface-area heuristic (binned, 16 bins per axis, leaves of at
/// most 4 items): over triangles (TriangleBvh) and over the items of a subtree index.
/// Node i's children are i + 1 and `second`; leaves hold items [first, first + count).
struct SGFX_API BvhNodes {
    struct Node {
        glm::vec3 min, max;      ///< float boxes, rounded outwards so they hold the exact item boxes
        std::uint32_t first = 0; ///< leaf: first item; inner: index of the second child
        std::uint32_t count = 0; ///< items in a leaf; 0 for an inner node
    };
    std::vector<Node> nodes;
    std::vector<std::uint32_t> order; ///< item index for each leaf slot (TriangleBvh: empty, see there)

    /// Builds over `boxes` (one per item; invalid boxes are left out).
    static BvhNodes build(const std::vector<QueryBox>& boxes);
    std::size_t memoryBytes() const {
        return nodes.size() * sizeof(Node) + order.size() * sizeof(std::uint32_t);
    }
};

/// The triangles of one Geometry (Triangles, TriangleStrip and TriangleFan; points and lines
/// have no area and are left out) in a BVH, in the geometry's own frame. Built lazily by
/// Geometry::triangleBvh() and rebuilt after Geometry::dirty().
class SGFX_API TriangleBvh {
public:
    /// Throws std::invalid_argument naming the geometry when its arrays are inconsistent
    /// (Geometry::validate). Degenerate triangles (zero area) are kept out.
    explicit TriangleBvh(const Geometry& geometry);

    /// A triangle's vertex indices and its number in the geometry's draw order. Stored in leaf
    /// order: a leaf's [first, first + count) indexes triangles() directly.
    struct Triangle {
        std::array<std::uint32_t, 3> v;
        std::uint32_t primitive;
    };
    const std::vector<Triangle>& triangles() const { return triangles_; }
    /// The three corners of triangles()[i] at [3i, 3i + 3): a copy of the positions in leaf
    /// order, so a leaf's triangles are read from one place instead of gathered from the vertex
    /// array (queries over large scenes are bound by cache misses; this is 36 of the bytes per
    /// triangle).
    const std::vector<glm::vec3>& corners() const { return corners_; }
    const BvhNodes& bvh() const { return bvh_; }
    /// Bytes held (nodes, order, triangle list): with the Geometry's own arrays the whole cost.
    std::size_t memoryBytes() const;
    std::uint64_t revision() const { return revision_; } ///< the Geometry::revision() it was built from

private:
    std::vector<Triangle> triangles_;
    std::vector<glm::vec3> corners_;
    BvhNodes bvh_;
    std::uint64_t revision_ = 0;
};

/// Vertex triples of every triangle of `geometry` in draw order (strips and fans unrolled with
/// the winding of the first triangle); empty for points and lines.
SGFX_API std::vector<std::array<std::uint32_t, 3>> triangleIndices(const Geometry& geometry);

} // namespace sgfx

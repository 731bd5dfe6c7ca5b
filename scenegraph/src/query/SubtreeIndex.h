#pragma once
// The query index of a Group: a BVH over the geometries (one entry per instance and per node
// path) and the view-dependent subtrees (LODs, billboards) below it, in the group's child frame.
#include "sgfx/Group.h"
#include "sgfx/TriangleBvh.h"

#include <memory>
#include <vector>

namespace sgfx {

class Geometry;

struct SubtreeIndex {
    struct Item {
        Node* node = nullptr;         ///< the geometry, or a LOD or billboard walked at query time
        Geometry* geometry = nullptr; ///< null for a walked subtree
        std::uint32_t instance = 0;
        glm::dmat4 toGroup{1.0};   ///< geometry (instance included) or the subtree's parent frame → group
        glm::dmat4 fromGroup{1.0}; ///< its inverse
        std::vector<Node*> path;   ///< below the group, down to `node`
        std::shared_ptr<const TriangleBvh> bvh; ///< geometry items
    };
    std::vector<Item> items;
    BvhNodes bvh;
    std::uint64_t boundChanges = 0; ///< the group's Node::boundChanges() when built

    /// Builds the index over `group`'s children (Group::subtreeIndex caches it).
    static std::shared_ptr<const SubtreeIndex> build(const Group& group);
    std::size_t memoryBytes() const;
};

} // namespace sgfx

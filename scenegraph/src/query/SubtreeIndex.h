#pragma once
// The query index of a Group: a BVH over the geometries (one entry per instance and per node
// path) and the view-dependent subtrees (LODs, billboards) below it, in the group's child frame.
// A large child group (kNestedItems or more items below) is one entry holding its own index, so a
// change below it (a vehicle driving) rebuilds that index and the small ones above, not the
// whole scene's.
#include "sgfx/Group.h"
#include "sgfx/TriangleBvh.h"

#include <memory>
#include <vector>

namespace sgfx {

class Geometry;

struct SubtreeIndex {
    static constexpr std::size_t kNestedItems = 16;
    enum class Kind : std::uint8_t {
        Geometry, ///< triangles: `bvh`
        Walk,     ///< a LOD or billboard, walked by the visitor at query time
        Nested,   ///< a group with its own index: `nested`
    };
    struct Item {
        Kind kind = Kind::Geometry;
        Node* node = nullptr;
        Geometry* geometry = nullptr; ///< Geometry items
        std::uint32_t instance = 0;
        /// To the group's child frame from: the geometry's frame (instance included), a walked
        /// subtree's parent frame, or a nested group's child frame.
        glm::dmat4 toGroup{1.0};
        glm::dmat4 fromGroup{1.0}; ///< its inverse
        QueryBox box;              ///< in the group's child frame: tested before the item is entered
        bool identity = true;      ///< toGroup is the identity: the item is in the group's frame
        std::vector<Node*> path;   ///< below the group, down to `node`
        std::shared_ptr<const TriangleBvh> bvh;     ///< Geometry items
        std::shared_ptr<const SubtreeIndex> nested; ///< Nested items
    };
    std::vector<Item> items;
    BvhNodes bvh;
    std::uint64_t boundChanges = 0; ///< the group's Node::boundChanges() when built

    /// Builds the index over `group`'s children (Group::subtreeIndex caches it).
    static std::shared_ptr<const SubtreeIndex> build(const Group& group);
    std::size_t memoryBytes() const;
};

} // namespace sgfx

#pragma once
#include "sgfx/Export.h"
#include "sgfx/Math.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace sgfx {

class NodeVisitor;
class UpdateVisitor;
class StateSet;
class Group;

using NodeMask = std::uint32_t;

/// Base of the graph. Nodes are shared (std::shared_ptr); a node may have several parents.
/// Parents are tracked as raw back-pointers: a Group clears them when it lets a child go.
class SGFX_API Node : public std::enable_shared_from_this<Node> {
public:
    using UpdateCallback = std::function<void(Node&, UpdateVisitor&)>;

    Node() = default;
    Node(const Node&) = delete;
    Node& operator=(const Node&) = delete;
    virtual ~Node();

    std::string name; ///< for finding nodes and for messages; not unique
    /// Visitors in ActiveChildren mode skip the node when (nodeMask & traversalMask) == 0: 0 hides
    /// it from culling and drawing.
    NodeMask nodeMask = ~NodeMask{0};
    /// Called by the UpdateVisitor once per frame before culling (animation, following a camera).
    UpdateCallback updateCallback;

    /// Calls v.apply with this node's most derived type (double dispatch).
    virtual void accept(NodeVisitor& v);
    /// Visits the children (none for a leaf).
    virtual void traverse(NodeVisitor&) {}

    /// The node's render state (null: all inherited). A StateSet may be shared by many nodes.
    const std::shared_ptr<StateSet>& stateSet() const { return stateSet_; }
    void setStateSet(std::shared_ptr<StateSet> s) { stateSet_ = std::move(s); }
    /// The node's own StateSet, made empty first if it has none.
    StateSet& getOrCreateStateSet();

    /// Bounding sphere in the node's parent frame; recomputed lazily after dirtyBound().
    const BoundingSphere& bound() const {
        if (boundDirty_) updateBound(); // inline: culling asks every node for its bound
        return bound_;
    }
    /// Marks this bound and every ancestor's for recomputation (geometry or matrix changed).
    void dirtyBound();
    /// Counts the times this bound went from clean to dirty: it changes whenever anything below
    /// changes (a matrix, a geometry's data, a child added or removed) after the bound was last
    /// computed. Caches over a subtree (the query index) compare it.
    std::uint64_t boundChanges() const { return boundChanges_; }

    /// OSG's cull-active flag: off, view-frustum culling never rejects this node or any of its
    /// ancestors (an effect whose passes cover the whole view, like fog over the sky, must be
    /// planned even when nothing below it is in view). Its children are still culled.
    void setCullingActive(bool active);
    bool cullingActive() const { return cullingActive_; } ///< see setCullingActive
    /// True when this node or a descendant has culling switched off.
    bool cullingDisabledInSubtree() const {
        bound();
        return !cullingActive_ || cullingDisabledBelow_;
    }

    /// The groups this node is a child of (back-pointers, not owners).
    const std::vector<Group*>& parents() const { return parents_; }

protected:
    /// The bound from scratch, in the parent frame (bound() caches it).
    virtual BoundingSphere computeBound() const { return {}; }
    /// Whether a descendant has culling switched off (cached with the bound).
    virtual bool computeCullingDisabledBelow() const { return false; }

private:
    friend class Group;
    void updateBound() const;
    std::shared_ptr<StateSet> stateSet_;
    std::vector<Group*> parents_;
    mutable BoundingSphere bound_;
    std::uint64_t boundChanges_ = 0;
    mutable bool boundDirty_ = true;
    mutable bool cullingDisabledBelow_ = false; ///< cached with the bound
    bool cullingActive_ = true;
};

using NodePtr = std::shared_ptr<Node>;

} // namespace sgfx

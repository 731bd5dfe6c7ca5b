#pragma once
#include "sgfx/Export.h"
#include "sgfx/Node.h"

#include <cstdint>
#include <vector>

namespace sgfx {

class Node;
class Group;
class Transform;
class LOD;
class PagedLOD;
class Switch;
class Sequence;
class Billboard;
class Geometry;
class Drawable;
class Camera;
class Light;
class EffectNode;

using NodeMask = std::uint32_t;

/// Double dispatch over node types. The default for each type forwards to its base's apply,
/// ending in apply(Node&), which traverses the children.
class SGFX_API NodeVisitor {
public:
    /// Which children traverse() visits: none, all, or those whose nodeMask passes traversalMask.
    enum class Mode { None, AllChildren, ActiveChildren };

    explicit NodeVisitor(Mode m = Mode::AllChildren)
        : mode(m) {}
    virtual ~NodeVisitor() = default;

    /// One overload per node type; override the ones a visitor cares about.
    virtual void apply(Node& node);
    virtual void apply(Group& group);
    virtual void apply(Transform& transform);
    virtual void apply(LOD& lod);             ///< default: all children, like a Group
    virtual void apply(PagedLOD& lod);        ///< default: as a LOD
    virtual void apply(Switch& sw);           ///< default: as a Group (Switch::traverse filters)
    virtual void apply(Sequence& sequence);   ///< default: as a Group (Sequence::traverse filters)
    virtual void apply(Billboard& billboard); ///< default: the children unrotated, like a Group
    virtual void apply(Geometry& geometry);
    virtual void apply(Drawable& drawable);
    virtual void apply(Camera& camera);
    virtual void apply(Light& light);
    virtual void apply(EffectNode& effect);

    /// Inline, like accepts: called for every node of every traversal.
    void traverse(Node& node) {
        if (mode == Mode::None) return;
        nodePath.push_back(&node);
        node.traverse(*this);
        nodePath.pop_back();
    }
    /// A node is visited if (node.nodeMask & traversalMask) != 0 (ActiveChildren mode only).
    bool accepts(const Node& node) const {
        return mode != Mode::ActiveChildren || (node.nodeMask & traversalMask) != 0;
    }

    Mode mode;                             ///< see Mode
    NodeMask traversalMask = ~NodeMask{0}; ///< see accepts()
    /// Nodes from the root to the current one (the current node last).
    std::vector<Node*> nodePath;
};

} // namespace sgfx

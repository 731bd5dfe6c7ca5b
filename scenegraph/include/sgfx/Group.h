#pragma once
#include "sgfx/Export.h"
#include "sgfx/Node.h"

#include <mutex>

namespace sgfx {

struct SubtreeIndex;

/// A node with children, in order (OSG's Group); a child may have several parents.
class SGFX_API Group : public Node {
public:
    static std::shared_ptr<Group> create() { return std::make_shared<Group>(); }
    ~Group() override;

    void accept(NodeVisitor& v) override;
    void traverse(NodeVisitor& v) override;

    /// Throws std::invalid_argument for a null child or one that would close a cycle.
    void addChild(NodePtr child);
    /// As addChild, at `index` (at most numChildren()).
    void insertChild(std::size_t index, NodePtr child);
    /// Removes the first occurrence of `child`; false when it is not a child.
    bool removeChild(const Node* child);
    void removeChildren(); ///< all of them, each parent back-pointer cleared
    /// Puts `child` in place of the child at `index` (checked as addChild).
    void replaceChild(std::size_t index, NodePtr child);

    std::size_t numChildren() const { return children_.size(); }
    const NodePtr& child(std::size_t i) const { return children_.at(i); } ///< throws std::out_of_range
    const std::vector<NodePtr>& children() const { return children_; }

    /// The query index over the geometries below (IntersectionVisitor::useSubtreeIndex), built on
    /// first use and again after boundChanges() moves. Thread-safe while the graph does not change.
    std::shared_ptr<const SubtreeIndex> subtreeIndex() const;

protected:
    BoundingSphere computeBound() const override;
    bool computeCullingDisabledBelow() const override;
    /// Called after a child enters at `index` / leaves from `index`, so subclasses that keep
    /// per-child data (LOD ranges) stay aligned with the children.
    virtual void childInserted(std::size_t /*index*/) {}
    virtual void childRemoved(std::size_t /*index*/) {}

private:
    void checkAcyclic(const Node& child) const;
    std::vector<NodePtr> children_;
    mutable std::mutex queryMutex_; ///< guards queryIndex_
    mutable std::shared_ptr<const SubtreeIndex> queryIndex_;
};

/// Local matrix relative to the parent; world matrices are accumulated during traversal.
class SGFX_API Transform : public Group {
public:
    static std::shared_ptr<Transform> create(const glm::mat4& m = glm::mat4(1.0f)) {
        auto t = std::make_shared<Transform>();
        t->setMatrix(m);
        return t;
    }
    void accept(NodeVisitor& v) override;

    const glm::mat4& matrix() const { return matrix_; }
    /// maxAxisScale(matrix()) and isSimilarity(matrix()), kept with the matrix for culling.
    float maxScale() const { return maxScale_; }
    bool similarity() const { return similarity_; }
    /// Sets the local matrix and dirties the bounds above.
    void setMatrix(const glm::mat4& m);

protected:
    BoundingSphere computeBound() const override;

private:
    glm::mat4 matrix_{1.0f};
    float maxScale_ = 1.0f;
    bool similarity_ = true;
};

} // namespace sgfx

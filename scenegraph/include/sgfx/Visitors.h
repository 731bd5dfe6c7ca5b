#pragma once
#include "sgfx/Export.h"
#include "sgfx/NodeVisitor.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <memory>
#include <vector>

namespace sgfx {

/// Runs update callbacks; carries the frame clock.
class SGFX_API UpdateVisitor : public NodeVisitor {
public:
    UpdateVisitor()
        : NodeVisitor(Mode::ActiveChildren) {}
    void apply(Node& node) override;
    void apply(Drawable& drawable) override;
    void apply(Geometry& geometry) override; ///< notes skinned geometries for updatePoses()
    void apply(Sequence& sequence) override; ///< advances it to simulationTime

    /// Recomputes the joint matrices of the skinned geometries the traversal met, once each, after
    /// every callback has moved its joints (Viewer::update calls it after the traversal).
    void updatePoses();

    double simulationTime = 0.0; ///< seconds
    double deltaTime = 0.0;
    std::uint64_t frameNumber = 0;

private:
    /// Weak: a callback may drop a subtree, or a traversal stop on an exception, before updatePoses.
    std::vector<std::weak_ptr<Node>> skinned_;
};

/// World-space bounds of everything below the visited node (accumulating transforms).
class SGFX_API ComputeBoundsVisitor : public NodeVisitor {
public:
    ComputeBoundsVisitor()
        : NodeVisitor(Mode::ActiveChildren) {}
    void apply(Transform& t) override;
    void apply(Geometry& g) override;
    void apply(Drawable& d) override;

    glm::vec3 min{std::numeric_limits<float>::max()};
    glm::vec3 max{-std::numeric_limits<float>::max()};
    bool valid() const { return min.x <= max.x; }

private:
    glm::mat4 matrix_{1.0f};
};

/// Counts what a traversal reaches: each shared subgraph counts once per parent path.
class SGFX_API StatsVisitor : public NodeVisitor {
public:
    StatsVisitor()
        : NodeVisitor(Mode::ActiveChildren) {}
    void apply(Node& n) override;
    void apply(Geometry& g) override;
    void apply(Drawable& d) override;

    std::size_t nodes = 0;
    std::size_t drawables = 0;
    std::size_t triangles = 0;
    std::size_t vertices = 0;
};

} // namespace sgfx

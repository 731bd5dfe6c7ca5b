#include "sgfx/Visitors.h"

#include "sgfx/Billboard.h"
#include "sgfx/Camera.h"
#include "sgfx/Drawable.h"
#include "sgfx/Effect.h"
#include "sgfx/Geometry.h"
#include "sgfx/Group.h"
#include "sgfx/LOD.h"
#include "sgfx/PagedLOD.h"
#include "sgfx/Sequence.h"
#include "sgfx/Switch.h"

namespace sgfx {

// ---------------------------------------------------------------- NodeVisitor
void NodeVisitor::apply(Node& node) {
    traverse(node);
}
void NodeVisitor::apply(Group& g) {
    apply(static_cast<Node&>(g));
}
void NodeVisitor::apply(Transform& t) {
    apply(static_cast<Group&>(t));
}
void NodeVisitor::apply(LOD& lod) {
    apply(static_cast<Group&>(lod));
}
void NodeVisitor::apply(PagedLOD& lod) {
    apply(static_cast<LOD&>(lod));
}
void NodeVisitor::apply(Switch& s) {
    apply(static_cast<Group&>(s));
}
void NodeVisitor::apply(Sequence& s) {
    apply(static_cast<Group&>(s));
}
void NodeVisitor::apply(Billboard& b) {
    apply(static_cast<Group&>(b));
}
void NodeVisitor::apply(Geometry& g) {
    apply(static_cast<Node&>(g));
}
void NodeVisitor::apply(Drawable& d) {
    apply(static_cast<Node&>(d));
}
void NodeVisitor::apply(Camera& c) {
    apply(static_cast<Group&>(c));
}
void NodeVisitor::apply(Light& l) {
    apply(static_cast<Node&>(l));
}
void NodeVisitor::apply(EffectNode& e) {
    apply(static_cast<Group&>(e));
}

// ---------------------------------------------------------------- UpdateVisitor
void UpdateVisitor::apply(Node& node) {
    nodePath.push_back(&node);
    if (node.updateCallback) node.updateCallback(node, *this);
    nodePath.pop_back();
    traverse(node);
}

void UpdateVisitor::apply(Sequence& s) {
    s.advanceTo(simulationTime); // before its callback and children: they see this frame's child
    apply(static_cast<Node&>(s));
}

void UpdateVisitor::apply(Geometry& g) {
    if (g.skin) skinned_.push_back(g.weak_from_this());
    apply(static_cast<Node&>(g));
}

void UpdateVisitor::updatePoses() {
    std::vector<std::shared_ptr<Node>> live;
    for (const auto& w : skinned_)
        if (auto g = w.lock()) live.push_back(std::move(g));
    skinned_.clear();
    std::sort(live.begin(), live.end());
    live.erase(std::unique(live.begin(), live.end()), live.end()); // shared geometries pose once
    for (const auto& g : live)
        static_cast<Geometry&>(*g).updateSkin();
}

void UpdateVisitor::apply(Drawable& d) {
    d.update(*this);
    apply(static_cast<Node&>(d));
}

// ---------------------------------------------------------------- ComputeBoundsVisitor
void ComputeBoundsVisitor::apply(Transform& t) {
    const glm::mat4 saved = matrix_;
    matrix_ = matrix_ * t.matrix();
    traverse(t);
    matrix_ = saved;
}

void ComputeBoundsVisitor::apply(Drawable& d) {
    const BoundingSphere s = d.worldBound(matrix_);
    if (!s.valid()) return;
    min = glm::min(min, s.center - glm::vec3(s.radius));
    max = glm::max(max, s.center + glm::vec3(s.radius));
}

void ComputeBoundsVisitor::apply(Geometry& g) {
    if (g.posed()) { // the present pose: its bound's box (the arrays hold the bind pose)
        const BoundingSphere s = g.bound();
        if (!s.valid()) return;
        for (int c = 0; c < 8; ++c) {
            const glm::vec3 corner =
                s.center + s.radius * glm::vec3(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1);
            const glm::vec3 w = glm::vec3(matrix_ * glm::vec4(corner, 1.0f));
            min = glm::min(min, w);
            max = glm::max(max, w);
        }
        return;
    }
    for (std::size_t i = 0; i < g.instanceCount(); ++i) {
        const glm::mat4 m = g.instances.empty() ? matrix_ : matrix_ * g.instances[i];
        for (const auto& p : g.positions) {
            const glm::vec3 w = glm::vec3(m * glm::vec4(p, 1.0f));
            min = glm::min(min, w);
            max = glm::max(max, w);
        }
    }
}

// ---------------------------------------------------------------- StatsVisitor
void StatsVisitor::apply(Node& n) {
    ++nodes;
    traverse(n);
}

void StatsVisitor::apply(Drawable& d) {
    ++nodes;
    ++drawables;
    triangles += d.triangleCount();
}

void StatsVisitor::apply(Geometry& g) {
    ++nodes;
    ++drawables;
    triangles += g.triangleCount();
    vertices += g.positions.size();
}

} // namespace sgfx

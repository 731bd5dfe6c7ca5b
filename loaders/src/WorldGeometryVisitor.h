#pragma once
// The writers' common walk: every Geometry below a node (node masks honoured) with its world
// matrix and the state resolved along its path, once per instance of instanced geometry. Of a
// LOD only the most detailed level is written (the one shown nearest), so levels never overlap
// in the file.
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/LOD.h>
#include <sgfx/NodeVisitor.h>
#include <sgfx/PagedLOD.h>
#include <sgfx/StateSet.h>

#include <vector>

namespace sgfx {

class WorldGeometryVisitor : public NodeVisitor {
public:
    explicit WorldGeometryVisitor(const glm::mat4& root = glm::mat4(1.0f))
        : NodeVisitor(Mode::ActiveChildren)
        , matrix_(root) {
        state_.push_back(ResolvedState{});
    }

    void apply(Node& n) override {
        if (n.stateSet()) state_.push_back(state_.back().merged(*n.stateSet()));
        traverse(n);
        if (n.stateSet()) state_.pop_back();
    }
    void apply(Transform& t) override {
        const glm::mat4 saved = matrix_;
        matrix_ = matrix_ * t.matrix();
        apply(static_cast<Node&>(t));
        matrix_ = saved;
    }
    void apply(LOD& lod) override {
        // A PagedLOD's slots not loaded are empty placeholders: the finest loaded child instead.
        const auto* paged = dynamic_cast<const PagedLOD*>(&lod);
        std::size_t best = PagedLOD::npos;
        for (std::size_t i = 0; i < lod.children().size(); ++i) {
            if (paged && !paged->loaded(i)) continue;
            if (best == PagedLOD::npos) {
                best = i;
                continue;
            }
            const LOD::Range &r = lod.range(i), &b = lod.range(best);
            const float f = lod.fineness(i), fb = lod.fineness(best);
            if (f > fb || (f == fb && r.minPixels > b.minPixels)) best = i;
        }
        if (best == PagedLOD::npos) return;
        if (lod.stateSet()) state_.push_back(state_.back().merged(*lod.stateSet()));
        nodePath.push_back(&lod);
        if (accepts(*lod.children()[best])) lod.children()[best]->accept(*this);
        nodePath.pop_back();
        if (lod.stateSet()) state_.pop_back();
    }
    void apply(Geometry& g) override {
        if (g.positions.empty()) return;
        g.validate();
        if (g.stateSet()) state_.push_back(state_.back().merged(*g.stateSet()));
        for (std::size_t i = 0; i < g.instanceCount(); ++i)
            visit(g, g.instances.empty() ? matrix_ : matrix_ * g.instances[i], state_.back());
        if (g.stateSet()) state_.pop_back();
    }

protected:
    virtual void visit(const Geometry& g, const glm::mat4& world, const ResolvedState& state) = 0;

private:
    glm::mat4 matrix_;
    std::vector<ResolvedState> state_;
};

} // namespace sgfx

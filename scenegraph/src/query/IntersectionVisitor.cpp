// IntersectionVisitor: walks the graph (or a group's index) for an intersector.
#include "BvhWalk.h"
#include "SubtreeIndex.h"
#include "sgfx/Billboard.h"
#include "sgfx/Camera.h"
#include "sgfx/Geometry.h"
#include "sgfx/Intersection.h"
#include "sgfx/LOD.h"
#include "sgfx/PagedLOD.h"
#include "sgfx/Sequence.h"
#include "sgfx/Switch.h"

#include <limits>
#include <stdexcept>
#include <utility>

namespace sgfx {

QueryView QueryView::of(const Camera& camera) {
    QueryView v;
    v.viewMatrix = glm::dmat4(camera.viewMatrix);
    v.projectionMatrix = camera.projectionMatrix;
    v.viewportHeight = camera.viewport.height;
    return v;
}

IntersectionVisitor::IntersectionVisitor(Intersector& intersector, NodeMask queryMask)
    : NodeVisitor(Mode::ActiveChildren)
    , intersector_(intersector) {
    traversalMask = queryMask;
}

void IntersectionVisitor::visit(Node& node, const glm::dmat4& parentToWorld) {
    if (lodSelection == LodSelection::Shown && !view)
        throw std::invalid_argument(
            "sgfx: IntersectionVisitor: LodSelection::Shown needs a view (set `view`)");
    frames_.assign(1, QueryFrame::of(parentToWorld));
    ++frameVersion_;
    nodePath.clear();
    atStart_ = true;
    if (accepts(node)) node.accept(*this);
    atStart_ = false;
    frames_.clear();
    intersector_.finish();
}

bool IntersectionVisitor::enterBound(const Node& node) {
    if (intersector_.done()) return false;
    const BoundingSphere& s = node.bound();
    if (!s.valid()) return false;
    // The float sphere may be a rounding short of its contents: widen it a little.
    const glm::dvec3 c(s.center);
    const double r = double(s.radius) * (1.0 + 1e-6) + 1e-9;
    QueryBox box;
    box.min = c - r;
    box.max = c + r;
    if (frameSet_ != frameVersion_) { // the intersector's local form is for another frame
        intersector_.setFrame(frames_.back());
        frameSet_ = frameVersion_;
    }
    return intersector_.mayHit(box);
}

void IntersectionVisitor::pushFrame(const glm::dmat4& local) {
    frames_.push_back(QueryFrame::of(frames_.back().toWorld * local));
    ++frameVersion_;
}

void IntersectionVisitor::popFrame() {
    frames_.pop_back();
    ++frameVersion_;
}

void IntersectionVisitor::apply(Node& node) {
    atStart_ = false;
    if (enterBound(node)) traverse(node);
}

void IntersectionVisitor::apply(Group& group) {
    const bool start = std::exchange(atStart_, false);
    if (!enterBound(group)) return;
    if (start && useSubtreeIndex)
        visitIndexed(group);
    else
        traverse(group);
}

void IntersectionVisitor::apply(Transform& t) {
    const bool start = std::exchange(atStart_, false);
    if (!enterBound(t)) return;
    pushFrame(glm::dmat4(t.matrix()));
    if (start && useSubtreeIndex)
        visitIndexed(t);
    else
        traverse(t);
    popFrame();
}

void IntersectionVisitor::apply(LOD& lod) {
    atStart_ = false;
    if (!enterBound(lod)) return;
    std::vector<bool> chosen(lod.numChildren(), false);
    // A PagedLOD's slots not loaded hold placeholders: the cull draws a coarser child instead.
    const auto* paged = dynamic_cast<const PagedLOD*>(&lod);
    auto present = [&](std::size_t i) { return !paged || paged->loaded(i); };
    if (lodSelection == LodSelection::Finest) {
        // The finest children (LOD::fineness): what the LOD shows when largest on screen or nearest.
        float top = -std::numeric_limits<float>::infinity();
        for (std::size_t i = 0; i < chosen.size(); ++i)
            if (present(i)) top = std::max(top, lod.fineness(i));
        for (std::size_t i = 0; i < chosen.size(); ++i)
            chosen[i] = present(i) && lod.fineness(i) == top;
    } else {
        // As CullVisitor does: the selection sphere's projected size, or the eye's distance in
        // the LOD's frame, in the query's view.
        const BoundingSphere& local = lod.selectionSphere();
        float measure = 0.0f;
        if (local.valid()) {
            const glm::dmat4 modelView = view->viewMatrix * frames_.back().toWorld;
            if (lod.rangeMode() == LOD::RangeMode::DistanceFromEye) {
                const glm::dvec3 eye(glm::inverse(modelView)[3]);
                measure = float(glm::length(eye - glm::dvec3(local.center)));
            } else {
                const glm::vec3 center(modelView * glm::dvec4(glm::dvec3(local.center), 1.0));
                const float radius = local.radius * maxAxisScale(glm::mat4(modelView));
                measure = pixelSize(center, radius, view->projectionMatrix, view->viewportHeight);
            }
        }
        for (std::size_t i = 0; i < chosen.size(); ++i) {
            if (!lod.range(i).contains(measure)) continue;
            const std::size_t shown = present(i) ? i : paged->coarserLoaded(i);
            if (shown != PagedLOD::npos) chosen[shown] = true;
        }
    }
    nodePath.push_back(&lod);
    for (std::size_t i = 0; i < chosen.size(); ++i)
        if (chosen[i] && accepts(*lod.child(i))) lod.child(i)->accept(*this);
    nodePath.pop_back();
}

// Never through the index: it would hold the children that are off or not shown.
void IntersectionVisitor::apply(Switch& s) {
    atStart_ = false;
    if (enterBound(s)) traverse(s);
}

void IntersectionVisitor::apply(Sequence& s) {
    atStart_ = false;
    if (enterBound(s)) traverse(s);
}

void IntersectionVisitor::apply(Billboard& b) {
    atStart_ = false;
    if (!enterBound(b)) return;
    if (!view) { // the rest pose
        traverse(b);
        return;
    }
    // The eye and the view's up in the billboard's frame, as CullVisitor turns it.
    const glm::dmat4 toLocal = glm::inverse(view->viewMatrix * frames_.back().toWorld);
    pushFrame(glm::dmat4(b.orientation(glm::vec3(toLocal[3]), glm::vec3(toLocal[1]))));
    traverse(b);
    popFrame();
}

void IntersectionVisitor::apply(Geometry& g) {
    atStart_ = false;
    if (!enterBound(g)) return;
    nodePath.push_back(&g);
    const auto bvh = g.triangleBvh();
    const QueryFrame& frame = frames_.back();
    ++geometriesTested_;
    if (g.instances.empty()) {
        intersector_.intersect(g, *bvh, frame, {&nodePath, 0});
    } else {
        for (std::size_t i = 0; i < g.instances.size() && !intersector_.done(); ++i)
            intersector_.intersect(g, *bvh, QueryFrame::of(frame.toWorld * glm::dmat4(g.instances[i])),
                                   {&nodePath, std::uint32_t(i)});
    }
    nodePath.pop_back();
}

void IntersectionVisitor::apply(Drawable&) {
    atStart_ = false; // particles and volumes have no triangles to hit
}

void IntersectionVisitor::apply(Light&) {
    atStart_ = false;
}

void IntersectionVisitor::apply(Camera& c) {
    atStart_ = false;
    if (c.renderTarget) return; // its children are drawn into a texture, not placed in the world
    if (enterBound(c)) traverse(c);
}

void IntersectionVisitor::visitIndexed(Group& group) {
    nodePath.push_back(&group);
    const QueryFrame base = frames_.back(); // a copy: walking a LOD or billboard pushes frames
    walkIndex(*group.subtreeIndex(), base);
    nodePath.pop_back();
}

// nodePath ends with the index's group; `base` is the group's child frame.
void IntersectionVisitor::walkIndex(const SubtreeIndex& index, const QueryFrame& base) {
    const std::size_t depth = nodePath.size();
    intersector_.setFrame(base);
    ++frameVersion_; // what enterBound set is gone
    auto entry = [&](const BvhNodes::Node& n) {
        QueryBox box;
        box.min = glm::dvec3(n.min);
        box.max = glm::dvec3(n.max);
        return intersector_.entry(box);
    };
    auto reach = [&] { return intersector_.reach(); };
    auto leaf = [&](std::uint32_t first, std::uint32_t count) {
        for (std::uint32_t k = first; k < first + count; ++k) {
            const SubtreeIndex::Item& item = index.items[index.bvh.order[k]];
            // A leaf holds up to four items: the line may miss this one's box.
            const double t = intersector_.entry(item.box);
            if (t == query::kMiss || t > intersector_.reach()) continue;
            bool active = true;
            for (Node* n : item.path)
                active = active && accepts(*n);
            if (!active) continue;
            QueryFrame composed;
            if (!item.identity) {
                composed.toWorld = base.toWorld * item.toGroup;
                composed.toLocal = item.fromGroup * base.toLocal;
            }
            const QueryFrame& frame = item.identity ? base : composed;
            nodePath.insert(nodePath.end(), item.path.begin(), item.path.end());
            switch (item.kind) {
            case SubtreeIndex::Kind::Geometry:
                ++geometriesTested_;
                intersector_.intersect(*item.geometry, *item.bvh, frame, {&nodePath, item.instance});
                break;
            case SubtreeIndex::Kind::Nested:
                walkIndex(*item.nested, frame);
                intersector_.setFrame(base);
                break;
            case SubtreeIndex::Kind::Walk:
                nodePath.pop_back(); // the node's apply adds it
                frames_.push_back(frame);
                ++frameVersion_;
                item.node->accept(*this);
                popFrame();
                intersector_.setFrame(base);
                break;
            }
            nodePath.resize(depth);
            if (intersector_.done()) return false;
        }
        return true;
    };
    query::walkNearFirst(index.bvh, entry, reach, leaf); // nearer items first: Nearest prunes the rest
}

} // namespace sgfx

// Building a group's query index (SubtreeIndex.h).
#include "SubtreeIndex.h"

#include "sgfx/Billboard.h"
#include "sgfx/Camera.h"
#include "sgfx/Geometry.h"
#include "sgfx/LOD.h"
#include "sgfx/NodeVisitor.h"
#include "sgfx/Sequence.h"
#include "sgfx/Switch.h"

namespace sgfx {

namespace {

QueryBox transformedBox(const glm::dmat4& m, const glm::dvec3& lo, const glm::dvec3& hi) {
    QueryBox out;
    for (int c = 0; c < 8; ++c)
        out.expandBy(
            glm::dvec3(m * glm::dvec4(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z, 1.0)));
    return out;
}

// Whether `node` holds at least `n` index items (stops counting there).
bool holdsAtLeast(const Node& node, std::size_t& n) {
    if (auto* g = dynamic_cast<const Geometry*>(&node)) {
        n -= std::min(n, g->instanceCount());
    } else if (dynamic_cast<const LOD*>(&node) || dynamic_cast<const Billboard*>(&node) ||
               dynamic_cast<const Switch*>(&node) || dynamic_cast<const Sequence*>(&node)) {
        n -= std::min<std::size_t>(n, 1);
    } else if (auto* group = dynamic_cast<const Group*>(&node)) {
        for (std::size_t i = 0; i < group->numChildren() && n > 0; ++i)
            holdsAtLeast(*group->child(i), n);
    }
    return n == 0;
}

bool large(const Group& group) {
    std::size_t n = SubtreeIndex::kNestedItems;
    return holdsAtLeast(group, n);
}

// Every node below the group, all children whatever their masks: masks are read at query time.
class Collector : public NodeVisitor {
public:
    Collector(SubtreeIndex& index, std::vector<QueryBox>& boxes)
        : NodeVisitor(Mode::AllChildren)
        , index_(index)
        , boxes_(boxes) {}

    void apply(Group& g) override {
        if (large(g))
            addNested(g, matrix_);
        else
            traverse(g);
    }
    void apply(Transform& t) override {
        const glm::dmat4 inner = matrix_ * glm::dmat4(t.matrix());
        if (large(t)) {
            addNested(t, inner);
            return;
        }
        const glm::dmat4 saved = matrix_;
        matrix_ = inner;
        traverse(t);
        matrix_ = saved;
    }
    // View-dependent: walked at query time from their parent frame.
    void apply(LOD& lod) override { addSubtree(lod); }
    void apply(Billboard& b) override { addSubtree(b); }
    // What they show changes without their bound changing (a sequence's frame): walked too.
    void apply(Switch& s) override { addSubtree(s); }
    void apply(Sequence& s) override { addSubtree(s); }
    void apply(Geometry& g) override {
        auto bvh = g.triangleBvh();
        if (bvh->bvh().nodes.empty()) return;
        const BvhNodes::Node& root = bvh->bvh().nodes.front();
        const std::size_t n = g.instanceCount();
        for (std::size_t i = 0; i < n; ++i) {
            const glm::dmat4 m = g.instances.empty() ? matrix_ : matrix_ * glm::dmat4(g.instances[i]);
            SubtreeIndex::Item& item =
                add(g, m, transformedBox(m, glm::dvec3(root.min), glm::dvec3(root.max)));
            item.kind = SubtreeIndex::Kind::Geometry;
            item.geometry = &g;
            item.instance = std::uint32_t(i);
            item.bvh = bvh;
        }
    }
    void apply(Drawable&) override {} // not hit
    void apply(Light&) override {}
    void apply(Camera& c) override {
        if (!c.renderTarget) traverse(c); // one with a target is drawn into a texture
    }

private:
    void addSubtree(Node& node) {
        const BoundingSphere& s = node.bound();
        if (!s.valid()) return;
        const glm::dvec3 c(s.center);
        const double r = double(s.radius) * (1.0 + 1e-6) + 1e-9;
        add(node, matrix_, transformedBox(matrix_, c - r, c + r)).kind = SubtreeIndex::Kind::Walk;
    }
    // `inner`: the group's child frame (its own matrix included for a Transform).
    void addNested(Group& g, const glm::dmat4& inner) {
        auto nested = g.subtreeIndex();
        if (nested->bvh.nodes.empty()) return;
        const BvhNodes::Node& root = nested->bvh.nodes.front();
        SubtreeIndex::Item& item =
            add(g, inner, transformedBox(inner, glm::dvec3(root.min), glm::dvec3(root.max)));
        item.kind = SubtreeIndex::Kind::Nested;
        item.nested = std::move(nested);
    }
    SubtreeIndex::Item& add(Node& node, const glm::dmat4& m, const QueryBox& box) {
        SubtreeIndex::Item& item = index_.items.emplace_back();
        item.node = &node;
        item.toGroup = m;
        item.fromGroup = glm::inverse(m);
        item.identity = m == glm::dmat4(1.0);
        item.box = box;
        item.path = nodePath;
        item.path.push_back(&node);
        boxes_.push_back(box);
        return item;
    }

    SubtreeIndex& index_;
    std::vector<QueryBox>& boxes_;
    glm::dmat4 matrix_{1.0};
};

} // namespace

std::shared_ptr<const SubtreeIndex> SubtreeIndex::build(const Group& group) {
    auto index = std::make_shared<SubtreeIndex>();
    group.bound(); // clean bounds: later changes below move boundChanges() again
    index->boundChanges = group.boundChanges();
    std::vector<QueryBox> boxes;
    Collector collector(*index, boxes);
    const_cast<Group&>(group).traverse(collector); // the collector only reads
    index->bvh = BvhNodes::build(boxes);
    return index;
}

std::size_t SubtreeIndex::memoryBytes() const {
    std::size_t bytes = sizeof(*this) + bvh.memoryBytes() + items.capacity() * sizeof(Item);
    for (const Item& item : items)
        bytes += item.path.capacity() * sizeof(Node*);
    return bytes;
}

std::shared_ptr<const SubtreeIndex> Group::subtreeIndex() const {
    std::lock_guard lock(queryMutex_);
    if (!queryIndex_ || queryIndex_->boundChanges != boundChanges()) queryIndex_ = SubtreeIndex::build(*this);
    return queryIndex_;
}

} // namespace sgfx

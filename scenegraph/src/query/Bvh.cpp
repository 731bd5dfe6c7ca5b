// BVH construction (binned SAH) and the per-Geometry triangle BVH.
#include "sgfx/Geometry.h"
#include "sgfx/TriangleBvh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {

constexpr int kBins = 16;
constexpr std::uint32_t kLeafSize = 4;
constexpr std::uint32_t kMaxLeafSize = 16; // the SAH may keep up to this many in a leaf

// Float bounds that hold the double value: boxes stay conservative after the narrowing.
float roundDown(double v) {
    const float f = static_cast<float>(v);
    return double(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float roundUp(double v) {
    const float f = static_cast<float>(v);
    return double(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

struct Split {
    int axis = -1;
    int bin = 0; // items in bins [0, bin] go left
    double cost = std::numeric_limits<double>::max();
};

// Builds the tree depth first with an explicit stack (an unbalanced split cannot overflow it).
class Builder {
public:
    Builder(const std::vector<QueryBox>& boxes, BvhNodes& out)
        : boxes_(boxes)
        , out_(out) {
        centroids_.reserve(boxes.size());
        for (const QueryBox& b : boxes)
            centroids_.push_back(b.center());
    }

    void run() {
        auto& order = out_.order;
        for (std::uint32_t i = 0; i < boxes_.size(); ++i)
            if (boxes_[i].valid()) order.push_back(i);
        if (order.empty()) return;
        out_.nodes.reserve(order.size() / 2 + 1);
        struct Task {
            std::uint32_t begin, end;
            std::int64_t parent; // node whose `first` becomes this node's index; -1: none
        };
        std::vector<Task> stack{{0, std::uint32_t(order.size()), -1}};
        while (!stack.empty()) {
            const Task t = stack.back();
            stack.pop_back();
            const auto index = std::uint32_t(out_.nodes.size());
            if (t.parent >= 0) out_.nodes[std::size_t(t.parent)].first = index;
            out_.nodes.push_back(makeNode(t.begin, t.end));
            const std::uint32_t mid = partition(t.begin, t.end);
            if (mid == t.begin) continue; // a leaf
            BvhNodes::Node& n = out_.nodes.back();
            n.count = 0;
            stack.push_back({mid, t.end, index}); // second child: its index is patched in
            stack.push_back({t.begin, mid, -1});  // first child: index + 1
        }
    }

private:
    BvhNodes::Node makeNode(std::uint32_t begin, std::uint32_t end) const {
        QueryBox box;
        for (std::uint32_t i = begin; i < end; ++i)
            box.expandBy(boxes_[out_.order[i]]);
        BvhNodes::Node n;
        n.min = {roundDown(box.min.x), roundDown(box.min.y), roundDown(box.min.z)};
        n.max = {roundUp(box.max.x), roundUp(box.max.y), roundUp(box.max.z)};
        n.first = begin;
        n.count = end - begin;
        return n;
    }

    // Sorts [begin, end) into two halves and returns the split point; `begin` for a leaf.
    std::uint32_t partition(std::uint32_t begin, std::uint32_t end) {
        const std::uint32_t count = end - begin;
        if (count <= kLeafSize) return begin;
        auto& order = out_.order;
        QueryBox cb; // centroid bounds
        QueryBox nodeBox;
        for (std::uint32_t i = begin; i < end; ++i) {
            cb.expandBy(centroids_[order[i]]);
            nodeBox.expandBy(boxes_[order[i]]);
        }
        const Split s = bestSplit(begin, end, cb);
        if (s.axis < 0) // every centroid in one place: halve by count so the depth stays logarithmic
            return count <= kMaxLeafSize ? begin : begin + count / 2;
        // SAH: a split costs one box test plus the halves' expected item tests (Wald 2007).
        const double area = nodeBox.area();
        if (count <= kMaxLeafSize && area > 0.0 && 1.0 + s.cost / area >= double(count)) return begin;
        const double lo = cb.min[s.axis], scale = kBins / (cb.max[s.axis] - cb.min[s.axis]);
        auto* mid = std::partition(order.data() + begin, order.data() + end, [&](std::uint32_t i) {
            return binOf(centroids_[i][s.axis], lo, scale) <= s.bin;
        });
        const auto m = std::uint32_t(mid - order.data());
        return (m == begin || m == end) ? begin + count / 2 : m;
    }

    static int binOf(double c, double lo, double scale) {
        return std::clamp(int((c - lo) * scale), 0, kBins - 1);
    }

    Split bestSplit(std::uint32_t begin, std::uint32_t end, const QueryBox& cb) const {
        Split best;
        for (int axis = 0; axis < 3; ++axis) {
            const double extent = cb.max[axis] - cb.min[axis];
            if (!(extent > 0.0)) continue;
            const double lo = cb.min[axis], scale = kBins / extent;
            std::array<QueryBox, kBins> box;
            std::array<std::uint32_t, kBins> n{};
            for (std::uint32_t i = begin; i < end; ++i) {
                const std::uint32_t item = out_.order[i];
                const int b = binOf(centroids_[item][axis], lo, scale);
                box[std::size_t(b)].expandBy(boxes_[item]);
                ++n[std::size_t(b)];
            }
            // Sweep from the right for the right halves' areas, then from the left.
            std::array<double, kBins> rightCost{};
            QueryBox acc;
            std::uint32_t cnt = 0;
            for (int b = kBins - 1; b > 0; --b) {
                acc.expandBy(box[std::size_t(b)]);
                cnt += n[std::size_t(b)];
                rightCost[std::size_t(b)] = acc.area() * cnt;
            }
            acc = QueryBox{};
            cnt = 0;
            for (int b = 0; b < kBins - 1; ++b) {
                acc.expandBy(box[std::size_t(b)]);
                cnt += n[std::size_t(b)];
                const double cost = acc.area() * cnt + rightCost[std::size_t(b) + 1];
                if (cnt > 0 && cnt < end - begin && cost < best.cost) best = {axis, b, cost};
            }
        }
        return best;
    }

    const std::vector<QueryBox>& boxes_;
    BvhNodes& out_;
    std::vector<glm::dvec3> centroids_;
};

std::string geometryLabel(const Geometry& g) {
    return g.name.empty() ? std::string("an unnamed geometry") : "geometry '" + g.name + "'";
}

} // namespace

double QueryBox::area() const {
    if (!valid()) return 0.0;
    const glm::dvec3 e = max - min;
    return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
}

BvhNodes BvhNodes::build(const std::vector<QueryBox>& boxes) {
    BvhNodes out;
    Builder(boxes, out).run();
    return out;
}

std::vector<std::array<std::uint32_t, 3>> triangleIndices(const Geometry& g) {
    std::vector<std::array<std::uint32_t, 3>> tris;
    const std::size_t n = g.elementCount();
    auto at = [&](std::size_t i) { return g.indices.empty() ? std::uint32_t(i) : g.indices[i]; };
    switch (g.mode) {
    case PrimitiveMode::Triangles:
        tris.reserve(n / 3);
        for (std::size_t i = 0; i + 2 < n; i += 3)
            tris.push_back({at(i), at(i + 1), at(i + 2)});
        break;
    case PrimitiveMode::TriangleStrip:
        // Odd triangles swap two vertices so every triangle keeps the first one's winding.
        for (std::size_t i = 0; i + 2 < n; ++i)
            tris.push_back(i % 2 ? std::array{at(i + 1), at(i), at(i + 2)}
                                 : std::array{at(i), at(i + 1), at(i + 2)});
        break;
    case PrimitiveMode::TriangleFan:
        for (std::size_t i = 1; i + 1 < n; ++i)
            tris.push_back({at(0), at(i), at(i + 1)});
        break;
    default:
        break; // points and lines have no area
    }
    return tris;
}

TriangleBvh::TriangleBvh(const Geometry& g)
    : revision_(g.revision()) {
    g.validate();
    const auto tris = triangleIndices(g);
    std::vector<QueryBox> boxes(tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t) {
        const glm::dvec3 a(g.positions[tris[t][0]]), b(g.positions[tris[t][1]]), c(g.positions[tris[t][2]]);
        if (!std::isfinite(a.x + a.y + a.z + b.x + b.y + b.z + c.x + c.y + c.z))
            throw std::invalid_argument("sgfx: " + geometryLabel(g) + ": triangle " + std::to_string(t) +
                                        " has a position that is not finite");
        if (glm::length(glm::cross(b - a, c - a)) == 0.0) continue; // no area: nothing to hit
        boxes[t].expandBy(a);
        boxes[t].expandBy(b);
        boxes[t].expandBy(c);
    }
    bvh_ = BvhNodes::build(boxes);
    // Store the triangles in leaf order, so a leaf reads consecutive entries.
    triangles_.reserve(bvh_.order.size());
    corners_.reserve(bvh_.order.size() * 3);
    for (const std::uint32_t t : bvh_.order) {
        triangles_.push_back({tris[t], t});
        for (const std::uint32_t v : tris[t])
            corners_.push_back(g.positions[v]);
    }
    bvh_.order = {}; // leaves index triangles_ directly
}

std::size_t TriangleBvh::memoryBytes() const {
    return sizeof(*this) + bvh_.memoryBytes() + triangles_.size() * sizeof(Triangle) +
           corners_.size() * sizeof(glm::vec3);
}

std::shared_ptr<const TriangleBvh> Geometry::triangleBvh() const {
    std::lock_guard lock(queryMutex_);
    if (!bvh_ || bvh_->revision() != revision()) bvh_ = std::make_shared<const TriangleBvh>(*this);
    return bvh_;
}

} // namespace sgfx

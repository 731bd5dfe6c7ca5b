#pragma once
// Walking a BvhNodes tree: in any order (boxes, spheres, polytopes) or nearer child first (lines).
#include "sgfx/TriangleBvh.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace sgfx::query {

constexpr double kMiss = std::numeric_limits<double>::infinity();

/// A stack that lives on the C stack until it is deep (an unbalanced tree may be).
template <class T> class WalkStack {
public:
    void push(const T& v) {
        if (size_ < kFixed)
            fixed_[size_] = v;
        else
            more_.push_back(v);
        ++size_;
    }
    T pop() {
        --size_;
        if (size_ < kFixed) return fixed_[size_];
        T v = more_.back();
        more_.pop_back();
        return v;
    }
    bool empty() const { return size_ == 0; }

private:
    static constexpr std::size_t kFixed = 64;
    T fixed_[kFixed];
    std::vector<T> more_;
    std::size_t size_ = 0;
};

/// Calls leaf(first, count) for every leaf whose box and ancestors' boxes pass test(node);
/// stops when leaf returns false. Returns false if stopped.
template <class Test, class Leaf> bool walk(const BvhNodes& b, Test&& test, Leaf&& leaf) {
    if (b.nodes.empty()) return true;
    WalkStack<std::uint32_t> stack;
    stack.push(0);
    while (!stack.empty()) {
        const std::uint32_t i = stack.pop();
        const BvhNodes::Node& n = b.nodes[i];
        if (!test(n)) continue;
        if (n.count > 0) {
            if (!leaf(n.first, n.count)) return false;
            continue;
        }
        stack.push(n.first);
        stack.push(i + 1);
    }
    return true;
}

/// As walk, nearer boxes first: entry(node) is where the line enters the box (kMiss: it does
/// not), bound() the farthest parameter still wanted (it shrinks as nearer hits are found).
template <class Entry, class Bound, class Leaf>
bool walkNearFirst(const BvhNodes& b, Entry&& entry, Bound&& bound, Leaf&& leaf) {
    if (b.nodes.empty()) return true;
    struct Item {
        std::uint32_t node;
        double t;
    };
    const double t0 = entry(b.nodes[0]);
    if (t0 == kMiss) return true;
    WalkStack<Item> stack;
    stack.push({0, t0});
    while (!stack.empty()) {
        const Item it = stack.pop();
        if (it.t > bound()) continue;
        const BvhNodes::Node& n = b.nodes[it.node];
        if (n.count > 0) {
            if (!leaf(n.first, n.count)) return false;
            continue;
        }
        const std::uint32_t a = it.node + 1, c = n.first;
        const double ta = entry(b.nodes[a]), tc = entry(b.nodes[c]);
        // Push the farther first so the nearer is taken next.
        if (ta <= tc) {
            if (tc != kMiss) stack.push({c, tc});
            if (ta != kMiss) stack.push({a, ta});
        } else {
            if (ta != kMiss) stack.push({a, ta});
            stack.push({c, tc});
        }
    }
    return true;
}

/// A line o + t·d, t in [0, tMax], against boxes (slab test in double).
struct LineSlab {
    glm::dvec3 o, inv;
    bool flat[3]; // d[axis] == 0: the line stays in one slab position on that axis

    LineSlab(const glm::dvec3& origin, const glm::dvec3& d)
        : o(origin) {
        for (int a = 0; a < 3; ++a) {
            flat[a] = d[a] == 0.0;
            inv[a] = flat[a] ? 0.0 : 1.0 / d[a];
        }
    }
    /// With the reciprocals computed already (0 where d is 0).
    LineSlab(const glm::dvec3& origin, const glm::dvec3& d, const glm::dvec3& reciprocal)
        : o(origin)
        , inv(reciprocal) {
        for (int a = 0; a < 3; ++a)
            flat[a] = d[a] == 0.0;
    }
    /// Entry parameter into [min, max] within [0, tMax], or kMiss. A relative slack of 1e-9 keeps
    /// rounding from losing a hit on a box face (it only costs a few extra tests).
    double entry(const glm::dvec3& min, const glm::dvec3& max, double tMax) const {
        double lo = 0.0, hi = tMax;
        for (int a = 0; a < 3; ++a) {
            if (flat[a]) {
                if (o[a] < min[a] || o[a] > max[a]) return kMiss;
                continue;
            }
            double t1 = (min[a] - o[a]) * inv[a], t2 = (max[a] - o[a]) * inv[a];
            if (t1 > t2) std::swap(t1, t2);
            lo = std::max(lo, t1);
            hi = std::min(hi, t2);
        }
        const double slack = 1e-9 * (std::abs(hi) + std::abs(lo) + 1e-300);
        return lo <= hi + slack ? lo : kMiss;
    }
    double entry(const BvhNodes::Node& n, double tMax) const {
        return entry(glm::dvec3(n.min), glm::dvec3(n.max), tMax);
    }
};

} // namespace sgfx::query

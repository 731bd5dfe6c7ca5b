// Levels of detail made at load with meshoptimizer's simplifier, and the independent measure of
// their error that sets their ranges (MeshOptimize.h).
#include "sgfx/MeshOptimize.h"

#include "ParallelFor.h"

#include <sgfx/Group.h>
#include <sgfx/Math.h>
#include <sgfx/TriangleBvh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <unordered_map>
#include <unordered_set>

#if SGFX_HAVE_MESHOPTIMIZER
#include <meshoptimizer.h>
#endif

namespace sgfx {

namespace {

float boxDistance2(glm::vec3 p, glm::vec3 lo, glm::vec3 hi) {
    const glm::vec3 d = glm::max(glm::max(lo - p, p - hi), glm::vec3(0.0f));
    return glm::dot(d, d);
}

float triangleDistance2(const std::vector<glm::vec3>& corners, std::uint32_t t, glm::vec3 p) {
    const glm::vec3 a = corners[3 * t], b = corners[3 * t + 1], c = corners[3 * t + 2];
    const glm::vec3 w = closestOnTriangle(p, a, b, c);
    const glm::vec3 q = w.x * a + w.y * b + w.z * c;
    return glm::dot(p - q, p - q);
}

// Squared distance from p to the nearest triangle of the BVH (depth-first, nearer child first).
// `hint` is the triangle nearest to the previous, nearby sample: starting from its distance prunes
// most of the tree at once; it becomes this sample's nearest.
float surfaceDistance2(const TriangleBvh& bvh, glm::vec3 p, std::uint32_t& hint) {
    const auto& nodes = bvh.bvh().nodes;
    const auto& corners = bvh.corners();
    float best = std::numeric_limits<float>::max();
    if (nodes.empty()) return best;
    if (3 * std::size_t(hint) + 2 < corners.size()) best = triangleDistance2(corners, hint, p);
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const auto& n = nodes[stack[--top]];
        if (boxDistance2(p, n.min, n.max) >= best) continue;
        if (n.count > 0) {
            for (std::uint32_t t = n.first; t < n.first + n.count; ++t) {
                const float d2 = triangleDistance2(corners, t, p);
                if (d2 < best) best = d2, hint = t;
            }
            continue;
        }
        const std::uint32_t a = std::uint32_t(&n - nodes.data()) + 1, b = n.first;
        const bool aNear =
            boxDistance2(p, nodes[a].min, nodes[a].max) <= boxDistance2(p, nodes[b].min, nodes[b].max);
        if (top + 2 > 64) continue; // deeper than any SAH tree over 2^32 triangles
        stack[top++] = aNear ? b : a;
        stack[top++] = aNear ? a : b;
    }
    return best;
}

// Largest distance from a sample of `from`'s triangles to `to`'s surface.
float oneSided(const Geometry& from, const TriangleBvh& to) {
    static const glm::vec3 weights[8] = {{1, 0, 0},
                                         {0, 1, 0},
                                         {0, 0, 1},
                                         {0.5f, 0.5f, 0},
                                         {0, 0.5f, 0.5f},
                                         {0.5f, 0, 0.5f},
                                         {1.0f / 3, 1.0f / 3, 1.0f / 3},
                                         {2.0f / 3, 1.0f / 6, 1.0f / 6}};
    float worst = 0.0f;
    std::uint32_t hint = 0;
    for (const auto& t : triangleIndices(from)) {
        const glm::vec3 a = from.positions[t[0]], b = from.positions[t[1]], c = from.positions[t[2]];
        for (const glm::vec3& w : weights)
            worst = std::max(worst, surfaceDistance2(to, w.x * a + w.y * b + w.z * c, hint));
    }
    return std::sqrt(worst);
}

// For each vertex of `from`, the triangles of `to`'s BVH that use a vertex at the identical position
// (meshoptimizer's levels keep the full mesh's vertices bit for bit): the vertex is at distance 0
// from each of them. The triangles of from's vertex v are list[first[v], first[v + 1]).
struct SharedVertices {
    std::vector<std::uint32_t> first, list;
    std::size_t size(std::uint32_t v) const { return first[v + 1] - first[v]; }
    const std::uint32_t* begin(std::uint32_t v) const { return list.data() + first[v]; }
};

// `toVertex[v]`: the vertex of `to` at the position of from's vertex v, or ~0u.
SharedVertices sharedVertices(const TriangleBvh& to, std::size_t toVertices,
                              const std::vector<std::uint32_t>& toVertex) {
    const auto& tris = to.triangles();
    std::vector<std::uint32_t> start(toVertices + 1, 0);
    for (const auto& t : tris)
        for (const std::uint32_t v : t.v)
            ++start[v + 1];
    for (std::size_t i = 1; i < start.size(); ++i)
        start[i] += start[i - 1];
    std::vector<std::uint32_t> fan(start.back()), fill(start.begin(), start.end() - 1);
    for (std::uint32_t k = 0; k < tris.size(); ++k)
        for (const std::uint32_t v : tris[k].v)
            fan[fill[v]++] = k;
    SharedVertices out;
    out.first.assign(toVertex.size() + 1, 0);
    for (std::size_t v = 0; v < toVertex.size(); ++v) {
        const std::uint32_t w = toVertex[v];
        if (w != ~0u && w < toVertices)
            out.list.insert(out.list.end(), fan.begin() + start[w], fan.begin() + start[w + 1]);
        out.first[v + 1] = std::uint32_t(out.list.size());
    }
    return out;
}

// A rigorous upper bound of the one-sided Hausdorff distance from `from` to `to`'s surface, by
// branch and bound over pieces of `from`'s triangles. For a piece with corners p_j, two bounds hold
// for every point q of it: (convexity) q's distance to one triangle t of `to` is a convex function,
// so it is at most max_j dist(p_j, t); (Lipschitz) the distance to a surface changes at most as fast
// as q moves, so it is at most dist(c, to) + max_j |p_j - c| for the centroid c. The convexity
// bound through a triangle nearest to all corners is exact. A piece whose smallest bound is within
// the slack of the largest distance found at an actual point (a lower bound of the result), or
// under `floor` (a value the caller rounds the result up to anyway), is done; otherwise it is split
// where its corners' nearest triangles change (split), at most maxDepth times and into at most
// pieceBudget pieces per triangle (past that, its bound is taken as it is: still an upper bound,
// only looser). Every number settled is an upper bound for its piece, and the pieces cover the
// triangle, so the largest is one for the whole side.
class OneSidedBound {
public:
    using Stats = HausdorffBoundStats;
    OneSidedBound(const TriangleBvh& to, float relSlack, float absSlack, float floor,
                  const SharedVertices* shared)
        : corners_(to.corners())
        , bvh_(to)
        , shared_(shared)
        , rel_(relSlack)
        , abs_(absSlack)
        , floor_(floor) {}

    // The vertices' distances first: returns their largest, a lower bound the other side may share.
    float prepare(const Geometry& from) {
        tris_ = drawnTriangles(from);
        vertices_.assign(from.positions.size(), Near{-1.0f, 0});
        for (const auto& t : tris_)
            for (const std::uint32_t v : t)
                if (vertices_[v].d < 0) {
                    if (shared_ && shared_->size(v) > 0)
                        vertices_[v] = {0.0f, *shared_->begin(v)}; // the same point: no query
                    else
                        vertices_[v] = nearest(from.positions[v]);
                }
        return lower_;
    }
    void share(float lower) { lower_ = std::max(lower_, lower); }

    float run(const Geometry& from) {
        for (const auto& t : tris_) {
            const Piece p{from.positions[t[0]], from.positions[t[1]], from.positions[t[2]]};
            const Corners n{vertices_[t[0]], vertices_[t[1]], vertices_[t[2]]};
            // The corners' own nearest triangles (and those the shared corners lie on) first: exact
            // when one of them is nearest to all three corners, the common case on a fine mesh.
            Stats::Path path = Stats::Convex;
            const float cb = convexBound(p, n, nullptr, &t, &path);
            if (cb <= accept()) {
                settle(cb, path, p, 0);
                continue;
            }
            const float h = projected(p[0], p[1], p[2]);
            if (h >= 0.0f && h <= accept()) {
                settle(h, Stats::Projection, p, 0);
                continue;
            }
            const bool projectedBetter = h >= 0.0f && h < cb;
            refine(p, n, 0, projectedBetter ? h : cb, projectedBetter ? Stats::Projection : path,
                   pieceBudget);
        }
        stats_.lower = lower_, stats_.upper = upper_;
        return upper_;
    }
    const Stats& stats() const { return stats_; }

private:
    struct Near {
        float d;
        std::uint32_t tri;
    };
    using Piece = std::array<glm::vec3, 3>;
    using Corners = std::array<Near, 3>;
    static constexpr int maxDepth = 8;
    static constexpr int pieceBudget = 256; // pieces per triangle of `from`

    // from's triangles with area. A triangle of zero area is a segment that draws nothing (it covers
    // no pixel from any view), as TriangleBvh leaves it out of `to`'s surface; the simplifier leaves
    // such slivers on flat parts and straight borders, where bounding them as segments is loose.
    static std::vector<std::array<std::uint32_t, 3>> drawnTriangles(const Geometry& from) {
        auto tris = triangleIndices(from);
        tris.erase(std::remove_if(tris.begin(), tris.end(),
                                  [&](const std::array<std::uint32_t, 3>& t) {
                                      const glm::dvec3 a(from.positions[t[0]]), b(from.positions[t[1]]),
                                          c(from.positions[t[2]]);
                                      return glm::length(glm::cross(b - a, c - a)) ==
                                             0.0; // TriangleBvh's test
                                  }),
                   tris.end());
        return tris;
    }
    float accept() const { return std::max(floor_, lower_ * (1.0f + rel_) + abs_); }
    void settle(float bound, Stats::Path path, const Piece& p, int depth) {
        ++stats_.settled[path];
        if (bound > upper_)
            upper_ = bound, stats_.worst = path, stats_.worstPiece = p, stats_.worstDepth = depth;
    }
    static glm::vec3 centroid(glm::vec3 a, glm::vec3 b, glm::vec3 c) { return (a + b + c) / 3.0f; }
    float distance(glm::vec3 p, std::uint32_t t) const {
        return std::sqrt(triangleDistance2(corners_, t, p));
    }
    Near nearest(glm::vec3 p) {
        ++stats_.queries;
        const float d = std::sqrt(surfaceDistance2(bvh_, p, hint_));
        lower_ = std::max(lower_, d);
        return {d, hint_};
    }

    // The bound along the normal n of triangle abc: every point q of abc is at most d(q, m) from
    // `to`, where m is a triangle of `to` whose projection onto abc's plane holds q, within the
    // height |g(q)| <= search along n. d(., m) is convex, so on m's projection clipped to abc (a
    // convex polygon) its largest value is at a corner of the polygon, and it is at most |g| there
    // (the corner plus g n lies on m). Valid when the clipped projections, all of one orientation,
    // cover abc (their areas sum to abc's): `to` is a graph over abc there. Returns -1 when they do
    // not (folds, holes, steep parts): the caller refines.
    float projected(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
        ++stats_.projections;
        // The search height starts at 4x the largest distance found and grows while the height
        // clip cuts area (the cover would then be short, or charged a crack margin).
        float search = std::max(4.0f * lower_, abs_) + 1e-6f * glm::length(b - a);
        for (int attempt = 0;; ++attempt, search *= 8.0f) {
            bool cut = false;
            std::size_t* why = nullptr;
            const float h = projected(a, b, c, search, cut, why);
            if (cut && attempt < 2) continue;
            if (h < 0.0f && why) ++*(cut ? &stats_.cut : why);
            return h;
        }
    }
    // One try at a given search height; `cut` tells whether the height clip removed area, `why`
    // points at the counter of the reason for a failure.
    float projected(glm::vec3 a, glm::vec3 b, glm::vec3 c, float search, bool& cut, std::size_t*& why) {
        using D2 = glm::dvec2;
        using D3 = glm::dvec3;
        const D3 A(a), cr = glm::cross(D3(b) - A, D3(c) - A);
        const double len = glm::length(cr);
        if (!(len > 0.0)) return why = &stats_.degenerate, -1.0f;
        const D3 n = cr / len, u = glm::normalize(D3(b) - A), v = glm::cross(n, u);
        const double area = 0.5 * len;
        const glm::vec3 lo = glm::min(glm::min(a, b), c) - glm::vec3(search),
                        hi = glm::max(glm::max(a, b), c) + glm::vec3(search);
        const D2 T[3] = {{0, 0},
                         {glm::dot(D3(b) - A, u), glm::dot(D3(b) - A, v)},
                         {glm::dot(D3(c) - A, u), glm::dot(D3(c) - A, v)}};
        const D2 tlo = glm::min(glm::min(T[0], T[1]), T[2]), thi = glm::max(glm::max(T[0], T[1]), T[2]);
        double covered[2] = {0.0, 0.0}, worst[2] = {0.0, 0.0};
        const auto& nodes = bvh_.bvh().nodes;
        std::uint32_t stack[64];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const auto& nd = nodes[stack[--top]];
            if (glm::any(glm::lessThan(nd.max, lo)) || glm::any(glm::greaterThan(nd.min, hi))) continue;
            if (nd.count == 0) {
                if (top + 2 > 64) return why = &stats_.degenerate, -1.0f;
                stack[top++] = std::uint32_t(&nd - nodes.data()) + 1, stack[top++] = nd.first;
                continue;
            }
            for (std::uint32_t t = nd.first; t < nd.first + nd.count; ++t) {
                double z[3];
                D2 q[3];
                for (std::uint32_t k = 0; k < 3; ++k) {
                    const D3 m = D3(corners_[3 * t + k]) - A;
                    z[k] = glm::dot(m, n), q[k] = {glm::dot(m, u), glm::dot(m, v)};
                }
                // Cheap rejections first: m entirely above or below the search height, or its
                // projection beside abc's box.
                if (std::min({z[0], z[1], z[2]}) > search || std::max({z[0], z[1], z[2]}) < -search) continue;
                const D2 qlo = glm::min(glm::min(q[0], q[1]), q[2]),
                         qhi = glm::max(glm::max(q[0], q[1]), q[2]);
                if (glm::any(glm::lessThan(qhi, tlo)) || glm::any(glm::greaterThan(qlo, thi))) continue;
                const double s2 = cross2(q[1] - q[0], q[2] - q[0]);
                // Steep triangles (over ~89 degrees to abc) are left out: any subset that covers abc
                // bounds it, and theirs would only add folds and tall offsets.
                const double full2 = glm::length(glm::cross(D3(corners_[3 * t + 1]) - D3(corners_[3 * t]),
                                                            D3(corners_[3 * t + 2]) - D3(corners_[3 * t])));
                if (std::abs(s2) <= 0.02 * full2 || std::abs(s2) <= 1e-12 * len) continue;
                // abc in m's projection as (x, y, g), g linear: clipped by m's edges, then |g| <= search.
                Polygon poly;
                int count = 0;
                for (const D2& p : T) {
                    const double w1 = cross2(p - q[0], q[2] - q[0]) / s2,
                                 w2 = cross2(q[1] - q[0], p - q[0]) / s2;
                    poly[std::size_t(count++)] = {p, z[0] + w1 * (z[1] - z[0]) + w2 * (z[2] - z[0])};
                }
                const double o = s2 > 0 ? 1.0 : -1.0;
                for (int e = 0; e < 3 && count > 0; ++e) {
                    const D2 p0 = q[e], p1 = q[(e + 1) % 3];
                    count = clip(poly, count, [&](D3 x) { return o * cross2(p1 - p0, D2(x) - p0); });
                }
                const int inside = count;
                if (count > 0) count = clip(poly, count, [&](D3 x) { return double(search) - x.z; });
                if (count > 0) count = clip(poly, count, [&](D3 x) { return double(search) + x.z; });
                cut = cut || count != inside;
                double part = 0.0;
                for (int k = 1; k + 1 < count; ++k)
                    part += 0.5 * cross2(D2(poly[std::size_t(k)] - poly[0]),
                                         D2(poly[std::size_t(k + 1)] - poly[0]));
                if (!(std::abs(part) > 0.0)) continue;
                const std::size_t side = s2 > 0 ? 0 : 1; // the two orientations, kept apart
                covered[side] += std::abs(part);
                const D3 m0(corners_[3 * t]), m1(corners_[3 * t + 1]), m2(corners_[3 * t + 2]);
                for (int k = 0; k < count; ++k) {
                    const D3 x = poly[std::size_t(k)];
                    const double g = std::abs(x.z);
                    if (g <= worst[side]) continue; // the corner distance is at most |g|
                    const D3 corner = A + x.x * u + x.y * v, w = closestOnTriangle(corner, m0, m1, m2);
                    const double d = glm::length(corner - (w.x * m0 + w.y * m1 + w.z * m2));
                    worst[side] = std::max(worst[side], std::min(g, d));
                }
            }
        }
        // A little uncovered area (cracks in `to`, rounding) costs a margin: a point q of abc that
        // is r from every covered point has a sector of the disk of radius r about q, of angle at
        // least abc's smallest angle a, uncovered, so r <= sqrt(2 missing / a); add r (Lipschitz).
        // One orientation alone must cover abc (its triangles then form a graph over abc).
        const std::size_t side = covered[0] >= covered[1] ? 0 : 1;
        const double missing = area - covered[side];
        if (missing < -1e-9 * area) return why = &stats_.overlap, -1.0f;
        if (missing > 1e-3 * area) return why = &stats_.uncovered, -1.0f;
        const double margin = std::sqrt(2.0 * std::max(missing, 0.0) / smallestAngle(T));
        stats_.crackMargins += margin > 0.25 * double(abs_);
        return float(worst[side] + margin) * (1.0f + 1e-6f);
    }
    static double smallestAngle(const glm::dvec2 (&t)[3]) {
        double smallest = 4.0;
        for (int k = 0; k < 3; ++k) {
            const glm::dvec2 e1 = t[(k + 1) % 3] - t[k], e2 = t[(k + 2) % 3] - t[k];
            smallest = std::min(smallest, std::atan2(std::abs(cross2(e1, e2)), glm::dot(e1, e2)));
        }
        return std::max(smallest, 1e-12);
    }
    using Polygon = std::array<glm::dvec3, 12>;
    static double cross2(glm::dvec2 p, glm::dvec2 q) { return p.x * q.y - p.y * q.x; }
    // Sutherland-Hodgman: keeps the part of the convex polygon where f >= 0 (f linear).
    template <class F> static int clip(Polygon& poly, int count, F f) {
        Polygon out;
        int k = 0;
        for (int i = 0; i < count; ++i) {
            const glm::dvec3 p = poly[std::size_t(i)], q = poly[std::size_t((i + 1) % count)];
            const double fp = f(p), fq = f(q);
            if (fp >= 0 && k < 12) out[std::size_t(k++)] = p;
            if ((fp >= 0) != (fq >= 0) && k < 12) out[std::size_t(k++)] = p + (q - p) * (fp / (fp - fq));
        }
        poly = out;
        return k;
    }

    // The convexity bound through the best of the corners' (and the centroid's) nearest triangles;
    // when that is above the accept threshold, also through the triangles of `to` that the corners
    // shared with it lie on (`v`: the piece's vertex indices, for a whole triangle of `from`).
    // `path` gets Exact when the bound is the largest corner distance (then it is the true value).
    float convexBound(const Piece& p, const Corners& n, const Near* c, const std::array<std::uint32_t, 3>* v,
                      Stats::Path* path) const {
        float best = std::numeric_limits<float>::max();
        auto through = [&](std::uint32_t t) {
            float worst = 0.0f;
            for (std::size_t j = 0; j < 3 && worst < best; ++j)
                worst = std::max(worst, n[j].tri == t ? n[j].d : distance(p[j], t));
            best = std::min(best, worst);
        };
        for (const Near& k : n)
            through(k.tri);
        if (c) through(c->tri);
        const float exact = std::max({n[0].d, n[1].d, n[2].d});
        if (v && shared_ && best > exact && best > accept())
            for (std::size_t j = 0; j < 3 && best > exact; ++j) {
                const std::uint32_t* fan = shared_->begin((*v)[j]);
                for (std::size_t k = 0; k < std::min<std::size_t>(shared_->size((*v)[j]), 16); ++k)
                    through(fan[k]);
            }
        if (path) *path = best <= exact ? Stats::Exact : Stats::Convex;
        return best;
    }
    // `inherited`: a bound already known for this piece or one holding it, found by `inheritedPath`.
    // `budget`: the pieces this one may be split into; returns how many it used.
    int refine(const Piece& p, const Corners& n, int depth, float inherited, Stats::Path inheritedPath,
               int budget) {
        float bound = inherited;
        Stats::Path path = depth > 0 ? Stats::Inherited : inheritedPath;
        auto take = [&](float b, Stats::Path w) {
            if (b < bound) bound = b, path = w;
        };
        if (const float thin = thinBound(p, n); thin >= 0.0f) {
            take(thin, Stats::Convex);
            if (bound <= accept()) {
                settle(bound, path, p, depth);
                return 1;
            }
        }
        if (depth > 0) { // the top level tried these before calling
            Stats::Path convex = Stats::Convex;
            take(convexBound(p, n, nullptr, nullptr, &convex), convex);
            if (bound > accept()) {
                const float h = projected(p[0], p[1], p[2]);
                if (h >= 0.0f) take(h, Stats::Projection);
            }
        }
        if (bound > accept()) {
            const glm::vec3 c = centroid(p[0], p[1], p[2]);
            const Near nc = nearest(c);
            const float radius = std::sqrt(std::max(
                {glm::dot(p[0] - c, p[0] - c), glm::dot(p[1] - c, p[1] - c), glm::dot(p[2] - c, p[2] - c)}));
            take(convexBound(p, n, &nc, nullptr, nullptr), Stats::Convex);
            take(nc.d + radius, Stats::Lipschitz);
        }
        if (bound <= accept() || depth == maxDepth || budget < 4) {
            stats_.atMaxDepth += bound > accept();
            settle(bound, path, p, depth);
            return 1;
        }
        return split(p, n, depth, bound, budget);
    }
    // A sliver (the simplifier leaves them along straight borders and on flat parts; splits that
    // cut near a corner make them too): every point is within its height h over the longest edge
    // of that edge, so h plus the edge's bound bounds it. -1 for a piece that is not thin.
    float thinBound(const Piece& p, const Corners& n) {
        std::size_t e = 0;
        for (std::size_t k = 1; k < 3; ++k)
            if (glm::distance(p[k], p[(k + 1) % 3]) > glm::distance(p[e], p[(e + 1) % 3])) e = k;
        const std::size_t i = e, j = (e + 1) % 3, k = (e + 2) % 3;
        const float length = glm::distance(p[i], p[j]);
        const glm::dvec3 a(p[i]);
        const float h = float(glm::length(glm::cross(glm::dvec3(p[j]) - a, glm::dvec3(p[k]) - a)) /
                              std::max(double(length), 1e-30));
        if (!(h <= std::max(1e-4f * length, 0.5f * accept()))) return -1.0f;
        // The angles at the longest edge's ends are acute, so p[k]'s foot on it is inside it.
        segments_ = 0;
        return segmentBound(p[i], n[i], p[j], n[j], 0) + h * (1.0f + 1e-5f);
    }
    // The convexity bound of segment ab, split where its ends' nearest triangles balance.
    float segmentBound(glm::vec3 a, Near na, glm::vec3 b, Near nb, int depth) {
        const float viaA = std::max(na.d, na.tri == nb.tri ? nb.d : distance(b, na.tri)),
                    viaB = std::max(nb.d, distance(a, nb.tri));
        const float bound = std::min(viaA, viaB);
        if (bound <= accept() || depth == 24 || ++segments_ > pieceBudget) return bound;
        const glm::vec3 x = balance(a, b, na.tri, nb.tri);
        const Near nx = nearest(x);
        return std::max(segmentBound(a, na, x, nx, depth + 1), segmentBound(x, nx, b, nb, depth + 1));
    }
    // Splits a piece where its corners' nearest triangles change: on each edge whose ends have
    // different ones (t_i, t_j), at a point where the distances to t_i and t_j balance, so that a
    // child's corners past a crease of `to` are at the true distance from the child's triangle
    // (a simplified reading of Tang, Lee & Kim 2009's Voronoi subdivision). Any cut point keeps
    // the children a cover of the piece; the balance only makes them tight. An edge with one
    // triangle at both ends is cut only when no edge has two (then the longest, at its midpoint).
    int split(const Piece& p, const Corners& n, int depth, float bound, int budget) {
        std::array<glm::vec3, 3> x{};
        std::array<Near, 3> nx{};
        std::array<bool, 3> cut{};
        for (std::size_t e = 0; e < 3; ++e) {
            const std::size_t i = e, j = (e + 1) % 3;
            // One end's triangle also nearest to the other end (a shared vertex lies on several):
            // then it serves both, and the edge needs no cut.
            if (n[i].tri == n[j].tri || distance(p[i], n[j].tri) <= n[i].d ||
                distance(p[j], n[i].tri) <= n[j].d)
                continue;
            x[e] = balance(p[i], p[j], n[i].tri, n[j].tri), nx[e] = nearest(x[e]), cut[e] = true;
        }
        if (!cut[0] && !cut[1] && !cut[2]) {
            std::size_t e = 0;
            for (std::size_t k = 1; k < 3; ++k)
                if (glm::distance(p[k], p[(k + 1) % 3]) > glm::distance(p[e], p[(e + 1) % 3])) e = k;
            x[e] = 0.5f * (p[e] + p[(e + 1) % 3]), nx[e] = nearest(x[e]), cut[e] = true;
        }
        const int cuts = int(cut[0]) + int(cut[1]) + int(cut[2]);
        int left = cuts + 1, used = 0; // children still to bound; a child's share of the budget
        auto child = [&](std::size_t a, std::size_t b, std::size_t c) { // 0-2 corners, 3-5 cut points
            auto pt = [&](std::size_t k) { return k < 3 ? p[k] : x[k - 3]; };
            auto nr = [&](std::size_t k) { return k < 3 ? n[k] : nx[k - 3]; };
            used += refine({pt(a), pt(b), pt(c)}, {nr(a), nr(b), nr(c)}, depth + 1, bound, Stats::Inherited,
                           (budget - used) / left--);
        };
        if (cuts == 3) { // the four-triangle pattern (x_e on edge e = (e, e + 1))
            child(0, 3, 5), child(3, 1, 4), child(5, 4, 2), child(3, 4, 5);
            return used;
        }
        for (std::size_t e = 0; e < 3; ++e) {
            const std::size_t i = e, j = (e + 1) % 3, k = (e + 2) % 3;
            if (cuts == 1 && cut[e]) { // two triangles through the opposite corner
                child(i, 3 + e, k), child(3 + e, j, k);
                return used;
            }
            if (cuts == 2 && !cut[e]) { // edge (i, j) uncut: corner k's triangle and the quad's two
                const std::size_t xjk = 3 + j, xki = 3 + k;
                child(k, xki, xjk), child(xki, i, j), child(xki, j, xjk);
                return used;
            }
        }
        return used;
    }
    // A point on segment ab where the distances to triangles ta (nearest to a) and tb (nearest to
    // b) are about equal: d(., ta) - d(., tb) is <= 0 at a and >= 0 at b; regula falsi, Illinois.
    glm::vec3 balance(glm::vec3 a, glm::vec3 b, std::uint32_t ta, std::uint32_t tb) const {
        auto f = [&](float s) {
            const glm::vec3 q = a + s * (b - a);
            return distance(q, ta) - distance(q, tb);
        };
        float s0 = 0.0f, s1 = 1.0f, f0 = f(0.0f), f1 = f(1.0f);
        if (!(f0 < 0.0f && f1 > 0.0f)) return 0.5f * (a + b);
        int side = 0;
        for (int step = 0; step < 4; ++step) {
            const float s = std::clamp((s0 * f1 - s1 * f0) / (f1 - f0), 0.0f, 1.0f), fs = f(s);
            if (fs == 0.0f) return a + s * (b - a);
            if (fs < 0.0f) {
                s0 = s, f0 = fs;
                if (side == -1) f1 *= 0.5f;
                side = -1;
            } else {
                s1 = s, f1 = fs;
                if (side == 1) f0 *= 0.5f;
                side = 1;
            }
        }
        const float s = std::clamp((s0 * f1 - s1 * f0) / (f1 - f0), 0.05f, 0.95f);
        return a + s * (b - a);
    }

    const std::vector<glm::vec3>& corners_;
    const TriangleBvh& bvh_;
    const SharedVertices* shared_;
    float rel_, abs_, floor_;
    float lower_ = 0.0f, upper_ = 0.0f;
    std::uint32_t hint_ = 0;
    int segments_ = 0;
    std::vector<std::array<std::uint32_t, 3>> tris_;
    std::vector<Near> vertices_;
    Stats stats_;
};

std::string refusal(const Geometry& g, const AutoLodOptions& o) {
    if (!meshOptimizerAvailable()) return "sgfx was built without meshoptimizer (libmeshoptimizer-dev)";
    if (g.mode != PrimitiveMode::Triangles || g.indices.empty())
        return "not indexed PrimitiveMode::Triangles";
    if (g.posed() || !g.joints0.empty() || !g.morphTargets.empty()) return "skinned or morphed";
    if (!g.instances.empty()) return "instanced (the LOD's sphere would not hold the instances)";
    if (g.triangleCount() < 2 * std::max<std::size_t>(o.minTriangles, 1)) return "too few triangles";
    if (!std::isfinite(o.errorPixels) || o.errorPixels <= 0.0f || !std::isfinite(o.focalPixels) ||
        o.focalPixels <= 0.0f)
        return "AutoLodOptions errorPixels and focalPixels must be finite and > 0";
    return "";
}

struct BoundExtras {
    float floor = 0.0f;                                               ///< refine no piece below this
    const std::vector<std::uint32_t>*aToB = nullptr, *bToA = nullptr; ///< vertices at identical positions
    HausdorffBoundStats* stats = nullptr;
    bool secondThread = true; ///< a large pair may run one side on a second thread
};

float bound(const Geometry& a, const Geometry& b, float relativeSlack, float absoluteSlack,
            const BoundExtras& x) {
    const auto bvhA = a.triangleBvh(), bvhB = b.triangleBvh();
    SharedVertices sharedAB, sharedBA;
    if (x.aToB) sharedAB = sharedVertices(*bvhB, b.positions.size(), *x.aToB);
    if (x.bToA) sharedBA = sharedVertices(*bvhA, a.positions.size(), *x.bToA);
    OneSidedBound ab(*bvhB, relativeSlack, absoluteSlack, x.floor, x.aToB ? &sharedAB : nullptr),
        ba(*bvhA, relativeSlack, absoluteSlack, x.floor, x.bToA ? &sharedBA : nullptr);
    // The vertex passes first, so each side's threshold starts from both sides' lower bound; then
    // the two sides are independent (they only read the geometries and both BVHs): a large pair
    // runs one on a second thread.
    const float lower = std::max(ab.prepare(a), ba.prepare(b));
    ab.share(lower), ba.share(lower);
    float hab = 0.0f, hba = 0.0f;
    std::thread other;
    std::exception_ptr otherError;
    if (x.secondThread && a.triangleCount() + b.triangleCount() >= 4096) {
        try {
            other = std::thread([&] {
                try {
                    hba = ba.run(b);
                } catch (...) {
                    otherError = std::current_exception();
                }
            });
        } catch (...) { // no thread to be had: both sides on this one
        }
    }
    try {
        hab = ab.run(a);
        if (!other.joinable()) hba = ba.run(b);
    } catch (...) {
        if (other.joinable()) other.join();
        throw;
    }
    if (other.joinable()) other.join();
    if (otherError) std::rethrow_exception(otherError);
    if (x.stats) {
        *x.stats = ab.stats();
        x.stats->add(ba.stats());
        x.stats->sides = {hab, hba};
    }
    const float h = std::max(hab, hba);
    // Float rounding in the distances: a few ulps of the largest coordinate.
    float extent = 0.0f;
    for (const Geometry* g : {&a, &b})
        for (const glm::vec3& p : g->positions)
            extent = std::max({extent, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    return h * (1.0f + 1e-5f) + 8.0f * std::numeric_limits<float>::epsilon() * extent;
}

#if SGFX_HAVE_MESHOPTIMIZER
// A copy of `full` drawing `indices`, with only the vertices they use, in fetch order; `remap`
// gets the copy's vertex of each of full's vertices (~0u where unused).
std::shared_ptr<Geometry> compacted(const Geometry& full, std::vector<unsigned> indices,
                                    std::vector<unsigned>& remap) {
    auto g = Geometry::create();
    g->name = full.name;
    g->setStateSet(full.stateSet());
    const std::size_t n = full.positions.size();
    meshopt_optimizeVertexCache(indices.data(), indices.data(), indices.size(), n);
    remap.assign(n, ~0u);
    const std::size_t used =
        meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), indices.size(), n);
    auto copy = [&](auto& dst, const auto& src) {
        if (src.empty()) return;
        dst.resize(used);
        meshopt_remapVertexBuffer(dst.data(), src.data(), n, sizeof(src[0]), remap.data());
    };
    copy(g->positions, full.positions), copy(g->normals, full.normals), copy(g->tangents, full.tangents);
    copy(g->texcoords, full.texcoords), copy(g->texcoords1, full.texcoords1), copy(g->colors, full.colors);
    meshopt_remapIndexBuffer(indices.data(), indices.data(), indices.size(), remap.data());
    g->indices = std::move(indices);
    return g;
}

// Levels of ½, ¼, ... of full's triangles, each simplified from full, with both errors.
std::vector<AutoLodLevel> simplifiedLevels(const Geometry& full, const AutoLodOptions& o) {
    const std::size_t n = full.indices.size(), vertices = full.positions.size();
    const float* pos = &full.positions[0].x;
    const float scale = meshopt_simplifyScale(pos, vertices, sizeof(glm::vec3));
    // Slack that shrinks a level's largest switching size by at most a fifth (makeErrorLod's ranges).
    const float absSlack = 0.25f * full.bound().radius * o.errorPixels / o.focalPixels;
    std::vector<AutoLodLevel> levels;
    std::size_t previous = n / 3;
    for (std::size_t target = n / 6; target >= o.minTriangles; target /= 2) {
        std::vector<unsigned> out(n);
        float error = 0.0f; // relative; target_error 1 lets the count decide
        out.resize(meshopt_simplify(out.data(), full.indices.data(), n, pos, vertices, sizeof(glm::vec3),
                                    target * 3, 1.0f,
                                    o.lockBorder ? unsigned(meshopt_SimplifyLockBorder) : 0u, &error));
        const std::size_t triangles = out.size() / 3;
        if (triangles < o.minTriangles || 5 * triangles > 4 * previous) break; // stuck or too coarse
        previous = triangles;
        AutoLodLevel level;
        std::vector<unsigned> toLevel, toFull;
        level.geometry = compacted(full, std::move(out), toLevel);
        toFull.assign(level.geometry->positions.size(), ~0u);
        for (std::size_t v = 0; v < toLevel.size(); ++v)
            if (toLevel[v] != ~0u) toFull[toLevel[v]] = unsigned(v);
        level.simplifierError = error * scale;
        // A coarser level's error is rounded up to the finer one's (makeErrorLod): below that, any
        // bound is as good as the exact value.
        const float floor = levels.empty() ? 0.0f : levels.back().measuredError;
        level.measuredError = bound(*level.geometry, full, 0.1f, absSlack,
                                    {floor, &toFull, &toLevel, &level.boundStats, o.threads != 1});
        levels.push_back(std::move(level));
    }
    return levels;
}
#endif

} // namespace

float hausdorffDistance(const Geometry& a, const Geometry& b) {
    const auto bvhA = a.triangleBvh(), bvhB = b.triangleBvh();
    return std::max(oneSided(a, *bvhB), oneSided(b, *bvhA));
}

void HausdorffBoundStats::add(const HausdorffBoundStats& o) {
    for (std::size_t k = 0; k < settled.size(); ++k)
        settled[k] += o.settled[k];
    atMaxDepth += o.atMaxDepth, queries += o.queries, projections += o.projections;
    degenerate += o.degenerate, uncovered += o.uncovered, overlap += o.overlap, cut += o.cut;
    crackMargins += o.crackMargins;
    if (o.upper > upper) worst = o.worst, worstPiece = o.worstPiece, worstDepth = o.worstDepth;
    lower = std::max(lower, o.lower), upper = std::max(upper, o.upper);
}

float hausdorffBound(const Geometry& a, const Geometry& b, float relativeSlack, float absoluteSlack,
                     HausdorffBoundStats* stats) {
    if (!(relativeSlack >= 0.0f) || !(absoluteSlack >= 0.0f) || !std::isfinite(relativeSlack) ||
        !std::isfinite(absoluteSlack))
        throw std::invalid_argument("hausdorffBound: slacks must be finite and >= 0");
    if (triangleIndices(a).empty() || triangleIndices(b).empty())
        throw std::invalid_argument("hausdorffBound: both geometries need triangles");
    return bound(a, b, relativeSlack, absoluteSlack, {0.0f, nullptr, nullptr, stats});
}

std::shared_ptr<LOD> makeErrorLod(const std::shared_ptr<Geometry>& full, const AutoLodOptions& o,
                                  std::vector<AutoLodLevel>* levelsOut, std::string* reason) {
    std::string why = full ? refusal(*full, o) : "no geometry";
    std::vector<AutoLodLevel> levels;
#if SGFX_HAVE_MESHOPTIMIZER
    if (why.empty()) levels = simplifiedLevels(*full, o);
#endif
    if (why.empty() && levels.empty()) why = "no level removes a fifth of the triangles";
    if (reason) *reason = why;
    if (!why.empty()) return nullptr;
    const BoundingSphere sphere = full->bound();
    const float r = std::max(sphere.radius, 1e-6f), f = o.focalPixels;
    // p <= 2f / (1 + e f / (r t)): at p = 2 r f / d an error e seen from the sphere's nearest
    // point, d - r away, spans e f / (d - r) <= t pixels.
    auto largest = [&](float e) { return 2.0f * f / (1.0f + e * f / (r * o.errorPixels)); };
    float e = 0.0f;
    for (AutoLodLevel& level : levels) {
        e = std::max(e, level.measuredError); // an upper bound; meshoptimizer's estimate is not

        level.maxPixels = largest(e);
    }
    auto lod = LOD::create();
    lod->name = full->name + " (auto LOD)";
    lod->setUserSphere(sphere.center, r);
    lod->addChild(full, levels.front().maxPixels, std::numeric_limits<float>::infinity());
    for (std::size_t i = 0; i < levels.size(); ++i) {
        levels[i].minPixels = i + 1 < levels.size() ? levels[i + 1].maxPixels : 0.0f;
        lod->addChild(levels[i].geometry, levels[i].minPixels, levels[i].maxPixels);
    }
    if (levelsOut) *levelsOut = std::move(levels);
    return lod;
}

std::size_t addAutoLods(Node& root, const AutoLodOptions& o) {
    // Where each distinct mesh is drawn, found first; the LODs are then made in parallel (each
    // job touches only its own mesh: its parent list, bound and BVH caches; one job per distinct
    // mesh) and put in place here, on the caller's thread.
    struct Place {
        Group* group;
        std::size_t child, mesh;
    };
    std::vector<std::shared_ptr<Geometry>> meshes;
    std::vector<Place> places;
    std::unordered_map<const Geometry*, std::size_t> index;
    std::unordered_set<const Node*> seen;
    auto visit = [&](auto& self, Node& node) -> void {
        auto* group = dynamic_cast<Group*>(&node);
        if (!group || dynamic_cast<LOD*>(&node) || !seen.insert(&node).second) return;
        for (std::size_t i = 0; i < group->numChildren(); ++i) {
            const NodePtr child = group->child(i);
            if (auto g = std::dynamic_pointer_cast<Geometry>(child)) {
                auto [it, added] = index.emplace(g.get(), meshes.size());
                if (added) meshes.push_back(g);
                places.push_back({group, i, it->second});
            } else if (child) {
                self(self, *child);
            }
        }
    };
    visit(visit, root);
    std::vector<std::size_t> order(meshes.size()); // largest first: the long jobs start early
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return meshes[a]->elementCount() > meshes[b]->elementCount();
    });
    std::vector<std::shared_ptr<LOD>> lods(meshes.size());
    const unsigned threads = o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency());
    AutoLodOptions perMesh = o;
    if (threads > 1 && meshes.size() > 1) perMesh.threads = 1; // the pool's threads are all it uses
    detail::parallelFor(order.size(), threads,
                        [&](std::size_t k) { lods[order[k]] = makeErrorLod(meshes[order[k]], perMesh); });
    for (const Place& p : places)
        if (lods[p.mesh]) p.group->replaceChild(p.child, lods[p.mesh]);
    return std::size_t(std::count_if(lods.begin(), lods.end(), [](const auto& l) { return l != nullptr; }));
}

} // namespace sgfx

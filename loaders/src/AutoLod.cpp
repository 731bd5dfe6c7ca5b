// Levels of detail made at load with meshoptimizer's simplifier, and the independent measure of
// their error that sets their ranges (MeshOptimize.h).
#include "sgfx/MeshOptimize.h"

#include <sgfx/Group.h>
#include <sgfx/Math.h>
#include <sgfx/TriangleBvh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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

// A rigorous upper bound of the one-sided Hausdorff distance from `from` to `to`'s surface, by
// branch and bound over pieces of `from`'s triangles. For a piece with corners p_j, two bounds hold
// for every point q of it: (convexity) q's distance to one triangle t of `to` is a convex function,
// so it is at most max_j dist(p_j, t); (Lipschitz) the distance to a surface changes at most as fast
// as q moves, so it is at most dist(c, to) + max_j |p_j - c| for the centroid c. A piece whose
// smaller bound is within `slack` of the largest distance found at an actual point (a lower bound
// of the result) is done; otherwise it is split in four at its edge midpoints, at most maxDepth
// times (past that, its bound is taken as it is: still an upper bound, only looser).
class OneSidedBound {
public:
    OneSidedBound(const TriangleBvh& to, float relSlack, float absSlack)
        : corners_(to.corners())
        , bvh_(to)
        , rel_(relSlack)
        , abs_(absSlack) {}

    float run(const Geometry& from) {
        const auto tris = triangleIndices(from);
        std::vector<Near> vertices(from.positions.size(), Near{-1.0f, 0});
        for (const auto& t : tris) // vertex distances first: the lower bound then holds them all
            for (std::uint32_t v : t)
                if (vertices[v].d < 0) vertices[v] = nearest(from.positions[v]);
        std::vector<Near> centroids;
        centroids.reserve(tris.size());
        for (const auto& t : tris)
            centroids.push_back(
                nearest(centroid(from.positions[t[0]], from.positions[t[1]], from.positions[t[2]])));
        for (std::size_t i = 0; i < tris.size(); ++i) {
            const auto& t = tris[i];
            const float h = projected(from.positions[t[0]], from.positions[t[1]], from.positions[t[2]]);
            if (h >= 0.0f && h <= lower_ * (1.0f + rel_) + abs_) {
                upper_ = std::max(upper_, h);
                continue;
            }
            refine({from.positions[t[0]], from.positions[t[1]], from.positions[t[2]]},
                   {vertices[t[0]], vertices[t[1]], vertices[t[2]]}, &centroids[i], 0,
                   h >= 0.0f ? h : std::numeric_limits<float>::max());
        }
        return upper_;
    }

private:
    struct Near {
        float d;
        std::uint32_t tri;
    };
    static constexpr int maxDepth = 3;

    static glm::vec3 centroid(glm::vec3 a, glm::vec3 b, glm::vec3 c) { return (a + b + c) / 3.0f; }
    float distance(glm::vec3 p, std::uint32_t t) const {
        return std::sqrt(triangleDistance2(corners_, t, p));
    }
    Near nearest(glm::vec3 p) {
        const float d = std::sqrt(surfaceDistance2(bvh_, p, hint_));
        lower_ = std::max(lower_, d);
        return {d, hint_};
    }
    // The bound along the normal n of triangle abc: every point q of abc is at most |g(q)| from
    // `to`, where g(q) is the signed distance along n to a triangle of `to` whose projection onto
    // abc's plane holds q. g is linear on each triangle's projection clipped to abc (and to |g| <=
    // search), so its largest size is at a corner of those polygons. Valid when the clipped
    // projections, all of one orientation, cover abc (their areas sum to abc's): `to` is a graph
    // over abc there. Returns -1 when they do not (folds, holes, steep parts): the caller refines.
    float projected(glm::vec3 a, glm::vec3 b, glm::vec3 c) const {
        // The search height starts at 4x the largest distance found and grows where the surface
        // is farther (the clip then cuts the cover short).
        float search = std::max(4.0f * lower_, abs_) + 1e-6f * glm::length(b - a);
        for (int attempt = 0; attempt < 2; ++attempt, search *= 8.0f) {
            bool cut = false;
            const float h = projected(a, b, c, search, cut);
            if (h >= 0.0f || !cut) return h;
        }
        return -1.0f;
    }
    // One try at a given search height; `cut` tells whether the height clip removed area.
    float projected(glm::vec3 a, glm::vec3 b, glm::vec3 c, float search, bool& cut) const {
        using D2 = glm::dvec2;
        using D3 = glm::dvec3;
        const D3 A(a), cr = glm::cross(D3(b) - A, D3(c) - A);
        const double len = glm::length(cr);
        if (!(len > 0.0)) return -1.0f;
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
                if (top + 2 > 64) return -1.0f;
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
                for (int k = 0; k < count; ++k)
                    worst[side] = std::max(worst[side], std::abs(poly[std::size_t(k)].z));
            }
        }
        // A little uncovered area (cracks in `to`, rounding) costs a margin: a point q of abc that
        // is r from every covered point has a sector of the disk of radius r about q, of angle at
        // least abc's smallest angle a, uncovered, so r <= sqrt(2 missing / a); add r (Lipschitz).
        // One orientation alone must cover abc (its triangles then form a graph over abc).
        const std::size_t side = covered[0] >= covered[1] ? 0 : 1;
        const double missing = area - covered[side];
        if (missing < -1e-9 * area || missing > 1e-3 * area) return -1.0f;
        const double margin = std::sqrt(2.0 * std::max(missing, 0.0) / smallestAngle(T));
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

    // The convexity bound through the best of the corners' (and centroid's) nearest triangles.
    float convexBound(const std::array<glm::vec3, 3>& p, const std::array<Near, 3>& n, const Near* c) const {
        float best = std::numeric_limits<float>::max();
        for (int k = 0; k < 4; ++k) {
            if (k == 3 && !c) break;
            const std::uint32_t t = k < 3 ? n[std::size_t(k)].tri : c->tri;
            float worst = 0.0f;
            for (std::size_t j = 0; j < 3 && worst < best; ++j)
                worst = std::max(worst, n[j].tri == t ? n[j].d : distance(p[j], t));
            best = std::min(best, worst);
        }
        return best;
    }
    // `inherited`: a bound already known for a piece holding this one.
    void refine(const std::array<glm::vec3, 3>& p, const std::array<Near, 3>& n, const Near* known, int depth,
                float inherited) {
        const float accept = lower_ * (1.0f + rel_) + abs_;
        float bound = std::min(inherited, convexBound(p, n, nullptr));
        if (bound > accept && depth > 0) {
            const float h = projected(p[0], p[1], p[2]);
            if (h >= 0.0f) bound = std::min(bound, h);
        }
        if (bound > accept) {
            const glm::vec3 c = centroid(p[0], p[1], p[2]);
            const Near nc = known ? *known : nearest(c);
            const float radius = std::sqrt(std::max(
                {glm::dot(p[0] - c, p[0] - c), glm::dot(p[1] - c, p[1] - c), glm::dot(p[2] - c, p[2] - c)}));
            bound = std::min({bound, convexBound(p, n, &nc), nc.d + radius});
        }
        if (bound <= lower_ * (1.0f + rel_) + abs_ || depth == maxDepth) {
            upper_ = std::max(upper_, bound);
            return;
        }
        const glm::vec3 m01 = 0.5f * (p[0] + p[1]), m12 = 0.5f * (p[1] + p[2]), m20 = 0.5f * (p[2] + p[0]);
        const Near n01 = nearest(m01), n12 = nearest(m12), n20 = nearest(m20);
        refine({p[0], m01, m20}, {n[0], n01, n20}, nullptr, depth + 1, bound);
        refine({m01, p[1], m12}, {n01, n[1], n12}, nullptr, depth + 1, bound);
        refine({m20, m12, p[2]}, {n20, n12, n[2]}, nullptr, depth + 1, bound);
        refine({m01, m12, m20}, {n01, n12, n20}, nullptr, depth + 1, bound);
    }

    const std::vector<glm::vec3>& corners_;
    const TriangleBvh& bvh_;
    float rel_, abs_;
    float lower_ = 0.0f, upper_ = 0.0f;
    std::uint32_t hint_ = 0;
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

#if SGFX_HAVE_MESHOPTIMIZER
// A copy of `full` drawing `indices`, with only the vertices they use, in fetch order.
std::shared_ptr<Geometry> compacted(const Geometry& full, std::vector<unsigned> indices) {
    auto g = Geometry::create();
    g->name = full.name;
    g->setStateSet(full.stateSet());
    const std::size_t n = full.positions.size();
    meshopt_optimizeVertexCache(indices.data(), indices.data(), indices.size(), n);
    std::vector<unsigned> remap(n);
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
        level.geometry = compacted(full, std::move(out));
        level.simplifierError = error * scale;
        level.measuredError = hausdorffBound(*level.geometry, full, 0.1f, absSlack);
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

float hausdorffBound(const Geometry& a, const Geometry& b, float relativeSlack, float absoluteSlack) {
    if (!(relativeSlack >= 0.0f) || !(absoluteSlack >= 0.0f) || !std::isfinite(relativeSlack) ||
        !std::isfinite(absoluteSlack))
        throw std::invalid_argument("hausdorffBound: slacks must be finite and >= 0");
    if (triangleIndices(a).empty() || triangleIndices(b).empty())
        throw std::invalid_argument("hausdorffBound: both geometries need triangles");
    const auto bvhA = a.triangleBvh(), bvhB = b.triangleBvh();
    OneSidedBound ab(*bvhB, relativeSlack, absoluteSlack), ba(*bvhA, relativeSlack, absoluteSlack);
    // The two sides are independent (they only read the geometries and both BVHs, built above): a
    // large pair runs one on a second thread.
    float hab = 0.0f, hba = 0.0f;
    if (a.triangleCount() + b.triangleCount() >= 4096) {
        std::thread other([&] { hba = ba.run(b); });
        hab = ab.run(a);
        other.join();
    } else {
        hab = ab.run(a), hba = ba.run(b);
    }
    const float h = std::max(hab, hba);
    // Float rounding in the distances: a few ulps of the largest coordinate.
    float extent = 0.0f;
    for (const Geometry* g : {&a, &b})
        for (const glm::vec3& p : g->positions)
            extent = std::max({extent, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    return h * (1.0f + 1e-5f) + 8.0f * std::numeric_limits<float>::epsilon() * extent;
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
    std::unordered_map<const Geometry*, std::shared_ptr<LOD>> made;
    std::unordered_set<const Node*> seen;
    std::size_t count = 0;
    auto visit = [&](auto& self, Node& node) -> void {
        auto* group = dynamic_cast<Group*>(&node);
        if (!group || dynamic_cast<LOD*>(&node) || !seen.insert(&node).second) return;
        for (std::size_t i = 0; i < group->numChildren(); ++i) {
            const NodePtr child = group->child(i);
            if (auto g = std::dynamic_pointer_cast<Geometry>(child)) {
                auto [it, added] = made.emplace(g.get(), nullptr);
                if (added) {
                    it->second = makeErrorLod(g, o);
                    count += it->second != nullptr;
                }
                if (it->second) group->replaceChild(i, it->second);
            } else if (child) {
                self(self, *child);
            }
        }
    };
    visit(visit, root);
    return count;
}

} // namespace sgfx

// 10^4 random rays on the proving ground against a brute-force reference: every triangle of the
// scene in world space, its own traversal (dynamic_cast, no NodeVisitor), and a plane-then-edge-
// signs test in place of the queries' Möller–Trumbore over a BVH.
#include "PolygonScene.h"

#include <sgfx/Billboard.h>
#include <sgfx/Camera.h>
#include <sgfx/Drawable.h>
#include <sgfx/Geometry.h>
#include <sgfx/Intersection.h>
#include <sgfx/LOD.h>
#include <sgfx/Queries.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <random>

using namespace sgfx;
using namespace polygon;

namespace {

struct WorldTriangle {
    glm::dvec3 a, b, c;
    const Geometry* geometry;
    std::uint32_t primitive, instance;
};

// The finest level of every LOD (the children with the greatest upper range bound), billboards
// in their rest pose, no drawables, no render-to-texture cameras: what the visitor's defaults hit.
void collect(const Node& node, const glm::dmat4& m, std::vector<WorldTriangle>& out) {
    if (auto* g = dynamic_cast<const Geometry*>(&node)) {
        const auto tris = triangleIndices(*g);
        for (std::size_t i = 0; i < g->instanceCount(); ++i) {
            const glm::dmat4 w = g->instances.empty() ? m : m * glm::dmat4(g->instances[i]);
            for (std::size_t t = 0; t < tris.size(); ++t) {
                auto p = [&](int k) {
                    return glm::dvec3(w * glm::dvec4(glm::dvec3(g->positions[tris[t][k]]), 1.0));
                };
                out.push_back({p(0), p(1), p(2), g, std::uint32_t(t), std::uint32_t(i)});
            }
        }
        return;
    }
    if (dynamic_cast<const Drawable*>(&node)) return;
    if (auto* cam = dynamic_cast<const Camera*>(&node); cam && cam->renderTarget) return;
    auto* group = dynamic_cast<const Group*>(&node);
    if (!group) return;
    const glm::dmat4 inner = dynamic_cast<const Transform*>(&node)
                                 ? m * glm::dmat4(static_cast<const Transform&>(node).matrix())
                                 : m;
    auto* lod = dynamic_cast<const LOD*>(&node);
    float top = -1.0f;
    if (lod)
        for (const auto& r : lod->ranges())
            top = std::max(top, r.maxPixels);
    for (std::size_t i = 0; i < group->numChildren(); ++i)
        if (!lod || lod->range(i).maxPixels == top) collect(*group->child(i), inner, out);
}

struct RefHit {
    double t = std::numeric_limits<double>::infinity();
    const WorldTriangle* tri = nullptr;
};

// The plane of the triangle, then the point's side of each edge (both windings accepted).
RefHit bruteForce(const std::vector<WorldTriangle>& tris, const glm::dvec3& o, const glm::dvec3& d) {
    RefHit best;
    for (const WorldTriangle& w : tris) {
        const glm::dvec3 n = glm::cross(w.b - w.a, w.c - w.a);
        const double den = glm::dot(n, d);
        if (den == 0.0) continue;
        const double t = glm::dot(n, w.a - o) / den;
        if (t < 0.0 || t > 1.0 || t >= best.t) continue;
        const glm::dvec3 p = o + t * d;
        const double s0 = glm::dot(glm::cross(w.b - w.a, p - w.a), n);
        const double s1 = glm::dot(glm::cross(w.c - w.b, p - w.b), n);
        const double s2 = glm::dot(glm::cross(w.a - w.c, p - w.c), n);
        if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0)) best = {t, &w};
    }
    return best;
}

} // namespace

TEST(QueryReference, TenThousandRaysMatchBruteForce) {
    SceneOptions options;
    options.scale = 0.25f; // the brute force tests every triangle for every ray
    const PolygonScene scene = buildPolygonScene(options);
    std::vector<WorldTriangle> tris;
    collect(*scene.root, glm::dmat4(1.0), tris);
    ASSERT_GT(tris.size(), 10000u);
    prepareForQueries(*scene.root);

    const BoundingSphere& s = scene.root->bound();
    const glm::dvec3 c(s.center);
    const double r = s.radius;
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int hits = 0, ties = 0, rays = 10000;
    double worst = 0.0;
    for (int k = 0; k < rays; ++k) {
        glm::dvec3 o, e;
        if (k % 2 == 0) { // vertical, over the ground: terrain following
            const double x = c.x + 0.4 * r * u(rng), y = c.y + 0.4 * r * u(rng);
            o = {x, y, c.z + r};
            e = {x, y, c.z - r};
        } else { // from a point near the ground in a random direction, across the scene
            o = c + glm::dvec3(0.4 * r * u(rng), 0.4 * r * u(rng), 0.02 * r * (1.0 + u(rng)));
            glm::dvec3 d(u(rng), u(rng), 0.3 * u(rng));
            e = o + glm::normalize(d) * r;
        }
        const RefHit ref = bruteForce(tris, o, e - o);
        LineSegmentIntersector line(o, e);
        line.limit = Intersector::Limit::Nearest;
        IntersectionVisitor iv(line);
        iv.visit(*scene.root);
        ASSERT_EQ(ref.tri != nullptr, line.nearest() != nullptr) << "ray " << k << ": hit and miss disagree";
        if (!ref.tri) continue;
        ++hits;
        const Intersection& h = *line.nearest();
        const glm::dvec3 refPoint = o + ref.t * (e - o);
        const double error = glm::length(h.point - refPoint) / r;
        EXPECT_LT(error, 1e-6) << "ray " << k << ": hit at t = " << h.ratio << " on '" << h.geometry->name
                               << "', the reference at t = " << ref.t << " on '" << ref.tri->geometry->name
                               << "'";
        worst = std::max(worst, error);
        if (h.geometry != ref.tri->geometry || h.primitiveIndex != ref.tri->primitive ||
            h.instanceIndex != ref.tri->instance) {
            // Two triangles at the same distance (a shared edge, coplanar overlap): either is right.
            EXPECT_NEAR(h.ratio, ref.t, 1e-9) << "ray " << k << ": a different triangle, farther";
            ++ties;
        }
    }
    std::printf("QUERY_REFERENCE rays=%d hits=%d ties=%d worst_relative_error=%.3g triangles=%zu\n", rays,
                hits, ties, worst, tris.size());
    EXPECT_LT(worst, 1e-6);
    EXPECT_GT(hits, rays / 2) << "most rays meet the ground";
    EXPECT_LT(ties, rays / 100);
}

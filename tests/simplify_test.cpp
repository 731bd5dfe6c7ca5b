// Decimated levels of detail: triangle counts, distance to the original surface both ways,
// carried attributes, the LOD that makeLod builds, and refused input.
#include <sgfx/Camera.h>
#include <sgfx/CullVisitor.h>
#include <sgfx/Math.h>
#include <sgfx/Shapes.h>
#include <sgfx/Simplify.h>
#include <sgfx/StateSet.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

using namespace sgfx;

namespace {

// Largest distance from a vertex of `from` to the surface of `to` (one side of Hausdorff).
float oneSidedHausdorff(const Geometry& from, const Geometry& to) {
    float worst = 0.0f;
    for (const glm::vec3& p : from.positions) {
        float best = std::numeric_limits<float>::max();
        for (std::size_t k = 0; k + 2 < to.indices.size(); k += 3) {
            const glm::vec3 a = to.positions[to.indices[k]], b = to.positions[to.indices[k + 1]],
                            c = to.positions[to.indices[k + 2]];
            const glm::vec3 w = closestOnTriangle(p, a, b, c);
            const glm::vec3 q = w.x * a + w.y * b + w.z * c;
            best = std::min(best, glm::length(p - q));
        }
        worst = std::max(worst, best);
    }
    return worst;
}

} // namespace

// The closed form in Math.h against a dense barycentric grid (no shared shortcut): the closed
// form's point lies on the triangle and is never farther than the grid's best, and the grid's
// best is within its spacing of it. Points fall in every Voronoi region (vertices, edges, face).
template <class V> void expectClosestMatchesGrid(std::uint32_t seed) {
    std::uint32_t state = seed;
    auto next = [&state] {
        state = state * 1664525u + 1013904223u;
        return double(state >> 8) / double(1u << 24) * 4.0 - 2.0;
    };
    constexpr int n = 120;
    for (int trial = 0; trial < 60; ++trial) {
        const V a(next(), next(), next()), b(next(), next(), next()), c(next(), next(), next());
        const V p(next() * 2, next() * 2, next() * 2);
        const V w = closestOnTriangle(p, a, b, c);
        ASSERT_NEAR(double(w.x + w.y + w.z), 1.0, 1e-5) << "trial " << trial;
        ASSERT_GE(double(std::min({w.x, w.y, w.z})), -1e-5) << "trial " << trial;
        const double closed = double(glm::length(p - (w.x * a + w.y * b + w.z * c)));
        double grid = std::numeric_limits<double>::max();
        for (int i = 0; i <= n; ++i)
            for (int j = 0; i + j <= n; ++j) {
                const double u = double(i) / n, v = double(j) / n;
                const glm::dvec3 q = (1 - u - v) * glm::dvec3(a) + u * glm::dvec3(b) + v * glm::dvec3(c);
                grid = std::min(grid, glm::length(glm::dvec3(p) - q));
            }
        const double spacing = std::max({glm::length(glm::dvec3(b - a)), glm::length(glm::dvec3(c - a)),
                                         glm::length(glm::dvec3(c - b))}) /
                               n;
        EXPECT_LE(closed, grid + 1e-5) << "trial " << trial;
        EXPECT_GE(closed, grid - spacing) << "trial " << trial;
    }
}

TEST(Simplify, ClosestPointOnTriangleMatchesADenseGrid) {
    expectClosestMatchesGrid<glm::vec3>(7);
    expectClosestMatchesGrid<glm::dvec3>(11);
}

TEST(Simplify, TriangleCountsFollowTheRatios) {
    for (bool uv : {true, false}) {
        auto sphere = shapes::sphere(1.0f, 64, 32); // 4096 triangles
        if (!uv) {
            sphere->texcoords.clear();
            sphere->tangents.clear();
        }
        const float ratios[] = {0.12f, 0.5f, 0.25f, 1.0f}; // any order
        const auto levels = simplify(*sphere, ratios);
        ASSERT_EQ(levels.size(), 4u);
        for (std::size_t i = 0; i < 4; ++i) {
            const double target = ratios[i] * double(sphere->triangleCount());
            EXPECT_NEAR(double(levels[i]->triangleCount()), target, 0.03 * target)
                << "ratio " << ratios[i] << (uv ? " with" : " without") << " texcoords";
            EXPECT_NO_THROW(levels[i]->validate());
            EXPECT_EQ(levels[i]->normals.size(), levels[i]->positions.size());
            EXPECT_EQ(levels[i]->texcoords.size(), uv ? levels[i]->positions.size() : 0u);
        }
        EXPECT_EQ(levels[3]->positions, sphere->positions); // ratio 1: unchanged
    }
}

TEST(Simplify, DecimatedSphereStaysOnTheOriginalSurface) {
    auto sphere = shapes::sphere(1.0f, 48, 24);
    const float ratios[] = {0.5f, 0.25f};
    const auto levels = simplify(*sphere, ratios);
    // Both ways: new vertices lie on the old surface (half-edge collapses keep a subset of the
    // vertices, so exactly), and the old vertices near the new one: measured 0.016 and 0.034 for
    // this radius-1 sphere, whose seam and poles are locked.
    const float bounds[] = {0.025f, 0.05f};
    for (std::size_t i = 0; i < 2; ++i) {
        const float there = oneSidedHausdorff(*levels[i], *sphere);
        const float back = oneSidedHausdorff(*sphere, *levels[i]);
        EXPECT_LT(there, bounds[i]) << "ratio " << ratios[i];
        EXPECT_LT(back, bounds[i]) << "ratio " << ratios[i];
        // Smooth normals: close to the radial direction.
        for (std::size_t v = 0; v < levels[i]->positions.size(); ++v)
            EXPECT_GT(glm::dot(levels[i]->normals[v], glm::normalize(levels[i]->positions[v])), 0.97f);
        // Texcoords carried: u and v still follow the position (v = polar angle / pi).
        for (std::size_t v = 0; v < levels[i]->positions.size(); ++v) {
            const float theta = std::acos(std::clamp(levels[i]->positions[v].z, -1.0f, 1.0f));
            EXPECT_NEAR(levels[i]->texcoords[v].y, theta / glm::pi<float>(), 0.02f);
        }
    }
}

TEST(Simplify, MakeLodSwitchesAtTheThresholds) {
    auto sphere = shapes::sphere(1.0f, 64, 32);
    sphere->name = "ball";
    sphere->getOrCreateStateSet();
    auto lod = makeLod(sphere); // 300 px and 100 px
    ASSERT_EQ(lod->numChildren(), 3u);
    EXPECT_EQ(lod->child(0), sphere);
    EXPECT_EQ(lod->child(1)->stateSet(), sphere->stateSet());
    EXPECT_EQ(lod->range(0).minPixels, 300.0f);
    EXPECT_EQ(lod->range(1).maxPixels, 300.0f);
    EXPECT_EQ(lod->range(2).maxPixels, 100.0f);

    // 90°, 1000 px tall: the radius-1 bound is 1000/d pixels across.
    auto cam = Camera::create();
    cam->setViewport(0, 0, 1000, 1000);
    cam->setPerspective(90.0f, 0.1f, 1000.0f);
    cam->addChild(lod);
    auto drawn = [&](float d) {
        cam->setLookAt({0, -d, 0}, {0, 0, 0});
        RenderQueue q;
        CullVisitor cv(*cam, q);
        cv.run(*cam);
        EXPECT_EQ(q.opaque.size(), 1u);
        return q.opaque.empty() ? nullptr : q.opaque.front().geometry;
    };
    EXPECT_EQ(drawn(1000.0f / 300.0f * 0.99f), lod->child(0).get());
    EXPECT_EQ(drawn(1000.0f / 300.0f * 1.01f), lod->child(1).get());
    EXPECT_EQ(drawn(1000.0f / 100.0f * 0.99f), lod->child(1).get());
    EXPECT_EQ(drawn(1000.0f / 100.0f * 1.01f), lod->child(2).get());
    for (std::size_t i = 1; i < 3; ++i) {
        const double target = (i == 1 ? 0.5 : 0.12) * 4096;
        EXPECT_NEAR(double(static_cast<const Geometry&>(*lod->child(i)).triangleCount()), target,
                    0.03 * target);
    }
}

TEST(Simplify, BadInputIsRefusedWithAClearMessage) {
    auto sphere = shapes::sphere(1.0f, 8, 4);
    sphere->name = "ball";
    auto expectRefused = [](auto&& f, const std::string& part) {
        try {
            f();
            ADD_FAILURE() << "no exception for " << part;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
        }
    };
    for (float r : {0.0f, -0.5f, 1.5f, std::numeric_limits<float>::quiet_NaN()})
        expectRefused([&] { simplify(*sphere, r); }, "ratio");
    auto lines = Geometry::create();
    lines->name = "wire";
    lines->positions = {{0, 0, 0}, {1, 0, 0}};
    lines->mode = PrimitiveMode::Lines;
    expectRefused([&] { simplify(*lines, 0.5f); }, "'wire' is not PrimitiveMode::Triangles");
    auto broken = shapes::sphere(1.0f, 8, 4);
    broken->indices.push_back(9999);
    expectRefused([&] { simplify(*broken, 0.5f); }, "out of range");
    const LodLevel unordered[] = {{1.0f, 100.0f}, {0.5f, 300.0f}};
    expectRefused([&] { makeLod(sphere, unordered); }, "level 1");
    const LodLevel badRatio[] = {{1.0f, 100.0f}, {0.0f, 10.0f}};
    expectRefused([&] { makeLod(sphere, badRatio); }, "ratio");
    EXPECT_THROW(makeLod(nullptr), std::invalid_argument);
}

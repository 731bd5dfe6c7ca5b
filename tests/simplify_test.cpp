// Decimated levels of detail: triangle counts, distance to the original surface both ways,
// carried attributes, the LOD that makeLod builds, and refused input.
#include <sgfx/Camera.h>
#include <sgfx/CullVisitor.h>
#include <sgfx/Shapes.h>
#include <sgfx/Simplify.h>
#include <sgfx/StateSet.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace sgfx;

namespace {

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
glm::vec3 closestOnTriangle(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const glm::vec3 bp = p - b;
    const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
    const glm::vec3 cp = p - c;
    const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const float denom = 1.0f / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

// Largest distance from a vertex of `from` to the surface of `to` (one side of Hausdorff).
float oneSidedHausdorff(const Geometry& from, const Geometry& to) {
    float worst = 0.0f;
    for (const glm::vec3& p : from.positions) {
        float best = std::numeric_limits<float>::max();
        for (std::size_t k = 0; k + 2 < to.indices.size(); k += 3) {
            const glm::vec3 q =
                closestOnTriangle(p, to.positions[to.indices[k]], to.positions[to.indices[k + 1]],
                                  to.positions[to.indices[k + 2]]);
            best = std::min(best, glm::length(p - q));
        }
        worst = std::max(worst, best);
    }
    return worst;
}

} // namespace

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

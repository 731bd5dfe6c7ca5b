// Levels of detail made at load (MeshOptimize.h's makeErrorLod): at each level's switching size its
// silhouette stays within a pixel of full detail's, its open border is full detail's, the sampled
// Hausdorff distance is right on an analytic case, and a shared mesh gets one LOD.
#include "TestUtil.h"

#include "../loaders/src/ParallelFor.h"

#include <sgfx/GltfLoader.h>
#include <sgfx/Group.h>
#include <sgfx/MeshOptimize.h>
#include <sgfx/Shapes.h>
#include <sgfx/StateSet.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <atomic>
#include <map>
#include <stdexcept>
#include <set>
#include <utility>

using namespace sgfx;

namespace {

// A sphere with bumps (so simplification has real error), its order optimized as a load would.
std::shared_ptr<Geometry> bumpySphere() {
    auto g = shapes::sphere(1.0f, 64, 32);
    for (glm::vec3& p : g->positions)
        p *= 1.0f + 0.06f * std::sin(5.0f * p.x) * std::sin(4.0f * p.y) * std::sin(3.0f * p.z);
    EXPECT_TRUE(optimizeMesh(*g));
    return g;
}

// Where `geometry`, drawn white and unlit on black, covers the 128x128 view from `eye`, plus a
// one-pixel margin on each side (130x130, the same focal length), so that a pixel on the 128-pixel
// image's border has all its neighbours.
constexpr int kMask = 130;
std::vector<bool> mask(const std::shared_ptr<Geometry>& geometry, glm::vec3 eye, float fovy) {
    auto viewer = Viewer::createHeadless(kMask, kMask);
    auto& cam = *viewer->camera();
    cam.setLookAt(eye, {0, 0, 0}, {0, 0, 1});
    const float widened = 2.0f * std::atan(std::tan(0.5f * fovy) * float(kMask) / 128.0f);
    cam.projectionMatrix = glm::perspective(widened, 1.0f, 0.05f, 100.0f);
    cam.clearColor = {0, 0, 0, 1};
    auto m = Material::create();
    m->model = ShadingModel::Unlit;
    m->diffuse = {1, 1, 1, 1};
    auto state = StateSet::create();
    state->material.set(m);
    auto root = Group::create();
    root->setStateSet(state);
    root->addChild(geometry);
    viewer->setSceneData(root);
    viewer->frame();
    const Image img = viewer->capture();
    std::vector<bool> out(kMask * kMask);
    for (int y = 0; y < kMask; ++y)
        for (int x = 0; x < kMask; ++x)
            out[std::size_t(y * kMask + x)] = img.pixel(x, y)[1] >= 128;
    return out;
}

// Edges used by one triangle, as pairs of positions (so UV seams do not count).
std::set<std::pair<std::array<float, 3>, std::array<float, 3>>> borderEdges(const Geometry& g) {
    std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, int> uses;
    auto key = [&](std::uint32_t i) {
        return std::array<float, 3>{g.positions[i].x, g.positions[i].y, g.positions[i].z};
    };
    for (std::size_t k = 0; k + 2 < g.indices.size(); k += 3)
        for (int e = 0; e < 3; ++e) {
            auto a = key(g.indices[k + std::size_t(e)]), b = key(g.indices[k + std::size_t((e + 1) % 3)]);
            if (b < a) std::swap(a, b);
            ++uses[{a, b}];
        }
    std::set<std::pair<std::array<float, 3>, std::array<float, 3>>> out;
    for (const auto& [edge, n] : uses)
        if (n == 1) out.insert(edge);
    return out;
}

// Distance from p to triangle abc in double, by another route than the library's (Ericson's
// regions): the plane's foot point if it is inside, else the nearest of the three edges.
double referenceDistance(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    auto segment = [](glm::dvec3 q, glm::dvec3 s, glm::dvec3 e) {
        const glm::dvec3 d = e - s;
        const double t = glm::dot(d, d) > 0 ? std::clamp(glm::dot(q - s, d) / glm::dot(d, d), 0.0, 1.0) : 0.0;
        return glm::length(q - (s + t * d));
    };
    const glm::dvec3 n = glm::cross(b - a, c - a);
    if (glm::dot(n, n) > 0) {
        const glm::dvec3 f = p - n * (glm::dot(p - a, n) / glm::dot(n, n));
        const bool inside = glm::dot(glm::cross(b - a, f - a), n) >= 0 &&
                            glm::dot(glm::cross(c - b, f - b), n) >= 0 &&
                            glm::dot(glm::cross(a - c, f - c), n) >= 0;
        if (inside) return glm::length(p - f);
    }
    return std::min({segment(p, a, b), segment(p, b, c), segment(p, c, a)});
}

// A brute-force lower bound of the one-sided Hausdorff distance from `from` to `to`: the largest
// distance, to every triangle of `to`, from a grid of k(k+3)/2+1 points on each triangle of `from`.
// Every sample is a real point, so the true distance is at least this.
double bruteForceLower(const Geometry& from, const Geometry& to, int k) {
    double worst = 0.0;
    for (std::size_t i = 0; i + 2 < from.indices.size(); i += 3) {
        const glm::dvec3 a = from.positions[from.indices[i]], b = from.positions[from.indices[i + 1]],
                         c = from.positions[from.indices[i + 2]];
        for (int u = 0; u <= k; ++u)
            for (int v = 0; u + v <= k; ++v) {
                const glm::dvec3 p = a + (b - a) * (double(u) / k) + (c - a) * (double(v) / k);
                double best = 1e300;
                for (std::size_t j = 0; j + 2 < to.indices.size() && best > worst; j += 3)
                    best = std::min(best, referenceDistance(p, to.positions[to.indices[j]],
                                                            to.positions[to.indices[j + 1]],
                                                            to.positions[to.indices[j + 2]]));
                worst = std::max(worst, best);
            }
    }
    return worst;
}

} // namespace

TEST(AutoLod, ErrorBoundNeverUnderEstimatesBruteForce) {
    ASSERT_TRUE(meshOptimizerAvailable());
    auto sphere = shapes::sphere(1.0f, 24, 12);
    for (glm::vec3& p : sphere->positions)
        p *= 1.0f + 0.08f * std::sin(5.0f * p.x) * std::sin(4.0f * p.y) * std::sin(3.0f * p.z);
    ASSERT_TRUE(optimizeMesh(*sphere));
    auto terrain = shapes::heightfield(-1, -1, 2, 2, 16, 16, [](float x, float y) {
        return 0.2f * std::sin(3.0f * x) * std::cos(2.0f * y) + (x > 0.3f ? 0.15f : 0.0f); // with a step
    });
    ASSERT_TRUE(optimizeMesh(*terrain));
    std::vector<std::shared_ptr<Geometry>> meshes{sphere, terrain};
    const std::filesystem::path duck = SGFX_SOURCE_DIR "/../shared/assets/gltf/Duck/glTF-Binary/Duck.glb";
    ASSERT_TRUE(std::filesystem::exists(duck)) << duck;
    const auto duckRoot = loadGltf(duck);
    std::vector<std::shared_ptr<Geometry>> found;
    auto collect = [&](auto& self, const NodePtr& n) -> void {
        if (auto g = std::dynamic_pointer_cast<Geometry>(n)) found.push_back(g);
        if (auto grp = std::dynamic_pointer_cast<Group>(n))
            for (std::size_t i = 0; i < grp->numChildren(); ++i)
                self(self, grp->child(i));
    };
    collect(collect, duckRoot);
    ASSERT_EQ(found.size(), 1u);
    meshes.push_back(found[0]);
    AutoLodOptions options;
    options.minTriangles = 48;
    int underEstimatedByMeshopt = 0, tooSmallCaught = 0, checked = 0;
    for (const auto& full : meshes) {
        std::vector<AutoLodLevel> levels;
        std::string why;
        ASSERT_TRUE(makeErrorLod(full, options, &levels, &why)) << why;
        // The duck's finer levels would make the brute force slow: its coarsest is checked.
        const bool duckMesh = full == found[0];
        const std::size_t first = duckMesh ? levels.size() - 1 : 0;
        for (std::size_t i = first; i < levels.size(); ++i) {
            const Geometry& s = *levels[i].geometry;
            const double lower =
                std::max(bruteForceLower(s, *full, duckMesh ? 2 : 4), bruteForceLower(*full, s, 1));
            EXPECT_GE(double(levels[i].measuredError), lower) << full->name << " level " << i;
            EXPECT_GE(double(hausdorffBound(s, *full)), lower) << full->name << " level " << i;
            // The same check catches a measure that is not a bound: meshoptimizer's estimate.
            underEstimatedByMeshopt += double(levels[i].simplifierError) < lower;
            // ... and a bound made 10 % smaller, on the levels where the bound is tight.
            tooSmallCaught += 0.9 * double(levels[i].measuredError) < lower;
            ++checked;
            std::printf("%s %zu triangles: bound %.4f, brute-force lower %.4f, meshopt %.4f\n",
                        full->name.c_str(), s.triangleCount(), levels[i].measuredError, lower,
                        levels[i].simplifierError);
        }
    }
    EXPECT_GE(checked, 6);
    EXPECT_GT(underEstimatedByMeshopt, 0);
    EXPECT_GE(tooSmallCaught, 3);
    EXPECT_THROW(hausdorffBound(*sphere, *terrain, -1.0f), std::invalid_argument);
}

TEST(AutoLod, SilhouetteStaysWithinAPixelAtEachSwitch) {
    ASSERT_TRUE(meshOptimizerAvailable());
    const auto full = bumpySphere();
    const float fovy = glm::radians(40.0f);
    AutoLodOptions options;
    options.focalPixels = 64.0f / std::tan(0.5f * fovy); // the test's own view: the tight case
    std::vector<AutoLodLevel> levels;
    std::string why;
    const auto lod = makeErrorLod(full, options, &levels, &why);
    ASSERT_TRUE(lod) << why;
    ASSERT_GE(levels.size(), 3u);
    const float r = lod->userSphere()->radius;
    int checkedLevels = 0;
    for (std::size_t i = 0; i < levels.size(); ++i) {
        EXPECT_EQ(lod->child(i + 1), levels[i].geometry);
        EXPECT_EQ(lod->range(i + 1).maxPixels, levels[i].maxPixels);
        EXPECT_GE(levels[i].measuredError, 0.0f);
        // Just inside the level's range: p = 2 r f / d.
        const float p = 0.999f * levels[i].maxPixels, d = 2.0f * r * options.focalPixels / p;
        if (d > 50.0f) continue; // beyond the far plane: the sphere is a dot
        ++checkedLevels;
        const glm::vec3 eye = d * glm::normalize(glm::vec3(0.8f, -0.5f, 0.3f));
        const auto a = mask(full, eye, fovy), b = mask(levels[i].geometry, eye, fovy);
        int differing = 0, covered = 0;
        for (int y = 1; y <= 128; ++y) // the 128x128 image inside the margin
            for (int x = 1; x <= 128; ++x) {
                const auto at = [&](int u, int v) { return std::size_t(v * kMask + u); };
                covered += a[at(x, y)];
                if (a[at(x, y)] == b[at(x, y)]) continue;
                ++differing;
                bool nearEdge = false; // full detail's coverage changes within one pixel
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                        nearEdge = nearEdge || a[at(x + dx, y + dy)] != a[at(x, y)];
                EXPECT_TRUE(nearEdge) << "level " << i << " pixel " << x << "," << y;
            }
        EXPECT_GT(covered, 20) << "level " << i;
        std::printf(
            "level %zu: %zu triangles, errors %.4f (meshopt) %.4f (measured), %.1f px, %d pixels differ\n",
            i + 1, levels[i].geometry->triangleCount(), levels[i].simplifierError, levels[i].measuredError,
            levels[i].maxPixels, differing);
    }
    EXPECT_GE(checkedLevels, 3);
}

// A 10 m tile of gentle waves with a 0.15 m curb rising over one cell: the bound that sets each
// level's range stays within the slack of an independent brute-force lower bound (the looseness
// was several times that before the bound split pieces where their nearest triangles change).
TEST(AutoLod, BoundIsTightOnCurbs) {
    ASSERT_TRUE(meshOptimizerAvailable());
    const float cell = 10.0f / 24.0f;
    auto tile = shapes::heightfield(-5, -5, 10, 10, 24, 24, [&](float x, float y) {
        return 0.3f * std::sin(0.6f * x) * std::cos(0.5f * y) +
               0.15f * std::clamp((x - 1.0f) / cell, 0.0f, 1.0f);
    });
    ASSERT_TRUE(optimizeMesh(*tile));
    AutoLodOptions options;
    std::vector<AutoLodLevel> levels;
    std::string why;
    ASSERT_TRUE(makeErrorLod(tile, options, &levels, &why)) << why;
    ASSERT_GE(levels.size(), 3u);
    const double absSlack = 0.25 * tile->bound().radius * options.errorPixels / options.focalPixels;
    double finer = 0.0;
    for (std::size_t i = 0; i < levels.size(); ++i) {
        const Geometry& s = *levels[i].geometry;
        const double lower = std::max(bruteForceLower(s, *tile, 4), bruteForceLower(*tile, s, 2));
        const double bound = levels[i].measuredError;
        EXPECT_GE(bound, lower) << "level " << i;
        // The bound may stop refining at 1.1 x its own lower bound + absSlack, or below the finer
        // level's error (which makeErrorLod rounds this one up to anyway); 1.25 leaves room for the
        // brute force's grid missing the worst point by a little.
        EXPECT_LE(bound, std::max(1.25 * lower + absSlack, finer) * (1.0 + 1e-4)) << "level " << i;
        std::printf("curb tile %zu triangles: bound %.4f, brute-force lower %.4f, slack %.4f\n",
                    s.triangleCount(), bound, lower, absSlack);
        finer = std::max(finer, bound);
    }
}

// The generic path (no shared vertices) on folds and 90-degree creases: a box against itself turned
// by 3 degrees, a coarse sphere against itself shifted, never under the brute-force lower bound.
TEST(AutoLod, BoundHoldsOnFoldsAndCreases) {
    auto box = shapes::box({1, 1, 1}), turned = box->clone();
    const glm::mat3 r(glm::rotate(glm::mat4(1), glm::radians(3.0f), glm::normalize(glm::vec3(1, 2, 3))));
    for (glm::vec3& p : turned->positions)
        p = r * p;
    turned->dirty();
    auto sphere = shapes::sphere(1.0f, 16, 8), shifted = sphere->clone();
    for (glm::vec3& p : shifted->positions)
        p += glm::vec3(0.1f, 0.02f, 0.0f);
    shifted->dirty();
    for (const auto& [a, b] : {std::pair{box, turned}, std::pair{sphere, shifted}}) {
        const double lower = std::max(bruteForceLower(*a, *b, 8), bruteForceLower(*b, *a, 8));
        HausdorffBoundStats stats;
        const double bound = hausdorffBound(*a, *b, 0.1f, 0.0f, &stats);
        EXPECT_GE(bound, lower);
        EXPECT_LE(bound, 1.25 * lower) << "looser than the slack allows"; // 1.1 plus the grid's miss
        std::printf("%zu triangles: bound %.5f, brute-force lower %.5f\n", a->triangleCount(), bound, lower);
    }
}

TEST(AutoLod, OpenBorderIsKept) {
    auto terrain = shapes::heightfield(-1, -1, 2, 2, 48, 48, [](float x, float y) {
        return 0.15f * std::sin(3.0f * x) * std::cos(2.0f * y);
    });
    ASSERT_TRUE(optimizeMesh(*terrain));
    std::vector<AutoLodLevel> levels;
    ASSERT_TRUE(makeErrorLod(terrain, {}, &levels));
    ASSERT_GE(levels.size(), 2u);
    const auto original = borderEdges(*terrain);
    EXPECT_EQ(original.size(), 4u * 48u);
    for (const auto& level : levels) {
        const auto border = borderEdges(*level.geometry);
        for (const auto& e : border)
            EXPECT_TRUE(original.count(e))
                << "a new border edge at " << level.geometry->triangleCount() << " triangles";
        EXPECT_EQ(border.size(), original.size()); // locked: every border edge is still there
    }
}

TEST(AutoLod, HausdorffDistanceOfAShiftedSphere) {
    auto a = shapes::sphere(1.0f, 48, 24), b = a->clone();
    for (glm::vec3& p : b->positions)
        p.x += 0.1f;
    b->dirty();
    // The farthest points are on the x axis, 0.1 from the other sphere's surface.
    const float h = hausdorffDistance(*a, *b);
    EXPECT_LE(h, 0.1f + 1e-5f);
    EXPECT_GE(h, 0.095f);
    EXPECT_LE(hausdorffDistance(*a, *a), 1e-5f);
    // The measure and meshoptimizer's estimate agree within a factor of two on a smooth sphere.
    std::vector<AutoLodLevel> levels;
    ASSERT_TRUE(optimizeMesh(*a));
    ASSERT_TRUE(makeErrorLod(a, {}, &levels));
    for (const auto& level : levels)
        EXPECT_GE(level.measuredError, 0.5f * level.simplifierError) << level.geometry->triangleCount();
}

TEST(AutoLod, SharedMeshGetsOneLod) {
    auto mesh = bumpySphere();
    auto root = Group::create();
    auto left = Transform::create(glm::translate(glm::mat4(1), glm::vec3(-2, 0, 0)));
    auto right = Transform::create(glm::translate(glm::mat4(1), glm::vec3(2, 0, 0)));
    left->addChild(mesh);
    right->addChild(mesh);
    root->addChild(left);
    root->addChild(right);
    root->addChild(shapes::box({1, 1, 1})); // too few triangles: stays
    AutoLodOptions options;
    EXPECT_EQ(addAutoLods(*root, options), 1u);
    ASSERT_TRUE(std::dynamic_pointer_cast<LOD>(left->child(0)));
    EXPECT_EQ(left->child(0), right->child(0));
    EXPECT_EQ(std::dynamic_pointer_cast<LOD>(left->child(0))->child(0), mesh);
    EXPECT_TRUE(std::dynamic_pointer_cast<Geometry>(root->child(2)));
    // Skinned or morphed meshes are refused with the reason.
    auto morphed = bumpySphere();
    morphed->morphTargets.push_back({std::vector<glm::vec3>(morphed->positions.size()), {}, {}});
    std::string why;
    EXPECT_FALSE(makeErrorLod(morphed, options, nullptr, &why));
    EXPECT_NE(why.find("morphed"), std::string::npos) << why;
}

// Several meshes, one shared by two transforms, made into LODs on one thread and on four: the same
// levels (indices, positions, ranges) wherever each mesh is drawn. Also run under ThreadSanitizer.
TEST(AutoLod, ThreadsMakeTheSameLods) {
    auto scene = [] {
        auto root = Group::create();
        std::shared_ptr<Geometry> shared;
        for (int k = 0; k < 6; ++k) {
            auto g = shapes::sphere(1.0f, 16 + 4 * k, 8 + 2 * k);
            for (glm::vec3& p : g->positions)
                p *= 1.0f + 0.05f * std::sin((3.0f + float(k)) * p.x) * std::sin(4.0f * p.y);
            g->dirty();
            EXPECT_TRUE(optimizeMesh(*g));
            auto t = Transform::create(glm::translate(glm::mat4(1), glm::vec3(3.0f * float(k), 0, 0)));
            t->addChild(g);
            root->addChild(t);
            if (k == 2) shared = g;
        }
        auto again = Transform::create(glm::translate(glm::mat4(1), glm::vec3(0, 3, 0)));
        again->addChild(shared);
        root->addChild(again);
        return root;
    };
    AutoLodOptions one, four;
    one.minTriangles = four.minTriangles = 32;
    one.threads = 1, four.threads = 4;
    const auto a = scene(), b = scene();
    EXPECT_EQ(addAutoLods(*a, one), 6u);
    EXPECT_EQ(addAutoLods(*b, four), 6u);
    ASSERT_EQ(a->numChildren(), b->numChildren());
    auto lodOf = [](const std::shared_ptr<Group>& root, std::size_t i) {
        return std::dynamic_pointer_cast<LOD>(std::dynamic_pointer_cast<Group>(root->child(i))->child(0));
    };
    EXPECT_EQ(lodOf(b, 2), lodOf(b, 6)) << "the shared mesh has one LOD";
    for (std::size_t i = 0; i < a->numChildren(); ++i) {
        const auto la = lodOf(a, i), lb = lodOf(b, i);
        ASSERT_TRUE(la && lb) << "mesh " << i;
        ASSERT_EQ(la->numChildren(), lb->numChildren()) << "mesh " << i;
        for (std::size_t c = 0; c < la->numChildren(); ++c) {
            const auto ga = std::dynamic_pointer_cast<Geometry>(la->child(c)),
                       gb = std::dynamic_pointer_cast<Geometry>(lb->child(c));
            ASSERT_TRUE(ga && gb);
            EXPECT_EQ(ga->indices, gb->indices) << "mesh " << i << " level " << c;
            EXPECT_EQ(ga->positions, gb->positions) << "mesh " << i << " level " << c;
            EXPECT_EQ(la->range(c).minPixels, lb->range(c).minPixels) << "mesh " << i << " level " << c;
            EXPECT_EQ(la->range(c).maxPixels, lb->range(c).maxPixels) << "mesh " << i << " level " << c;
        }
    }
    // makeErrorLod alone bounds a large level's two sides on two threads unless threads is 1.
    const auto big = bumpySphere();
    AutoLodOptions alone = one, two = one;
    two.threads = 2;
    std::vector<AutoLodLevel> l1, l2;
    ASSERT_TRUE(makeErrorLod(big, alone, &l1));
    ASSERT_TRUE(makeErrorLod(big, two, &l2));
    ASSERT_EQ(l1.size(), l2.size());
    ASSERT_GE(big->triangleCount() + l1[0].geometry->triangleCount(), 4096u); // the two-thread size
    for (std::size_t i = 0; i < l1.size(); ++i) {
        EXPECT_EQ(l1[i].measuredError, l2[i].measuredError) << "level " << i;
        EXPECT_EQ(l1[i].geometry->indices, l2[i].geometry->indices) << "level " << i;
    }
}

// The loader's thread spreader: every job once, and a job's exception comes back to the caller.
TEST(AutoLod, ParallelForRunsEveryJobOnceAndRethrows) {
    std::vector<std::atomic<int>> runs(1000);
    detail::parallelFor(runs.size(), 3, [&](std::size_t i) { ++runs[i]; });
    for (std::size_t i = 0; i < runs.size(); ++i)
        EXPECT_EQ(runs[i].load(), 1) << "job " << i;
    for (const unsigned threads : {1u, 3u})
        try {
            detail::parallelFor(100, threads, [](std::size_t i) {
                if (i == 17) throw std::runtime_error("job 17 failed");
            });
            ADD_FAILURE() << "no exception with " << threads << " threads";
        } catch (const std::runtime_error& e) {
            EXPECT_STREQ(e.what(), "job 17 failed");
        }
}

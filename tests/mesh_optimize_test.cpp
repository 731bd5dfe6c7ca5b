// meshoptimizer's vertex-cache, overdraw and fetch order (MeshOptimize.h): the same triangles with
// the same vertex records, the same image, no worse cache or overdraw figures, and the meshes whose
// order shows (skinned, morphed, blended, strips) left as they are.
#include "TestUtil.h"

#include <sgfx/GltfLoader.h>
#include <sgfx/Group.h>
#include <sgfx/MeshLoader.h>
#include <sgfx/MeshOptimize.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/Shapes.h>
#include <sgfx/StateSet.h>

#include <meshoptimizer.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

using namespace sgfx;

namespace {

// Every stream of vertex v, byte for byte.
std::string record(const Geometry& g, std::size_t v) {
    std::string r;
    auto add = [&](const auto& stream) {
        if (stream.empty()) return;
        const char* p = reinterpret_cast<const char*>(&stream[v]);
        r.append(p, sizeof(stream[v]));
    };
    add(g.positions), add(g.normals), add(g.tangents), add(g.texcoords), add(g.texcoords1), add(g.colors);
    return r;
}

// The triangles as a sorted list, each its three vertex records rotated so the smallest comes first
// (the winding is kept).
std::vector<std::array<std::string, 3>> triangles(const Geometry& g) {
    std::vector<std::array<std::string, 3>> out;
    const std::size_t n = g.elementCount();
    for (std::size_t k = 0; k + 2 < n; k += 3) {
        std::array<std::string, 3> t;
        for (std::size_t j = 0; j < 3; ++j)
            t[j] = record(g, g.indices.empty() ? k + j : g.indices[k + j]);
        std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
        out.push_back(std::move(t));
    }
    std::sort(out.begin(), out.end());
    return out;
}

// A colour per vertex from its position, so a fourth stream travels with the others.
void addColours(Geometry& g) {
    g.colors.clear();
    for (const glm::vec3& p : g.positions)
        g.colors.emplace_back(0.5f + 0.5f * glm::sin(3.0f * p), 1.0f);
}

// The triangles in a random (fixed) order and the vertices permuted: a poor order to start from.
void shuffle(Geometry& g, unsigned seed) {
    std::mt19937 rng(seed);
    std::vector<std::array<std::uint32_t, 3>> tris;
    for (std::size_t k = 0; k + 2 < g.indices.size(); k += 3)
        tris.push_back({g.indices[k], g.indices[k + 1], g.indices[k + 2]});
    for (std::size_t i = tris.size(); i > 1; --i)
        std::swap(tris[i - 1], tris[rng() % i]);
    std::vector<std::uint32_t> perm(g.positions.size());
    for (std::uint32_t i = 0; i < perm.size(); ++i)
        perm[i] = i;
    for (std::size_t i = perm.size(); i > 1; --i)
        std::swap(perm[i - 1], perm[rng() % i]);
    auto permute = [&](auto& stream) {
        if (stream.empty()) return;
        auto copy = stream;
        for (std::size_t i = 0; i < perm.size(); ++i)
            stream[perm[i]] = copy[i];
    };
    permute(g.positions), permute(g.normals), permute(g.tangents), permute(g.texcoords), permute(g.colors);
    g.indices.clear();
    for (const auto& t : tris)
        for (std::uint32_t v : t)
            g.indices.push_back(perm[v]);
    g.dirty();
}

// Three spheres and a box, closed and apart (no coplanar faces), shuffled.
std::shared_ptr<Geometry> cluster() {
    auto g = Geometry::create();
    shapes::append(*g, *shapes::sphere(0.6f, 24, 12), glm::translate(glm::mat4(1), glm::vec3(-0.7f, 0, 0)));
    shapes::append(*g, *shapes::sphere(0.5f, 20, 10),
                   glm::translate(glm::mat4(1), glm::vec3(0.6f, 0.2f, 0.3f)));
    shapes::append(*g, *shapes::sphere(0.4f, 16, 8),
                   glm::translate(glm::mat4(1), glm::vec3(0.1f, -0.3f, 0.9f)));
    shapes::append(*g, *shapes::box({0.5f, 0.7f, 0.9f}),
                   glm::translate(glm::mat4(1), glm::vec3(0.1f, 0.8f, -0.6f)));
    addColours(*g);
    shuffle(*g, 7);
    return g;
}

float acmr(const Geometry& g) {
    return meshopt_analyzeVertexCache(g.indices.data(), g.indices.size(), g.positions.size(), 16, 0, 0).acmr;
}
float overdraw(const Geometry& g) {
    return meshopt_analyzeOverdraw(g.indices.data(), g.indices.size(), &g.positions[0].x, g.positions.size(),
                                   sizeof(glm::vec3))
        .overdraw;
}

Image render(const std::shared_ptr<Geometry>& g, glm::vec3 eye) {
    auto viewer = Viewer::createHeadless(96, 96);
    auto& cam = *viewer->camera();
    cam.setLookAt(eye, {0, 0, 0}, {0, 0, 1});
    cam.projectionMatrix = glm::perspective(glm::radians(40.0f), 1.0f, 0.5f, 20.0f);
    auto root = Group::create();
    root->addChild(g);
    viewer->setSceneData(root);
    viewer->frame();
    return viewer->capture();
}

// Every Geometry under `node` in traversal order.
void geometries(const NodePtr& node, std::vector<std::shared_ptr<Geometry>>& out) {
    if (auto g = std::dynamic_pointer_cast<Geometry>(node)) out.push_back(g);
    if (auto group = std::dynamic_pointer_cast<Group>(node))
        for (const NodePtr& c : group->children())
            geometries(c, out);
}

} // namespace

TEST(MeshOptimize, KeepsEveryTriangleWithItsVertexRecords) {
    ASSERT_TRUE(meshOptimizerAvailable());
    auto sphere = shapes::sphere(1.0f, 32, 16);
    addColours(*sphere);
    shuffle(*sphere, 3);
    for (const auto& original : {sphere, cluster()}) {
        // Indexed, and the same triangles unindexed (three vertices each, to be welded).
        auto unindexed = original->clone();
        unindexed->indices.clear();
        auto expand = [&](auto& dst, const auto& src) {
            dst.clear();
            for (std::uint32_t i : original->indices)
                dst.push_back(src[i]);
        };
        expand(unindexed->positions, original->positions), expand(unindexed->normals, original->normals);
        expand(unindexed->tangents, original->tangents), expand(unindexed->texcoords, original->texcoords);
        expand(unindexed->colors, original->colors);
        for (const auto& input : {original, unindexed}) {
            auto g = input->clone();
            const auto revision = g->revision();
            std::string why;
            ASSERT_TRUE(optimizeMesh(*g, {}, &why)) << why;
            EXPECT_EQ(why, "");
            EXPECT_GT(g->revision(), revision); // dirtied
            EXPECT_NO_THROW(g->validate());
            EXPECT_EQ(triangles(*g), triangles(*input));
            EXPECT_LE(g->positions.size(), original->positions.size()); // welded
        }
    }
}

TEST(MeshOptimize, RenderedImagesAreByteEqual) {
    const auto original = cluster();
    auto optimized = original->clone();
    ASSERT_TRUE(optimizeMesh(*optimized));
    ASSERT_NE(optimized->indices, original->indices); // the order did change
    for (glm::vec3 eye : {glm::vec3(3.5f, -2.0f, 1.5f), glm::vec3(-2.0f, 3.0f, -2.5f)}) {
        const Image a = render(original, eye), b = render(optimized, eye);
        ASSERT_EQ(a.pixels.size(), b.pixels.size());
        std::size_t covered = 0;
        for (int y = 0; y < a.height; ++y)
            for (int x = 0; x < a.width; ++x)
                covered += test::pixelAt(a, x, y) != test::pixelAt(a, 0, 0);
        EXPECT_GT(covered, 1000u); // the cluster fills a good part of the view
        EXPECT_TRUE(a.pixels == b.pixels) << "eye " << eye.x << "," << eye.y << "," << eye.z;
    }
}

TEST(MeshOptimize, CacheMissesAndOverdrawDoNotGrow) {
    auto sphere = shapes::sphere(1.0f, 48, 24);
    shuffle(*sphere, 11);
    for (const auto& original : {sphere, cluster()}) {
        auto g = original->clone();
        ASSERT_TRUE(optimizeMesh(*g));
        EXPECT_LT(acmr(*g), 0.8f * acmr(*original)); // from a shuffled order it falls far
        EXPECT_LE(overdraw(*g), overdraw(*original));
    }
}

TEST(MeshOptimize, RefusesWhereTheOrderShows) {
    std::string why;
    auto strip = shapes::sphere(1.0f, 8, 4);
    strip->mode = PrimitiveMode::TriangleStrip;
    EXPECT_FALSE(optimizeMesh(*strip, {}, &why));
    EXPECT_NE(why.find("Triangles"), std::string::npos) << why;

    auto morphed = shapes::sphere(1.0f, 8, 4);
    morphed->morphTargets.push_back(
        {std::vector<glm::vec3>(morphed->positions.size(), glm::vec3(0.1f)), {}, {}});
    const auto before = morphed->indices;
    EXPECT_FALSE(optimizeMesh(*morphed, {}, &why));
    EXPECT_NE(why.find("morphed"), std::string::npos) << why;
    EXPECT_EQ(morphed->indices, before);

    auto blended = shapes::sphere(1.0f, 8, 4);
    auto state = StateSet::create();
    state->blend.set(BlendMode::Alpha);
    blended->setStateSet(state);
    EXPECT_FALSE(optimizeMesh(*blended, {}, &why));
    EXPECT_NE(why.find("blends"), std::string::npos) << why;

    // Under a blending group: left alone by optimizeMeshes; the same geometry shared by an opaque
    // path and a blended one is left alone too; an opaque one shared twice is reordered once.
    auto opaque = shapes::sphere(1.0f, 8, 4), shared = shapes::sphere(1.0f, 8, 4);
    const auto opaqueBefore = opaque->indices, sharedBefore = shared->indices;
    auto root = Group::create(), glass = Group::create();
    glass->setStateSet(state);
    glass->addChild(shared);
    root->addChild(glass);
    root->addChild(shared);
    root->addChild(opaque);
    root->addChild(opaque);
    EXPECT_EQ(optimizeMeshes(*root), 1u);
    EXPECT_EQ(shared->indices, sharedBefore);
    EXPECT_NE(opaque->indices, opaqueBefore);
}

TEST(MeshOptimize, SkinnedAndMorphedGltfIsLeftAsItIs) {
    const std::filesystem::path assets = SGFX_SOURCE_DIR "/../shared/assets/gltf";
    const char* files[] = {"SimpleSkin/glTF/SimpleSkin.gltf", "SimpleMorph/glTF/SimpleMorph.gltf",
                           "RiggedSimple/glTF/RiggedSimple.gltf"};
    for (const char* file : files) {
        SGFX_REQUIRE(std::filesystem::exists(assets / file), "shared glTF sample " << file);
        GltfOptions off;
        off.optimizeOrder = false;
        GltfStats stats;
        std::vector<std::shared_ptr<Geometry>> with, without;
        geometries(loadGltf(assets / file, {}, &stats), with);
        geometries(loadGltf(assets / file, off), without);
        EXPECT_EQ(stats.reordered, 0u) << file;
        ASSERT_EQ(with.size(), without.size()) << file;
        ASSERT_FALSE(with.empty()) << file;
        for (std::size_t i = 0; i < with.size(); ++i) {
            EXPECT_TRUE(with[i]->posed()) << file;
            EXPECT_EQ(with[i]->indices, without[i]->indices) << file;
            EXPECT_EQ(with[i]->positions, without[i]->positions) << file;
            std::string why;
            EXPECT_FALSE(optimizeMesh(*with[i], {}, &why));
            EXPECT_NE(why.find("skinned or morphed"), std::string::npos) << why;
        }
    }
}

TEST(MeshOptimize, GltfLoadReordersOpaqueMeshesOnce) {
    const std::filesystem::path duck = SGFX_SOURCE_DIR "/../shared/assets/gltf/Duck/glTF-Binary/Duck.glb";
    SGFX_REQUIRE(std::filesystem::exists(duck), "shared glTF sample Duck.glb");
    GltfStats stats;
    GltfOptions off;
    off.optimizeOrder = false;
    std::vector<std::shared_ptr<Geometry>> with, without;
    geometries(loadGltf(duck, {}, &stats), with);
    geometries(loadGltf(duck, off), without);
    EXPECT_EQ(stats.reordered, 1u);
    ASSERT_EQ(with.size(), 1u);
    ASSERT_EQ(without.size(), 1u);
    EXPECT_EQ(triangles(*with[0]), triangles(*without[0]));
    EXPECT_LE(acmr(*with[0]), acmr(*without[0]));
}

TEST(MeshOptimize, LoadModelReordersObjMeshesToo) {
    auto sphere = shapes::sphere(1.0f, 32, 16);
    sphere->texcoords.clear(), sphere->tangents.clear();
    shuffle(*sphere, 5);
    const auto file = std::filesystem::temp_directory_path() / "sgfx_mesh_optimize_test.obj";
    writeMesh(*sphere, file);
    GltfOptions off;
    off.optimizeOrder = false;
    std::vector<std::shared_ptr<Geometry>> with, without;
    geometries(loadModel(file), with);
    geometries(loadModel(file, off), without);
    std::filesystem::remove(file);
    ASSERT_EQ(with.size(), 1u);
    ASSERT_EQ(without.size(), 1u);
    EXPECT_EQ(triangles(*with[0]), triangles(*without[0]));
    EXPECT_LT(acmr(*with[0]), 0.8f * acmr(*without[0]));
}

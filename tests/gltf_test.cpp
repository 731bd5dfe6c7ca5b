// glTF loading: every shared model (../shared/assets/gltf, see its README for the figures) loads
// with the README's triangle, node and material counts and alpha modes and renders; hand-made
// files check sparse accessors, strides and normalised values; bad files name the element.
#include "TestUtil.h"

#include <sgfx/GltfLoader.h>
#include <sgfx/Group.h>
#include <sgfx/Visitors.h>

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

using namespace sgfx;
using namespace sgfx::test;

namespace {

const std::filesystem::path kAssets =
    std::filesystem::path(SGFX_SOURCE_DIR) / ".." / "shared" / "assets" / "gltf";

struct Expected {
    const char* file;
    std::size_t triangles, nodes, materials, opaque, masked, blended, textures;
};

std::string base64(const std::vector<unsigned char>& bytes) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const unsigned v = unsigned(bytes[i]) << 16 |
                           (i + 1 < bytes.size() ? unsigned(bytes[i + 1]) << 8 : 0u) |
                           (i + 2 < bytes.size() ? unsigned(bytes[i + 2]) : 0u);
        out += t[v >> 18 & 63];
        out += t[v >> 12 & 63];
        out += i + 1 < bytes.size() ? t[v >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? t[v & 63] : '=';
    }
    return out;
}

template <class T> void put(std::vector<unsigned char>& b, T v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    b.insert(b.end(), p, p + sizeof v);
}

// A one-triangle file: positions (3 floats each) then uint16 indices, in one base64 buffer.
// `edit` may change the JSON text before it is written.
std::filesystem::path tinyFile(const std::string& name, std::vector<float> positions,
                               std::vector<std::uint16_t> indices,
                               const std::function<void(std::string&)>& edit = {}) {
    std::vector<unsigned char> bytes;
    for (float f : positions)
        put(bytes, f);
    const std::size_t posBytes = bytes.size();
    for (auto i : indices)
        put(bytes, i);
    while (bytes.size() % 4)
        bytes.push_back(0);
    std::string json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
"buffers":[{"byteLength":BYTES,"uri":"data:application/octet-stream;base64,DATA"}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":POSBYTES},{"buffer":0,"byteOffset":POSBYTES,"byteLength":IDXBYTES}],
"accessors":[{"bufferView":0,"componentType":5126,"count":POSCOUNT,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
{"bufferView":1,"componentType":5123,"count":IDXCOUNT,"type":"SCALAR"}]})";
    auto replace = [&](const std::string& key, const std::string& value) {
        for (auto at = json.find(key); at != std::string::npos; at = json.find(key))
            json.replace(at, key.size(), value);
    };
    replace("POSBYTES", std::to_string(posBytes));
    replace("IDXBYTES", std::to_string(indices.size() * 2));
    replace("POSCOUNT", std::to_string(positions.size() / 3));
    replace("IDXCOUNT", std::to_string(indices.size()));
    replace("BYTES", std::to_string(bytes.size()));
    replace("DATA", base64(bytes));
    if (edit) edit(json);
    const auto path = std::filesystem::temp_directory_path() / name;
    std::ofstream(path) << json;
    return path;
}

void expectLoadError(const std::filesystem::path& file, const std::string& needle) {
    try {
        (void)loadGltf(file);
        ADD_FAILURE() << "loaded: " << file;
    } catch (const LoadError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(needle), std::string::npos) << what;
        EXPECT_NE(what.find(file.filename().string()), std::string::npos)
            << "the message names the file: " << what;
    }
}

} // namespace

TEST(Gltf, EverySharedModelLoadsWithTheReadmesFigures) {
    if (!std::filesystem::exists(kAssets)) GTEST_SKIP() << "no shared assets at " << kAssets;
    const Expected models[] = {
        {"Box/glTF-Binary/Box.glb", 12, 2, 1, 1, 0, 0, 0},
        {"Box/glTF/Box.gltf", 12, 2, 1, 1, 0, 0, 0},
        {"BoxTextured/glTF-Binary/BoxTextured.glb", 12, 2, 1, 1, 0, 0, 1},
        {"Duck/glTF-Binary/Duck.glb", 4212, 3, 1, 1, 0, 0, 1},
        {"AlphaBlendModeTest/glTF/AlphaBlendModeTest.gltf", 61, 9, 6, 2, 3, 1, 0},
        {"NormalTangentMirrorTest/glTF/NormalTangentMirrorTest.gltf", 5240, 1, 1, 1, 0, 0, 0},
        {"TextureCoordinateTest/glTF/TextureCoordinateTest.gltf", 10, 5, 5, 5, 0, 0, 0},
        {"OrientationTest/glTF/OrientationTest.gltf", 524, 13, 7, 7, 0, 0, 0},
        {"SimpleSparseAccessor/glTF/SimpleSparseAccessor.gltf", 12, 1, 0, 0, 0, 0, 0},
        {"MetalRoughSpheresNoTextures/glTF/MetalRoughSpheresNoTextures.gltf", 1040409, 119, 98, 98, 0, 0, 0},
    };
    for (const Expected& e : models) {
        SCOPED_TRACE(e.file);
        GltfStats st;
        const auto root = loadGltf(kAssets / e.file, {}, &st);
        EXPECT_EQ(st.triangles, e.triangles);
        EXPECT_EQ(st.nodes, e.nodes);
        EXPECT_EQ(st.materials, e.materials);
        EXPECT_EQ(st.opaque, e.opaque);
        EXPECT_EQ(st.masked, e.masked);
        EXPECT_EQ(st.blended, e.blended);
        EXPECT_GE(st.textures, e.textures);
        // Rendered headless: not blank.
        ComputeBoundsVisitor bounds;
        root->accept(bounds);
        ASSERT_TRUE(bounds.valid());
        const glm::vec3 centre = 0.5f * (bounds.min + bounds.max);
        const float radius = 0.5f * glm::length(bounds.max - bounds.min);
        auto v = Viewer::createHeadless(64, 64);
        auto& cam = *v->camera();
        cam.setPerspective(40.0f, radius * 0.05f, radius * 10.0f);
        cam.setLookAt(centre + glm::vec3(radius * 1.5f, -radius * 2.5f, radius * 1.2f), centre, {0, 0, 1});
        cam.clearColor = {0, 0, 0, 1};
        auto scene = Group::create();
        scene->addChild(root);
        scene->addChild(Light::create());
        auto ambient = Light::create(LightType::Ambient);
        ambient->color = glm::vec3(0.3f);
        scene->addChild(ambient);
        v->setSceneData(scene);
        v->frame();
        const Image img = v->capture();
        int lit = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x)
                lit += pixelAt(img, x, y).r + pixelAt(img, x, y).g + pixelAt(img, x, y).b > 10;
        EXPECT_GT(lit, 40);
    }
}

TEST(Gltf, SparseAccessorReplacesTheListedValues) {
    if (!std::filesystem::exists(kAssets)) GTEST_SKIP();
    // SimpleSparseAccessor: 14 points on y ∈ {0, 1}, three of them raised by sparse substitution;
    // the accessor's min/max, (0, 0, 0)..(6, 4, 0), describe the substituted values.
    const auto root =
        loadGltf(kAssets / "SimpleSparseAccessor/glTF/SimpleSparseAccessor.gltf", {.zUp = false});
    ComputeBoundsVisitor b;
    root->accept(b);
    EXPECT_EQ(b.min, glm::vec3(0.0f));
    EXPECT_EQ(b.max, glm::vec3(6.0f, 4.0f, 0.0f));
}

TEST(Gltf, YUpBecomesZUpUnlessAsked) {
    const auto file = tinyFile("sgfx_tiny_up.gltf", {0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2});
    ComputeBoundsVisitor zUp, yUp;
    loadGltf(file)->accept(zUp);
    loadGltf(file, {.zUp = false})->accept(yUp);
    EXPECT_FLOAT_EQ(yUp.max.y, 1.0f);
    EXPECT_FLOAT_EQ(zUp.max.z, 1.0f); // glTF's +Y is sgfx's +Z
    EXPECT_NEAR(zUp.max.y, 0.0f, 1e-6f);
    std::filesystem::remove(file);
}

TEST(Gltf, BadFilesNameTheElementAndTheReason) {
    expectLoadError("/nonexistent/model.gltf", "no such file");
    const auto dir = std::filesystem::temp_directory_path();
    {
        std::ofstream(dir / "sgfx_notgltf.gltf") << "[1, 2, 3]";
        expectLoadError(dir / "sgfx_notgltf.gltf", "sgfx_notgltf.gltf");
    }
    if (std::filesystem::exists(kAssets)) {
        // A .glb cut short.
        std::ifstream in(kAssets / "Box/glTF-Binary/Box.glb", std::ios::binary);
        std::vector<char> bytes(200);
        in.read(bytes.data(), 200);
        std::ofstream(dir / "sgfx_truncated.glb", std::ios::binary).write(bytes.data(), 200);
        expectLoadError(dir / "sgfx_truncated.glb", "sgfx_truncated.glb");
    }
    const std::vector<float> tri{0, 0, 0, 1, 0, 0, 0, 1, 0};
    expectLoadError(tinyFile("sgfx_bad_index.gltf", tri, {0, 1, 7}),
                    "meshes[0].primitives[0].indices: index 7");
    expectLoadError(tinyFile("sgfx_nan.gltf", {0, 0, 0, std::nanf(""), 0, 0, 0, 1, 0}, {0, 1, 2}),
                    "meshes[0].primitives[0].attributes.POSITION: has a NaN");
    expectLoadError(tinyFile("sgfx_overrun.gltf", tri, {0, 1, 2},
                             [](std::string& j) {
                                 const auto at = j.find("\"count\":3,\"type\":\"VEC3\"");
                                 j.replace(at, 9, "\"count\":99");
                             }),
                    "accessors[0]: 99 elements");
    expectLoadError(tinyFile("sgfx_cycle.gltf", tri, {0, 1, 2},
                             [](std::string& j) {
                                 j.replace(j.find("\"nodes\":[{\"mesh\":0}]"), 20,
                                           "\"nodes\":[{\"mesh\":0,\"children\":[0]}]");
                             }),
                    "nodes[0]: is its own ancestor");
    expectLoadError(tinyFile("sgfx_required.gltf", tri, {0, 1, 2},
                             [](std::string& j) {
                                 j.insert(1, "\"extensionsRequired\":[\"KHR_draco_mesh_compression\"],");
                             }),
                    "KHR_draco_mesh_compression");
}

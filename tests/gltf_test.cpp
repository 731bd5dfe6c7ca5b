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
#include <iterator>
#include <span>

using namespace sgfx;
using namespace sgfx::test;

namespace {

const std::filesystem::path kAssets =
    std::filesystem::path(SGFX_SOURCE_DIR) / ".." / "shared" / "assets" / "gltf";

struct Expected {
    const char* file;
    std::size_t triangles, nodes, materials, opaque, masked, blended, textures;
};

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
    SGFX_REQUIRE(std::filesystem::exists(kAssets), "the shared assets at " << kAssets);
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
    SGFX_REQUIRE(std::filesystem::exists(kAssets), "the shared assets at " << kAssets);
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
    if (optionalPrerequisite(std::filesystem::exists(kAssets), "the shared assets at " + kAssets.string())) {
        // A .glb cut short.
        std::ifstream in(kAssets / "Box/glTF-Binary/Box.glb", std::ios::binary);
        std::vector<char> bytes(200);
        in.read(bytes.data(), 200);
        std::ofstream(dir / "sgfx_truncated.glb", std::ios::binary).write(bytes.data(), 200);
        expectLoadError(dir / "sgfx_truncated.glb", "sgfx_truncated.glb");
    }
    const std::vector<float> tri{0, 0, 0, 1, 0, 0, 0, 1, 0};
    expectLoadError(
        tinyFile("sgfx_bad_index.gltf", tri, {0, 1, 7}),
        "meshes[0].primitives[0].indices: index 7 (entry 2 of accessors[1]) is out of range for 3 "
        "vertices");
    expectLoadError(tinyFile("sgfx_nan.gltf", {0, 0, 0, std::nanf(""), 0, 0, 0, 1, 0}, {0, 1, 2}),
                    "meshes[0].primitives[0].attributes.POSITION: has a NaN");
    expectLoadError(
        tinyFile("sgfx_overrun.gltf", tri, {0, 1, 2},
                 [](std::string& j) {
                     const auto at = j.find("\"count\":3,\"type\":\"VEC3\"");
                     j.replace(at, 9, "\"count\":99");
                 }),
        "accessors[0]: 99 elements of 12 bytes from offset 0 (stride 12) run past the 36 bytes of "
        "bufferViews[0] (used by meshes[0].primitives[0].attributes.POSITION)");
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
    // A texture whose image will not decode (a PNG signature followed by garbage).
    expectLoadError(
        tinyFile("sgfx_bad_image.gltf", tri, {0, 1, 2},
                 [](std::string& j) {
                     j.replace(j.find("\"indices\":1}"), 12, "\"indices\":1,\"material\":0}");
                     j.insert(j.size() - 1,
                              R"(,"images":[{"uri":"data:image/png;base64,iVBORw0KGgoAAAAAAAAAAAAAAAAAAAA="}],
"textures":[{"source":0}],"materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}])");
                 }),
        "images[0]");
    // A PNG whose image-data chunk claims more bytes than there are: stb would copy from past
    // the end of the buffer (found by the fuzzer); refused before stb sees it.
    expectLoadError(
        tinyFile(
            "sgfx_truncated_png.gltf", tri, {0, 1, 2},
            [](std::string& j) {
                j.replace(j.find("\"indices\":1}"), 12, "\"indices\":1,\"material\":0}");
                j.insert(
                    j.size() - 1,
                    R"(,"images":[{"uri":"data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAAAAAAAAAPoElEQVR4nAAAAAAAAAAAAAA="}],
"textures":[{"source":0}],"materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}])");
            }),
        "images[0]: cannot decode: truncated PNG: the chunk at byte 33 claims 4000 bytes");
    // An image in a buffer view that runs past its buffer: tinygltf 2.7 hands such views to the
    // image decoder unchecked (the fuzzer's heap overread); checked before anything reads it.
    expectLoadError(tinyFile("sgfx_image_view_overrun.gltf", tri, {0, 1, 2},
                             [](std::string& j) {
                                 j.replace(j.find("\"indices\":1}"), 12, "\"indices\":1,\"material\":0}");
                                 const auto views = j.find("\"bufferViews\":[") + 15;
                                 j.insert(views, R"({"buffer":0,"byteOffset":8,"byteLength":4000},)");
                                 // the views the mesh uses move up by one
                                 for (const char* from : {"\"bufferView\":1", "\"bufferView\":0"})
                                     for (auto at = j.find(from); at != std::string::npos;
                                          at = j.find(from, at + 1))
                                         j[at + 13] = char(j[at + 13] + 1);
                                 j.insert(j.size() - 1,
                                          R"(,"images":[{"bufferView":0,"mimeType":"image/png"}],
"textures":[{"source":0}],"materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}])");
                             }),
                    "images[0]: its buffer view (4000 bytes at 8) runs past the buffer's");
}

namespace {
std::vector<std::byte> readBytes(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::byte> bytes(chars.size());
    std::memcpy(bytes.data(), chars.data(), chars.size());
    return bytes;
}

// A .glb of a JSON chunk and, unless `bin` is 0, a BIN chunk of `bin` zero bytes.
std::vector<std::byte> glb(std::string json, std::size_t bin) {
    while (json.size() % 4)
        json += ' ';
    std::vector<unsigned char> b;
    put(b, std::uint32_t(0x46546C67)); // "glTF"
    put(b, std::uint32_t(2));
    put(b, std::uint32_t(12 + 8 + json.size() + (bin ? 8 + bin : 0)));
    put(b, std::uint32_t(json.size()));
    put(b, std::uint32_t(0x4E4F534A)); // "JSON"
    b.insert(b.end(), json.begin(), json.end());
    if (bin) {
        put(b, std::uint32_t(bin));
        put(b, std::uint32_t(0x004E4942)); // "BIN\0"
        b.resize(b.size() + bin, 0);
    }
    std::vector<std::byte> out(b.size());
    std::memcpy(out.data(), b.data(), b.size());
    return out;
}

std::string memoryLoadError(std::span<const std::byte> bytes, const GltfOptions& options = {}) {
    try {
        (void)loadGltfFromMemory(bytes, "in-memory.glb", options);
    } catch (const LoadError& e) {
        return e.what();
    }
    return "loaded";
}
} // namespace

TEST(Gltf, LoadsFromMemoryAsFromTheFile) {
    const auto file = tinyFile("sgfx_tiny_memory.gltf", {0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2});
    GltfStats fromFile, fromMemory;
    (void)loadGltf(file, {}, &fromFile);
    const auto bytes = readBytes(file);
    const auto root = loadGltfFromMemory(bytes, "tiny", {}, &fromMemory);
    EXPECT_EQ(root->name, "tiny");
    EXPECT_EQ(fromMemory.triangles, 1u);
    EXPECT_EQ(fromMemory.nodes, fromFile.nodes);
    std::filesystem::remove(file);
    SGFX_REQUIRE(std::filesystem::exists(kAssets), "the shared assets at " << kAssets);
    GltfStats duck;
    (void)loadGltfFromMemory(readBytes(kAssets / "Duck/glTF-Binary/Duck.glb"), "duck", {}, &duck);
    EXPECT_EQ(duck.triangles, 4212u);
    EXPECT_EQ(duck.textures, 1u);
    // Bytes in memory have no directory: an external buffer cannot be found.
    const std::string why = memoryLoadError(readBytes(kAssets / "Box/glTF/Box.gltf"));
    EXPECT_NE(why.find("in-memory.glb"), std::string::npos) << why;
    EXPECT_NE(why.find("Box0.bin"), std::string::npos) << why;
    EXPECT_NE(why.find("external files cannot be read"), std::string::npos) << why;
}

TEST(Gltf, HostileFilesAreRefusedBeforeTheyCostMemory) {
    // Past the memory limit (the node takes 256 bytes of it): the accessor, not an allocation, fails.
    const auto file = tinyFile("sgfx_tiny_limit.gltf", {0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2});
    const std::string limited = memoryLoadError(readBytes(file), {.memoryLimit = 276});
    EXPECT_NE(limited.find("accessors[0]: needs more memory than the load's limit of 276 bytes"),
              std::string::npos)
        << limited;
    std::filesystem::remove(file);
    // A sparse accessor without a bufferView declares 2^28 zero vectors from a few bytes.
    const std::string sparse =
        memoryLoadError(glb(R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"buffers":[{"byteLength":8}],
"bufferViews":[{"buffer":0,"byteLength":8}],
"accessors":[{"componentType":5126,"count":268435456,"type":"VEC3","sparse":{"count":1,
"indices":{"bufferView":0,"componentType":5125},"values":{"bufferView":0}}}]})",
                            8),
                        {.memoryLimit = std::size_t(64) << 20});
    EXPECT_NE(sparse.find("needs more memory"), std::string::npos) << sparse;
    // A node used twice by each of 60 nested nodes: 2^60 instances.
    std::string nodes;
    for (int i = 0; i < 60; ++i)
        nodes += "{\"children\":[" + std::to_string(i + 1) + "," + std::to_string(i + 1) + "]},";
    nodes += "{}";
    const std::string doubling = memoryLoadError(
        glb(R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[)" + nodes + "]}", 0),
        {.memoryLimit = std::size_t(16) << 20});
    EXPECT_NE(doubling.find("needs more memory"), std::string::npos) << doubling;
    // Nesting deep enough to overflow tinygltf's recursive copy of `extras`.
    const std::string deep = memoryLoadError(glb(
        R"({"asset":{"version":"2.0"},"extras":)" + std::string(100000, '[') + std::string(100000, ']') + "}",
        0));
    EXPECT_NE(deep.find("nested more than 256 deep"), std::string::npos) << deep;
    // tinygltf 2.7 throws std::out_of_range for a GLB buffer of byteLength 0: a LoadError here.
    const std::string empty =
        memoryLoadError(glb(R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":0}]})", 4));
    EXPECT_NE(empty.find("in-memory.glb"), std::string::npos) << empty;
    // A material factor that is negative is refused with its element, not std::invalid_argument.
    const std::string negative = memoryLoadError(glb(
        R"({"asset":{"version":"2.0"},"materials":[{"pbrMetallicRoughness":{"baseColorFactor":[-1,0,0,1]}}]})",
        0));
    EXPECT_NE(negative.find("materials[0]"), std::string::npos) << negative;
}

namespace {
// tinyFile's triangle with its "asset" object replaced.
std::filesystem::path withAsset(const std::string& name, const std::string& asset) {
    return tinyFile(name, {0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2}, [&](std::string& j) {
        const std::string from = R"("asset":{"version":"2.0"})";
        j.replace(j.find(from), from.size(), "\"asset\":" + asset);
    });
}

// tinyFile's triangle with `"byteStride":stride` on its positions' buffer view.
std::filesystem::path withStride(const std::string& name, const std::string& stride) {
    return tinyFile(name, {0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2}, [&](std::string& j) {
        j.insert(j.find(R"("byteOffset":0,)"), "\"byteStride\":" + stride + ",");
    });
}
} // namespace

TEST(Gltf, OnlyGltf2IsRead) {
    // Refused: another major version, a minVersion past 2.0, a version not of the form MAJOR.MINOR.
    expectLoadError(withAsset("sgfx_version3.gltf", R"({"version":"3.0"})"),
                    R"(asset.version: "3.0" is not supported: this loader reads glTF 2.x)");
    expectLoadError(withAsset("sgfx_version1.gltf", R"({"version":"1.0"})"),
                    R"(asset.version: "1.0" is not supported: this loader reads glTF 2.x)");
    expectLoadError(withAsset("sgfx_minversion.gltf", R"({"version":"2.1","minVersion":"2.1"})"),
                    "asset.minVersion: 2.1 is newer than the 2.0 this loader reads");
    expectLoadError(withAsset("sgfx_version_form.gltf", R"({"version":"2.0.1"})"),
                    R"(asset.version: "2.0.1" is not of the form MAJOR.MINOR (such as "2.0"))");
    expectLoadError(withAsset("sgfx_version_v.gltf", R"({"version":"v2.0"})"),
                    R"(asset.version: "v2.0" is not of the form MAJOR.MINOR)");
    expectLoadError(withAsset("sgfx_version_empty.gltf", R"({"version":""})"),
                    R"(asset.version: "" is not of the form MAJOR.MINOR)");
    expectLoadError(withAsset("sgfx_minversion_form.gltf", R"({"version":"2.0","minVersion":"2"})"),
                    R"(asset.minVersion: "2" is not of the form MAJOR.MINOR)");
    expectLoadError(withAsset("sgfx_version_number.gltf", R"({"version":2.0})"),
                    R"(asset.version: 2.0 is not a string such as "2.0")");
    expectLoadError(withAsset("sgfx_version_missing.gltf", R"({"generator":"x"})"),
                    "asset.version: is missing");
    // Read: 2.0 with minVersion 2.0; 2.1 without minVersion (minor versions only add to 2.0).
    for (const char* asset : {R"({"version":"2.0","minVersion":"2.0"})", R"({"version":"2.1"})"}) {
        SCOPED_TRACE(asset);
        const auto file = withAsset("sgfx_version_ok.gltf", asset);
        GltfStats st;
        EXPECT_NO_THROW((void)loadGltf(file, {}, &st));
        EXPECT_EQ(st.triangles, 1u);
        std::filesystem::remove(file);
    }
    // From memory too, where the name stands in for the file's.
    const std::string glb3 = memoryLoadError(glb(R"({"asset":{"version":"3.0"}})", 0));
    EXPECT_NE(glb3.find(R"(sgfx: glTF 'in-memory.glb': asset.version: "3.0" is not supported)"),
              std::string::npos)
        << glb3;
}

TEST(Gltf, ByteStrideIsAMultipleOfFourIn4To252) {
    expectLoadError(withStride("sgfx_stride_negative.gltf", "-4"),
                    "bufferViews[0].byteStride: -4 is outside 4..252");
    expectLoadError(withStride("sgfx_stride_2.gltf", "2"), "bufferViews[0].byteStride: 2 is outside 4..252");
    expectLoadError(withStride("sgfx_stride_0.gltf", "0"), "bufferViews[0].byteStride: 0 is outside 4..252");
    expectLoadError(withStride("sgfx_stride_256.gltf", "256"),
                    "bufferViews[0].byteStride: 256 is outside 4..252");
    expectLoadError(withStride("sgfx_stride_6.gltf", "6"),
                    "bufferViews[0].byteStride: 6 is not a multiple of 4");
    expectLoadError(withStride("sgfx_stride_float.gltf", "4.5"),
                    "bufferViews[0].byteStride: 4.5 is not an integer");
    // In range but smaller than the VEC3 of floats read through it.
    expectLoadError(withStride("sgfx_stride_8.gltf", "8"),
                    "bufferViews[0].byteStride: 8 is less than the 12 bytes of each element of accessors[0] "
                    "(used by meshes[0].primitives[0].attributes.POSITION)");
    const auto file = withStride("sgfx_stride_12.gltf", "12");
    ComputeBoundsVisitor bounds;
    loadGltf(file, {.zUp = false})->accept(bounds);
    EXPECT_EQ(bounds.max, glm::vec3(1.0f, 1.0f, 0.0f));
    std::filesystem::remove(file);
}

TEST(Gltf, BadIndicesNameTheMeshAndPrimitive) {
    const std::vector<float> tri{0, 0, 0, 1, 0, 0, 0, 1, 0};
    // An index past the vertices: the value, where it is and how many vertices there are.
    expectLoadError(
        tinyFile("sgfx_index_57.gltf", tri, {0, 57, 2}),
        "meshes[0].primitives[0].indices: index 57 (entry 1 of accessors[1]) is out of range for 3 "
        "vertices");
    // An indices accessor that does not exist (tinygltf's own message names neither mesh nor primitive).
    auto indices = [&](const std::string& name, const std::string& value) {
        return tinyFile(name, tri, {0, 1, 2}, [&](std::string& j) {
            j.replace(j.find(R"("indices":1)"), 11, "\"indices\":" + value);
        });
    };
    expectLoadError(indices("sgfx_indices_5.gltf", "5"),
                    "meshes[0].primitives[0].indices: accessor 5 does not exist (2 accessors)");
    // A negative one, which tinygltf takes for "no indices".
    expectLoadError(indices("sgfx_indices_negative.gltf", "-1"),
                    "meshes[0].primitives[0].indices: -1 is not an accessor index");
    // An indices accessor without a buffer view.
    expectLoadError(tinyFile("sgfx_indices_no_view.gltf", tri, {0, 1, 2},
                             [](std::string& j) { j.replace(j.find(R"("bufferView":1,)"), 15, ""); }),
                    "meshes[0].primitives[0].indices: accessors[1] has no bufferView");
}

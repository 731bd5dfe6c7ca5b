// glTF features beyond the core: hand-made files for KHR_texture_transform, TEXCOORD_1,
// KHR_materials_emissive_strength, the metallic-roughness material's factors and maps and
// EXT_mesh_gpu_instancing, each with exact expected values; extension policy (unknown required:
// error, unknown optional: warning); crease-angle normals and made tangents; and every shared
// model's primitives match their accessors' min/max.
#include "TestUtil.h"

#include <sgfx/Geometry.h>
#include <sgfx/GltfLoader.h>
#include <sgfx/Group.h>
#include <sgfx/Material.h>
#include <sgfx/NodeVisitor.h>
#include <sgfx/StateSet.h>
#include <sgfx/Visitors.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

using namespace sgfx;
using namespace sgfx::test;

namespace {

const std::filesystem::path kAssets =
    std::filesystem::path(SGFX_SOURCE_DIR) / ".." / "shared" / "assets" / "gltf";

// Builds a one-buffer glTF: float accessors appended with add(), the rest of the JSON given.
struct Builder {
    std::vector<unsigned char> bytes;
    std::string views, accessors;
    int count = 0;
    int add(const std::vector<float>& values, const char* type, int components) {
        const std::size_t offset = bytes.size();
        for (float f : values) {
            unsigned char b[4];
            std::memcpy(b, &f, 4);
            bytes.insert(bytes.end(), b, b + 4);
        }
        const std::string sep = count ? "," : "";
        views += sep + "{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) +
                 ",\"byteLength\":" + std::to_string(values.size() * 4) + "}";
        accessors += sep + "{\"bufferView\":" + std::to_string(count) + ",\"componentType\":5126,\"count\":" +
                     std::to_string(values.size() / std::size_t(components)) + ",\"type\":\"" + type + "\"}";
        return count++;
    }
    std::filesystem::path write(const std::string& name, const std::string& rest) const {
        const std::string json =
            "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":" + std::to_string(bytes.size()) +
            ",\"uri\":\"data:application/octet-stream;base64," + base64(bytes) + "\"}],\"bufferViews\":[" +
            views + "],\"accessors\":[" + accessors + "]," + rest + "}";
        const auto path = std::filesystem::temp_directory_path() / name;
        std::ofstream(path) << json;
        return path;
    }
};

class CollectGeometry : public NodeVisitor {
public:
    CollectGeometry()
        : NodeVisitor(Mode::AllChildren) {}
    void apply(Geometry& g) override {
        found.push_back(std::static_pointer_cast<Geometry>(g.shared_from_this()));
    }
    std::vector<std::shared_ptr<Geometry>> found;
};

std::vector<std::shared_ptr<Geometry>> geometriesOf(Node& root) {
    CollectGeometry c;
    root.accept(c);
    return c.found;
}

const Material& materialOf(const Geometry& g) {
    return **g.stateSet()->material.value;
}

// One triangle with two UV sets, a textured metallic-roughness material and an instanced node.
std::filesystem::path featureFile(const std::string& name, const std::string& extraTop = "") {
    // A 2×1 PNG beside the file for every texture slot.
    auto img = Image::create(2, 1, 4);
    img->pixels = {255, 0, 0, 255, 0, 0, 255, 255};
    writePng(std::filesystem::temp_directory_path() / "sgfx_feature_texture.png", *img);
    Builder b;
    b.add({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);                              // 0 POSITION
    b.add({0, 0, 1, 0, 0, 1}, "VEC2", 2);                                       // 1 TEXCOORD_0
    b.add({0.5f, 0.5f, 0.25f, 0.75f, 1, 0}, "VEC2", 2);                         // 2 TEXCOORD_1
    b.add({1, 2, 3, -4, 5, 6}, "VEC3", 3);                                      // 3 TRANSLATION
    b.add({0, 0, 0.38268343f, 0.92387953f, 0.5f, 0.5f, 0.5f, 0.5f}, "VEC4", 4); // 4 ROTATION
    b.add({1, 1, 1, 2, 0.5f, 3}, "VEC3", 3);                                    // 5 SCALE
    return b.write(name, extraTop + R"(
"scene":0,"scenes":[{"nodes":[0,1]}],
"nodes":[{"mesh":0},{"mesh":0,"extensions":{"EXT_mesh_gpu_instancing":{"attributes":{"TRANSLATION":3,"ROTATION":4,"SCALE":5}}}}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1,"TEXCOORD_1":2},"material":0}]}],
"images":[{"uri":"sgfx_feature_texture.png"}],
"textures":[{"source":0}],
"materials":[{
  "pbrMetallicRoughness":{"baseColorFactor":[0.5,0.6,0.7,1],"metallicFactor":0.3,"roughnessFactor":0.6,
    "baseColorTexture":{"index":0,"texCoord":1,"extensions":{"KHR_texture_transform":{"offset":[0.25,0.5],"rotation":0.5,"scale":[2,3]}}},
    "metallicRoughnessTexture":{"index":0}},
  "normalTexture":{"index":0,"scale":0.7},
  "occlusionTexture":{"index":0,"strength":0.4,"texCoord":1},
  "emissiveTexture":{"index":0,"extensions":{"KHR_texture_transform":{"texCoord":1,"offset":[0.5,0]}}},
  "emissiveFactor":[0.5,0.25,1],
  "extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":4}}}]
)");
}

} // namespace

TEST(GltfFeatures, MaterialFactorsMapsAndTextureTransformsLoadExactly) {
    GltfStats st;
    const auto root = loadGltf(
        featureFile(
            "sgfx_features.gltf",
            R"("extensionsUsed":["KHR_texture_transform","KHR_materials_emissive_strength","EXT_mesh_gpu_instancing"],)"),
        {}, &st);
    EXPECT_TRUE(st.warnings.empty()) << st.warnings.front();
    const auto geos = geometriesOf(*root);
    ASSERT_EQ(geos.size(), 2u);
    const Geometry& g = *geos[0];
    ASSERT_EQ(g.texcoords1.size(), 3u);
    EXPECT_EQ(g.texcoords1[1], glm::vec2(0.25f, 0.75f));
    const Material& m = materialOf(g);
    EXPECT_EQ(m.model, ShadingModel::MetallicRoughness);
    EXPECT_EQ(m.diffuse, glm::vec4(0.5f, 0.6f, 0.7f, 1.0f));
    EXPECT_FLOAT_EQ(m.metallic, 0.3f);
    EXPECT_FLOAT_EQ(m.roughness, 0.6f);
    EXPECT_EQ(m.emissive, glm::vec3(2.0f, 1.0f, 4.0f)); // factor × strength 4
    EXPECT_FLOAT_EQ(m.normalScale, 0.7f);
    EXPECT_FLOAT_EQ(m.occlusionStrength, 0.4f);
    ASSERT_TRUE(m.baseColorTexture && m.metallicRoughnessTexture && m.normalTexture && m.occlusionTexture &&
                m.emissiveTexture);
    EXPECT_TRUE(m.baseColorTexture->srgb);
    EXPECT_FALSE(m.metallicRoughnessTexture->srgb);
    EXPECT_TRUE(m.emissiveTexture->srgb);
    const TextureMapping& base = m.mapping(MaterialMap::BaseColor);
    EXPECT_EQ(base.texCoord, 1);
    EXPECT_EQ(base.offset, glm::vec2(0.25f, 0.5f));
    EXPECT_FLOAT_EQ(base.rotation, 0.5f);
    EXPECT_EQ(base.scale, glm::vec2(2.0f, 3.0f));
    // The extension's matrix: T · R · S with R = [[cos, sin], [−sin, cos]] (row-major).
    const glm::vec3 uv = base.matrix() * glm::vec3(1.0f, 0.0f, 1.0f);
    EXPECT_NEAR(uv.x, 0.25f + 2.0f * std::cos(0.5f), 1e-6f);
    EXPECT_NEAR(uv.y, 0.5f - 2.0f * std::sin(0.5f), 1e-6f);
    EXPECT_EQ(m.mapping(MaterialMap::Occlusion).texCoord, 1);
    // The extension's texCoord overrides the textureInfo's.
    EXPECT_EQ(m.mapping(MaterialMap::Emissive).texCoord, 1);
    EXPECT_EQ(m.mapping(MaterialMap::Emissive).offset, glm::vec2(0.5f, 0.0f));
    EXPECT_TRUE(m.mapping(MaterialMap::MetallicRoughness).isIdentity());
    // A normal map and no TANGENT: tangents made for the primitive.
    EXPECT_EQ(g.tangents.size(), g.positions.size());
    EXPECT_EQ(st.tangentsMade, 1u);
}

TEST(GltfFeatures, GpuInstancingBecomesOneInstancedDraw) {
    GltfStats st;
    const auto root = loadGltf(featureFile("sgfx_instancing.gltf"), {}, &st);
    const auto geos = geometriesOf(*root);
    ASSERT_EQ(geos.size(), 2u);
    EXPECT_TRUE(geos[0]->instances.empty());
    const Geometry& inst = *geos[1];
    ASSERT_EQ(inst.instances.size(), 2u);
    EXPECT_EQ(st.instances, 2u);
    // The plain node and the instanced one share vertex data by value but not the node.
    EXPECT_EQ(inst.positions, geos[0]->positions);
    EXPECT_EQ(inst.stateSet(), geos[0]->stateSet());
    const glm::mat4 expected[2] = {glm::translate(glm::mat4(1.0f), {1, 2, 3}) *
                                       glm::mat4_cast(glm::quat(0.92387953f, 0.0f, 0.0f, 0.38268343f)),
                                   glm::scale(glm::translate(glm::mat4(1.0f), {-4, 5, 6}) *
                                                  glm::mat4_cast(glm::quat(0.5f, 0.5f, 0.5f, 0.5f)),
                                              {2.0f, 0.5f, 3.0f})};
    for (int i = 0; i < 2; ++i)
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                EXPECT_NEAR(inst.instances[std::size_t(i)][c][r], expected[i][c][r], 1e-6f)
                    << i << " " << c << r;
    EXPECT_EQ(inst.triangleCount(), 2u);

    // Drawn: one call for both instances, and each instance's triangle covers its projected spot.
    auto v = Viewer::createHeadless(64, 64);
    auto& cam = *v->camera();
    cam.setLookAt({0, -40, 0}, {0, 0, 0}, {0, 0, 1});
    cam.setPerspective(40.0f, 1.0f, 100.0f);
    auto scene = Group::create();
    scene->addChild(root);
    v->setSceneData(scene);
    v->frame();
    EXPECT_EQ(v->renderer().stats().drawCalls, 2u); // the plain node + one instanced draw
    EXPECT_EQ(v->renderer().stats().triangles, 3u);
}

TEST(GltfFeatures, ExtensionPolicyRequiredFailsOptionalWarns) {
    try {
        (void)loadGltf(
            featureFile("sgfx_required.gltf", R"("extensionsRequired":["KHR_draco_mesh_compression"],
"extensionsUsed":["KHR_draco_mesh_compression"],)"));
        ADD_FAILURE() << "loaded";
    } catch (const LoadError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("extensionsRequired"), std::string::npos) << what;
        EXPECT_NE(what.find("KHR_draco_mesh_compression"), std::string::npos) << what;
        EXPECT_NE(what.find("sgfx_required.gltf"), std::string::npos) << what;
    }
    GltfStats st;
    (void)loadGltf(featureFile("sgfx_optional.gltf", R"("extensionsUsed":["KHR_materials_iridescence"],)"),
                   {}, &st);
    ASSERT_EQ(st.warnings.size(), 1u);
    EXPECT_NE(st.warnings[0].find("KHR_materials_iridescence"), std::string::npos);

    // Malformed extension data names the element.
    const auto bad = featureFile("sgfx_bad_transform.gltf");
    std::string text;
    {
        std::ifstream in(bad);
        text.assign(std::istreambuf_iterator<char>(in), {});
    }
    text.replace(text.find("\"rotation\":0.5"), 14, "\"rotation\":\"a\"");
    std::ofstream(bad) << text;
    try {
        (void)loadGltf(bad);
        ADD_FAILURE() << "loaded";
    } catch (const LoadError& e) {
        EXPECT_NE(std::string(e.what()).find("materials[0].pbrMetallicRoughness.baseColorTexture.extensions."
                                             "KHR_texture_transform.rotation"),
                  std::string::npos)
            << e.what();
    }
}

TEST(GltfFeatures, CreaseAngleSmoothsNormalsMadeForTheFile) {
    // A tent: two triangles meeting along x = 0 whose normals are 60° apart, no normals in the file.
    Builder b;
    b.add({0, 0, 0, 0, 1, 0, -1, 0, -0.57735027f, 0, 0, 0, 1, 0, -0.57735027f, 0, 1, 0}, "VEC3", 3);
    const std::string rest = R"("scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}])";
    const auto file = b.write("sgfx_tent.gltf", rest);
    GltfOptions flat;
    flat.zUp = false;
    const auto g0 = geometriesOf(*loadGltf(file, flat)).at(0);
    GltfOptions smooth = flat;
    smooth.creaseAngle = glm::radians(70.0f); // the faces' normals differ by 60°
    const auto g1 = geometriesOf(*loadGltf(file, smooth)).at(0);
    GltfOptions sharp = flat;
    sharp.creaseAngle = glm::radians(50.0f);
    const auto g2 = geometriesOf(*loadGltf(file, sharp)).at(0);
    // Flat and sharp: two face normals. Smooth: the ridge shares their mean, (0, 0, 1).
    auto ridgeNormals = [](const Geometry& g) {
        std::vector<glm::vec3> out;
        for (std::size_t i = 0; i < g.positions.size(); ++i)
            if (g.positions[i].x == 0.0f) out.push_back(g.normals[i]);
        return out;
    };
    for (const glm::vec3 n : ridgeNormals(*g1))
        EXPECT_NEAR(glm::distance(n, glm::vec3(0, 0, 1)), 0.0f, 1e-5f);
    EXPECT_EQ(g1->positions.size(), 4u); // ridge vertices welded
    for (const auto& g : {g0, g2}) {
        EXPECT_EQ(g->positions.size(), 6u);
        for (const glm::vec3 n : ridgeNormals(*g))
            EXPECT_NEAR(std::abs(n.x), 0.5f, 1e-5f);
    }
}

TEST(GltfFeatures, SharedModelsMatchTheirAccessorBounds) {
    // Every primitive's vertex positions span exactly its POSITION accessor's min/max.
    SGFX_REQUIRE(std::filesystem::exists(kAssets), "the shared assets at " << kAssets);
    for (const char* file : {"Box/glTF-Binary/Box.glb", "BoxTextured/glTF-Binary/BoxTextured.glb",
                             "Duck/glTF-Binary/Duck.glb", "AlphaBlendModeTest/glTF/AlphaBlendModeTest.gltf",
                             "NormalTangentMirrorTest/glTF/NormalTangentMirrorTest.gltf",
                             "TextureCoordinateTest/glTF/TextureCoordinateTest.gltf",
                             "OrientationTest/glTF/OrientationTest.gltf",
                             "MetalRoughSpheresNoTextures/glTF/MetalRoughSpheresNoTextures.gltf"}) {
        SCOPED_TRACE(file);
        tinygltf::TinyGLTF reader;
        tinygltf::Model model;
        std::string err, warn;
        const std::string path = (kAssets / file).string();
        ASSERT_TRUE(std::string(file).ends_with(".glb") ? reader.LoadBinaryFromFile(&model, &err, &warn, path)
                                                        : reader.LoadASCIIFromFile(&model, &err, &warn, path))
            << err;
        std::multimap<std::string, std::pair<glm::vec3, glm::vec3>> expected;
        for (std::size_t mi = 0; mi < model.meshes.size(); ++mi)
            for (std::size_t pi = 0; pi < model.meshes[mi].primitives.size(); ++pi) {
                const auto& a =
                    model.accessors[std::size_t(model.meshes[mi].primitives[pi].attributes.at("POSITION"))];
                ASSERT_EQ(a.minValues.size(), 3u);
                const std::string name =
                    model.meshes[mi].name.empty()
                        ? "meshes[" + std::to_string(mi) + "].primitives[" + std::to_string(pi) + "]"
                        : model.meshes[mi].name + "." + std::to_string(pi);
                expected.emplace(name, std::pair{glm::vec3(a.minValues[0], a.minValues[1], a.minValues[2]),
                                                 glm::vec3(a.maxValues[0], a.maxValues[1], a.maxValues[2])});
            }
        const auto root = loadGltf(kAssets / file);
        const auto geos = geometriesOf(*root);
        ASSERT_FALSE(geos.empty());
        for (const auto& g : geos) {
            BoundingBox box;
            for (const glm::vec3& p : g->positions)
                box.expandBy(p);
            const auto [lo, hi] = expected.equal_range(g->name);
            ASSERT_NE(lo, hi) << g->name;
            bool match = false;
            for (auto it = lo; it != hi; ++it)
                match = match ||
                        (glm::all(glm::lessThan(glm::abs(box.min - it->second.first), glm::vec3(1e-4f))) &&
                         glm::all(glm::lessThan(glm::abs(box.max - it->second.second), glm::vec3(1e-4f))));
            EXPECT_TRUE(match) << g->name << " spans (" << box.min.x << "," << box.min.y << "," << box.min.z
                               << ")..(" << box.max.x << "," << box.max.y << "," << box.max.z << ")";
        }
    }
}

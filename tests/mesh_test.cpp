// OBJ/OFF/PLY/STL through OpenMesh: round trips through the writer keep the vertex positions and
// the triangle count; normals are made when a file has none; bad files say why.
#include "TestUtil.h"

#include <sgfx/Image.h>
#include <sgfx/Material.h>
#include <sgfx/MeshLoader.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/Shapes.h>
#include <sgfx/StateSet.h>
#include <sgfx/Visitors.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

using namespace sgfx;

namespace {
const std::filesystem::path kAssets =
    std::filesystem::path(SGFX_SOURCE_DIR) / ".." / "shared" / "assets" / "gltf";

// A fresh directory for one test's files.
std::filesystem::path tempDir(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / ("sgfx_" + name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

std::string loadError(const std::function<void()>& load) {
    try {
        load();
    } catch (const LoadError& e) {
        return e.what();
    }
    return "loaded";
}

const Material& materialOf(const Node& node) {
    EXPECT_TRUE(node.stateSet() && node.stateSet()->material.value);
    return **node.stateSet()->material.value;
}

bool contains(const std::vector<glm::vec3>& set, glm::vec3 p) {
    return std::any_of(set.begin(), set.end(),
                       [&](const glm::vec3& q) { return glm::length(q - p) < 1e-5f; });
}
} // namespace

TEST(Mesh, RoundTripsKeepPositionsAndTriangles) {
    const auto box = shapes::box({1.0f, 2.0f, 3.0f});
    const auto sphere = shapes::sphere(1.5f, 12, 6);
    for (const auto& source : {box, sphere})
        for (const char* ext : {".obj", ".off", ".ply", ".stl"}) {
            SCOPED_TRACE(std::string(ext) + " " + std::to_string(source->triangleCount()) + " triangles");
            const auto file = std::filesystem::temp_directory_path() / (std::string("sgfx_roundtrip") + ext);
            writeMesh(*source, file);
            const auto loaded = loadMesh(file);
            // STL keeps no vertex identity: vertices are merged by position on reading, so the
            // sphere's zero-area pole triangles collapse and are dropped.
            std::size_t expected = source->triangleCount();
            if (std::string(ext) == ".stl") {
                expected = 0;
                for (std::size_t k = 0; k + 2 < source->indices.size(); k += 3) {
                    const glm::vec3 a = source->positions[source->indices[k]],
                                    b = source->positions[source->indices[k + 1]],
                                    c = source->positions[source->indices[k + 2]];
                    expected += a != b && b != c && a != c; // identical corners merge into a non-face
                }
            }
            EXPECT_EQ(loaded->triangleCount(), expected);
            for (const glm::vec3& p : source->positions)
                ASSERT_TRUE(contains(loaded->positions, p));
            for (const glm::vec3& p : loaded->positions)
                ASSERT_TRUE(contains(source->positions, p));
            ASSERT_EQ(loaded->normals.size(), loaded->positions.size());
            for (const glm::vec3& n : loaded->normals)
                EXPECT_NEAR(glm::length(n), 1.0f, 1e-4f);
            std::filesystem::remove(file);
        }
}

TEST(Mesh, NormalsAreMadeWhenTheFileHasNone) {
    const auto file = std::filesystem::temp_directory_path() / "sgfx_plain.off";
    std::ofstream(file) << "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
    const auto g = loadMesh(file);
    EXPECT_EQ(g->triangleCount(), 2u);
    for (const glm::vec3& n : g->normals)
        EXPECT_NEAR(n.z, 1.0f, 1e-5f);
    std::filesystem::remove(file);
}

TEST(Mesh, BadFilesSayWhy) {
    auto expectError = [](const std::filesystem::path& file, const std::string& needle) {
        try {
            (void)loadMesh(file);
            ADD_FAILURE() << "loaded " << file;
        } catch (const LoadError& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    expectError("/nonexistent/part.stl", "no such file");
    expectError("part.fbx", "is not one of");
    const auto garbage = std::filesystem::temp_directory_path() / "sgfx_garbage.off";
    std::ofstream(garbage) << "this is not an OFF file";
    expectError(garbage, "could not read");
    std::filesystem::remove(garbage);
    auto lines = shapes::box({1, 1, 1});
    lines->mode = PrimitiveMode::Lines;
    EXPECT_THROW(writeMesh(*lines, std::filesystem::temp_directory_path() / "sgfx_lines.obj"), LoadError);
}

namespace {

// Two materials, one textured: a quad and a triangle in "red" (normals from the file and made),
// one triangle in "m l" with texcoords; a 2×1 PNG whose right texel is blue.
std::filesystem::path writeObjScene(const std::filesystem::path& dir, const std::string& mtl) {
    Image img;
    img.width = 2;
    img.height = 1;
    img.channels = 4;
    img.pixels = {255, 0, 0, 255, 0, 0, 255, 255};
    writePng(dir / "tex.png", img);
    std::ofstream(dir / "scene.mtl") << mtl;
    std::ofstream(dir / "scene.obj") << "# two materials\nmtllib scene.mtl\n"
                                        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
                                        "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
                                        "usemtl red\nf 1//1 2//1 3//1 4//1\n"
                                        "usemtl m l\nf 1/1 2/2 5/3\n"
                                        "usemtl red\nf -1 -2 -3\n";
    return dir / "scene.obj";
}

const char* kSceneMtl = "newmtl red\nKd 1 0 0\nKa 0.1 0.2 0.3\nKs 0.5 0.5 0.5\nNs 64\nKe 0 0.25 0\nd 0.5\n"
                        "illum 2\n\nnewmtl m l\nKd 0.8 0.8 0.8\nmap_Kd -s 1 1 1 tex.png\n";

} // namespace

TEST(Mesh, ObjWithMtlHasOneGeometryPerMaterial) {
    const auto root = loadMeshModel(writeObjScene(tempDir("obj_mtl"), kSceneMtl));
    ASSERT_EQ(root->numChildren(), 2u);
    const auto& red = dynamic_cast<const Geometry&>(*root->child(0));
    const auto& textured = dynamic_cast<const Geometry&>(*root->child(1));
    EXPECT_EQ(red.name, "red");
    EXPECT_EQ(red.triangleCount(), 3u);  // the quad's two and the one by negative indices
    EXPECT_EQ(red.positions.size(), 7u); // the shared corners split: file normal vs made normal
    EXPECT_TRUE(red.texcoords.empty());
    const Material& r = materialOf(red);
    EXPECT_EQ(r.diffuse, glm::vec4(1, 0, 0, 0.5f));
    EXPECT_EQ(r.ambient, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_EQ(r.specular, glm::vec3(0.5f));
    EXPECT_EQ(r.shininess, 64.0f);
    EXPECT_EQ(r.emissive, glm::vec3(0, 0.25f, 0));
    EXPECT_EQ(red.stateSet()->blend.value, BlendMode::Alpha); // d < 1
    for (const glm::vec3& n : red.normals)
        EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);

    EXPECT_EQ(textured.name, "m l"); // a name with a space, letters of the keywords
    EXPECT_EQ(textured.triangleCount(), 1u);
    ASSERT_EQ(textured.texcoords.size(), 3u);
    EXPECT_EQ(textured.texcoords[0], glm::vec2(0, 1)); // OBJ (0, 0) is the bottom-left corner
    EXPECT_EQ(textured.texcoords[2], glm::vec2(1, 0));
    const Material& t = materialOf(textured);
    EXPECT_EQ(t.diffuse, glm::vec4(0.8f, 0.8f, 0.8f, 1.0f));
    EXPECT_EQ(t.ambient, glm::vec3(0.8f)); // Kd when there is no Ka
    EXPECT_FALSE(textured.stateSet()->blend.value);
    ASSERT_TRUE(t.baseColorTexture && t.baseColorTexture->image);
    const Image& img = *t.baseColorTexture->image;
    EXPECT_EQ(img.width, 2);
    EXPECT_EQ(img.height, 1);
    EXPECT_TRUE(t.baseColorTexture->srgb);
    EXPECT_EQ(img.pixel(1, 0)[0], 0);
    EXPECT_EQ(img.pixel(1, 0)[2], 255);
}

TEST(Mesh, ObjWithoutItsMtlFallsBackToTheDefaultMaterial) {
    const auto dir = tempDir("obj_nomtl");
    const auto obj = writeObjScene(dir, kSceneMtl);
    std::filesystem::remove(dir / "scene.mtl");
    const auto root = loadMeshModel(obj);
    ASSERT_EQ(root->numChildren(), 2u);
    EXPECT_FALSE(root->child(0)->stateSet());
    EXPECT_EQ(dynamic_cast<const Geometry&>(*root->child(0)).triangleCount(), 3u);
}

TEST(Mesh, BadObjAndMtlFilesNameTheLine) {
    const auto dir = tempDir("obj_bad");
    const auto obj = writeObjScene(dir, "newmtl red\nKd 1 0 0\nKs 1 x 0\n");
    std::string why = loadError([&] { (void)loadMeshModel(obj); });
    EXPECT_NE(why.find("scene.mtl:3"), std::string::npos) << why;
    EXPECT_NE(why.find("'x' is not a number"), std::string::npos) << why;

    writeObjScene(dir, "newmtl textured\nmap_Kd missing.png\n");
    why = loadError([&] { (void)loadMeshModel(obj); });
    EXPECT_NE(why.find("scene.mtl"), std::string::npos) << why;
    EXPECT_NE(why.find("material 'textured'"), std::string::npos) << why;
    EXPECT_NE(why.find("does not exist"), std::string::npos) << why;

    writeObjScene(dir, kSceneMtl);
    std::ofstream(dir / "tex.png") << "not a PNG";
    why = loadError([&] { (void)loadMeshModel(obj); });
    EXPECT_NE(why.find("material 'm l'"), std::string::npos) << why;
    EXPECT_NE(why.find("cannot be decoded"), std::string::npos) << why;

    std::ofstream(dir / "bad.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
    why = loadError([&] { (void)loadMeshModel(dir / "bad.obj"); });
    EXPECT_NE(why.find("bad.obj:4"), std::string::npos) << why;
    EXPECT_NE(why.find("vertex 9 of 3"), std::string::npos) << why;
}

TEST(Mesh, LoadModelChoosesTheLoaderByExtension) {
    const auto dir = tempDir("load_model");
    const auto obj = loadModel(writeObjScene(dir, kSceneMtl));
    EXPECT_EQ(obj->numChildren(), 2u);
    writeMesh(*shapes::box({1, 1, 1}), dir / "box.STL");
    const auto stl = loadModel(dir / "box.STL");
    ASSERT_EQ(stl->numChildren(), 1u);
    EXPECT_EQ(dynamic_cast<const Geometry&>(*stl->child(0)).triangleCount(), 12u);
    if (sgfx::test::optionalPrerequisite(std::filesystem::exists(kAssets),
                                         "the shared assets at " + kAssets.string())) {
        ComputeBoundsVisitor bounds;
        loadModel(kAssets / "Box/glTF-Binary/Box.glb")->accept(bounds);
        EXPECT_TRUE(bounds.valid());
    }
    const std::string why = loadError([&] { (void)loadModel(dir / "part.fbx"); });
    EXPECT_NE(why.find("part.fbx"), std::string::npos) << why;
    EXPECT_NE(why.find(".gltf, .glb, .obj, .off, .ply, .stl"), std::string::npos) << why;
}

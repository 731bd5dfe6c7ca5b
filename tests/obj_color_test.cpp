// OBJ vertex colours (`v x y z r g b`, as MeshLab, CloudCompare and OpenSceneGraph's tools write
// them): sRGB display values in 0..1 or 0..255, read by both OBJ readers into linear
// Geometry::colors, written back by both OBJ writers, checked on bad lines, and drawn.
#include "TestUtil.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Material.h>
#include <sgfx/MeshLoader.h>
#include <sgfx/ObjWriter.h>
#include <sgfx/StateSet.h>

#include <gtest/gtest.h>

#include <cfloat>
#include <filesystem>
#include <fstream>
#include <functional>

using namespace sgfx;
using namespace sgfx::test;

namespace {

// IEC 61966-2-1 sRGB decoding, written out here rather than taken from the loader.
double srgbDecode(double s) {
    return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}

std::filesystem::path writeFile(const std::string& name, const std::string& text) {
    const auto dir = std::filesystem::temp_directory_path() / "sgfx_obj_color";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / name) << text;
    return dir / name;
}

std::string loadError(const std::function<void()>& load) {
    try {
        load();
    } catch (const LoadError& e) {
        return e.what();
    }
    return "loaded";
}

const Geometry& geometryAt(const Group& root, std::size_t i) {
    return dynamic_cast<const Geometry&>(*root.child(i));
}

// The colour of the geometry's vertex at `position` (the loaders split and reorder vertices).
glm::vec4 colourAt(const Geometry& g, glm::vec3 position) {
    for (std::size_t i = 0; i < g.positions.size(); ++i)
        if (glm::length(g.positions[i] - position) < 1e-5f) return g.colors.at(i);
    ADD_FAILURE() << "no vertex at " << position.x << " " << position.y << " " << position.z;
    return glm::vec4(-1.0f);
}

void expectColour(const Geometry& g, glm::vec3 position, glm::dvec3 linear, double tolerance = 1e-6) {
    const glm::vec4 c = colourAt(g, position);
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(c[k], linear[k], tolerance) << g.name << " vertex (" << position.x << " " << position.y
                                                << " " << position.z << ") channel " << k;
    EXPECT_EQ(c.a, 1.0f);
}

} // namespace

TEST(ObjColor, ZeroToOneColoursAreDecodedFromSrgbToLinear) {
    // 0.02 lies on the linear segment of the curve, 0.5 and 0.8 on the power segment.
    const auto file = writeFile("unit.obj", "v 0 0 0 1 0 0.02\n"
                                            "v 1 0 0 0 0.5 0\n"
                                            "v 0 1 0 0.8 0.25 1\n"
                                            "f 1 2 3\n");
    const auto model = loadMeshModel(file);
    const std::shared_ptr<const Geometry> mesh = loadMesh(file);
    for (const Geometry* g : {&geometryAt(*model, 0), mesh.get()}) {
        SCOPED_TRACE(g == mesh.get() ? "loadMesh" : "loadMeshModel");
        ASSERT_EQ(g->colors.size(), g->positions.size());
        expectColour(*g, {0, 0, 0}, {1.0, 0.0, 0.02 / 12.92});
        expectColour(*g, {1, 0, 0}, {0.0, std::pow(0.555 / 1.055, 2.4), 0.0});
        expectColour(*g, {0, 1, 0}, {srgbDecode(0.8), srgbDecode(0.25), 1.0});
    }
    // sRGB 0.5 is about 0.214 in linear light: not the value in the file.
    EXPECT_NEAR(colourAt(*mesh, {1, 0, 0}).g, 0.2140, 1e-4);
}

TEST(ObjColor, ZeroTo255ColoursAreScaledWhenAnyComponentIsAboveOne) {
    const auto file = writeFile("bytes.obj", "v 0 0 0 255 0 0\n"
                                             "v 1 0 0 0 128 0\n"
                                             "v 0 1 0 10 20 30\n"
                                             "v 1 1 0 1 1 1\n" // in a 0..255 file: almost black
                                             "f 1 2 3\nf 2 4 3\n");
    const auto model = loadMeshModel(file);
    const std::shared_ptr<const Geometry> mesh = loadMesh(file);
    for (const Geometry* g : {&geometryAt(*model, 0), mesh.get()}) {
        SCOPED_TRACE(g == mesh.get() ? "loadMesh" : "loadMeshModel");
        expectColour(*g, {0, 0, 0}, {1.0, 0.0, 0.0});
        expectColour(*g, {1, 0, 0}, {0.0, srgbDecode(128.0 / 255.0), 0.0});
        expectColour(*g, {0, 1, 0},
                     {srgbDecode(10.0 / 255.0), srgbDecode(20.0 / 255.0), srgbDecode(30.0 / 255.0)});
        expectColour(*g, {1, 1, 0}, glm::dvec3(srgbDecode(1.0 / 255.0)));
    }
}

TEST(ObjColor, VerticesWithoutAColourAreWhiteAndUncolouredGroupsHaveNone) {
    // MeshLab writes a colour on every vertex; a file that mixes takes white for the others, the
    // colour that leaves the material's as it is. A material group with no coloured vertex has none.
    const auto file = writeFile("mixed.obj", "v 0 0 0 0 0 1\n"
                                             "v 1 0 0\n"
                                             "v 0 1 0 1\n" // x y z w
                                             "v 5 5 0\nv 6 5 0\nv 5 6 0\n"
                                             "usemtl a\nf 1 2 3\n"
                                             "usemtl b\nf 4 5 6\n");
    const auto model = loadMeshModel(file);
    ASSERT_EQ(model->numChildren(), 2u);
    const Geometry& a = geometryAt(*model, 0);
    expectColour(a, {0, 0, 0}, {0, 0, 1});
    expectColour(a, {1, 0, 0}, {1, 1, 1});
    expectColour(a, {0, 1, 0}, {1, 1, 1});
    EXPECT_TRUE(geometryAt(*model, 1).colors.empty());
    const std::shared_ptr<const Geometry> mesh = loadMesh(file);
    expectColour(*mesh, {0, 0, 0}, {0, 0, 1});
    expectColour(*mesh, {6, 5, 0}, {1, 1, 1});
    // No colour at all: no colour array (the material alone, as before).
    EXPECT_TRUE(loadMesh(writeFile("plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"))->colors.empty());
}

TEST(ObjColor, LoadMeshColoursTheVerticesOpenMeshCopiesForNonManifoldFaces) {
    // A third face on the edge 1-2: OpenMesh adds it with new copies of its three vertices.
    const auto file = writeFile("fan.obj", "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\n"
                                           "v 0 -1 0 0.5 0.5 0.5\nv 0 0 1 1 1 0\n"
                                           "f 1 2 3\nf 2 1 4\nf 1 2 5\n");
    const std::shared_ptr<const Geometry> mesh = loadMesh(file);
    ASSERT_GT(mesh->positions.size(), 5u) << "OpenMesh no longer copies vertices: this test checks nothing";
    ASSERT_EQ(mesh->colors.size(), mesh->positions.size());
    const std::vector<std::pair<glm::vec3, glm::dvec3>> file_ = {{{0, 0, 0}, {1, 0, 0}},
                                                                 {{1, 0, 0}, {0, 1, 0}},
                                                                 {{0, 1, 0}, {0, 0, 1}},
                                                                 {{0, -1, 0}, glm::dvec3(srgbDecode(0.5))},
                                                                 {{0, 0, 1}, {1, 1, 0}}};
    for (std::size_t i = 0; i < mesh->positions.size(); ++i) {
        const auto it = std::find_if(file_.begin(), file_.end(),
                                     [&](const auto& v) { return v.first == mesh->positions[i]; });
        ASSERT_NE(it, file_.end());
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(mesh->colors[i][k], it->second[k], 1e-6) << "vertex " << i << " channel " << k;
    }
}

TEST(ObjColor, BadVertexLinesNameTheFileTheLineAndTheReason) {
    const struct {
        const char* line;
        const char* reason;
    } cases[] = {
        {"v 0 0 0 1 0", "'v' takes 3, 4 or 6 numbers (x y z, x y z w or x y z r g b), not 5"},
        {"v 0 0 0 1 0 0 1", "not 7"},
        {"v 0 0 0 nan 0 0", "'nan' is not a number"},
        {"v 0 0 0 0.5 -0.25 0", "colour component '-0.25' is negative"},
        {"v 0 0 0 0 0 300", "colour component '300' is above 255"},
        {"v 0 0 0 red 0 0", "'red' is not a number"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.line);
        const auto file =
            writeFile("bad.obj", std::string("v 1 0 0 1 1 1\n") + c.line + "\nv 0 1 0\nf 1 2 3\n");
        for (const std::string& why :
             {loadError([&] { (void)loadMeshModel(file); }), loadError([&] { (void)loadMesh(file); })}) {
            EXPECT_NE(why.find("bad.obj:2"), std::string::npos) << why;
            EXPECT_NE(why.find(c.reason), std::string::npos) << why;
        }
    }
}

TEST(ObjColor, WritersRoundTripVertexAndMaterialColours) {
    // Both writers print sRGB to 6 decimals (±5e-7); decoding multiplies an error by at most the
    // curve's steepest slope, 2.4 / 1.055 at 1; the file's floats and the stored floats add an
    // epsilon each.
    const double bound = 2.4 / 1.055 * (0.5e-6 + FLT_EPSILON) + FLT_EPSILON;
    auto g = Geometry::create();
    g->name = "coloured";
    const std::vector<glm::vec4> linear = {
        {0.0f, 1.0f, 0.5f, 1.0f},      {0.0031308f, 0.003f, 0.0032f, 1.0f}, {0.2140411f, 0.9f, 0.01f, 1.0f},
        {0.73f, 0.0001f, 0.33f, 1.0f}, {1.5f, -0.2f, 0.999f, 1.0f}, // clamped to [0, 1]
        {0.05f, 0.6f, 0.95f, 1.0f}};
    for (std::size_t i = 0; i < linear.size(); ++i) {
        g->positions.emplace_back(float(i), float(i * i % 5), 0.5f * float(i % 2));
        g->colors.push_back(linear[i]);
    }
    g->indices = {0, 1, 2, 2, 3, 4, 4, 5, 0};
    // writeObj's MTL keeps the material's colours too, to 6 significant digits, Ke included.
    auto m = Material::create();
    m->ambient = {0.1234567f, 0.0456789f, 0.9f};
    m->diffuse = {0.3456789f, 0.2f, 0.7654321f, 1.0f};
    m->specular = glm::vec3(0.0123457f);
    m->emissive = {0.5f, 0.0678901f, 0.0f};
    g->getOrCreateStateSet().material.set(m);
    auto root = Group::create();
    root->addChild(g);
    const auto dir = std::filesystem::temp_directory_path() / "sgfx_obj_color";
    std::filesystem::create_directories(dir);
    writeObj(*root, dir / "written.obj");
    writeMesh(*g, dir / "mesh.obj");
    const auto model = loadMeshModel(dir / "written.obj");
    const std::shared_ptr<const Geometry> mesh = loadMesh(dir / "mesh.obj");
    const Material& mb = **model->child(0)->stateSet()->material.value;
    // 6 significant digits: half a unit of the 6th is at most 5e-6 of the value.
    const auto digits6 = [](float v) { return (5e-6 + FLT_EPSILON) * v; };
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(mb.ambient[k], m->ambient[k], digits6(m->ambient[k])) << "Ka " << k;
        EXPECT_NEAR(mb.diffuse[k], m->diffuse[k], digits6(m->diffuse[k])) << "Kd " << k;
        EXPECT_NEAR(mb.specular[k], m->specular[k], digits6(m->specular[k])) << "Ks " << k;
        EXPECT_NEAR(mb.emissive[k], m->emissive[k], digits6(m->emissive[k])) << "Ke " << k;
    }
    for (const Geometry* back : {&geometryAt(*model, 0), mesh.get()}) {
        SCOPED_TRACE(back == mesh.get() ? "writeMesh, loadMesh" : "writeObj, loadMeshModel");
        ASSERT_EQ(back->colors.size(), back->positions.size());
        for (std::size_t i = 0; i < linear.size(); ++i)
            expectColour(*back, g->positions[i], glm::clamp(glm::dvec3(linear[i]), 0.0, 1.0), bound);
    }
}

TEST(ObjColor, VertexColoursAreDrawnInterpolatedInLinearLight) {
    // Red, sRGB 0.5 green and sRGB 0.5 blue corners under a white ambient light alone, on a
    // material that reflects all of it: each pixel is the barycentric mix of the linear colours.
    const auto file = writeFile("drawn.obj", "v -1.8 -1.8 0 1 0 0\n"
                                             "v 1.8 -1.8 0 0 0.5 0\n"
                                             "v 0 1.8 0 0 0 0.5\n"
                                             "f 1 2 3\n");
    const auto model = loadMeshModel(file);
    auto m = Material::create();
    m->ambient = glm::vec3(1.0f);
    m->diffuse = {0, 0, 0, 1};
    m->specular = glm::vec3(0.0f);
    model->child(0)->getOrCreateStateSet().material.set(m);
    auto ambient = Light::create(LightType::Ambient);
    ambient->color = glm::vec3(1.0f);
    auto root = Group::create();
    root->addChild(model);
    root->addChild(ambient);
    constexpr int kSize = 64;
    constexpr float kHalf = 2.0f;
    auto v = orthoTopViewer(kSize, kHalf);
    v->setSceneData(root);
    v->frame();
    const Image img = v->capture();
    const glm::dvec2 a(-1.8, -1.8), b(1.8, -1.8), c(0, 1.8);
    const glm::dvec3 ca(1, 0, 0), cb(0, srgbDecode(0.5), 0), cc(0, 0, srgbDecode(0.5));
    // Near the red corner, near the green one, near the blue one, and the middle.
    for (auto [px, py] : {std::pair{6, 55}, {57, 55}, {32, 9}, {32, 40}}) {
        const glm::dvec2 p(-kHalf + (px + 0.5) / kSize * 2 * kHalf, kHalf - (py + 0.5) / kSize * 2 * kHalf);
        const double area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        const double wb = ((p.x - a.x) * (c.y - a.y) - (c.x - a.x) * (p.y - a.y)) / area;
        const double wc = ((b.x - a.x) * (p.y - a.y) - (p.x - a.x) * (b.y - a.y)) / area;
        ASSERT_GT(std::min({wb, wc, 1.0 - wb - wc}), 0.0) << px << "," << py << " is outside";
        const glm::dvec3 expected = (1.0 - wb - wc) * ca + wb * cb + wc * cc;
        const glm::ivec4 got = pixelAt(img, px, py);
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(got[k], srgbByte(expected[k]), 2)
                << "pixel (" << px << "," << py << ") channel " << k;
    }
    // The red corner's pixel is red: the sRGB-encoded framebuffer shows the file's value again.
    const glm::ivec4 red = pixelAt(img, 6, 55);
    EXPECT_GT(red.r, 200);
    EXPECT_LT(red.g, 80);
    EXPECT_LT(red.b, 80);
    expectNoGlErrors(*v);
}

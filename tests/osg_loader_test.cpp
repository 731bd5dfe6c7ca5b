// The OpenSceneGraph bridge (loadOsg): OSG's own sample data loads with OSG's counts and bounds,
// renders as OSG draws it (textures, billboards, sphere maps, animation paths, the file's own
// shaders under fog), and bad files give LoadError naming the file.
#include "TestUtil.h"

#include <sgfx/Billboard.h>
#include <sgfx/DOFTransform.h>
#include <sgfx/DatabasePager.h>
#include <sgfx/Geometry.h>
#include <sgfx/LOD.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/OsgLoader.h>
#include <sgfx/Queries.h>
#include <sgfx/Sequence.h>
#include <sgfx/Shapes.h>
#include <sgfx/Switch.h>
#include <sgfx/Viewer.h>
#include <sgfx/Visitors.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/fog/FogMath.h>
#include <sgfx/nodes/fog/FogNode.h>

#include <glm/gtc/type_ptr.hpp>

#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#ifdef SGFX_TEST_HAVE_OSG
#include <osg/AnimationPath>
#include <osg/ClipNode>
#include <osg/Fog>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/LOD>
#include <osg/LightSource>
#include <osg/Material>
#include <osg/MatrixTransform>
#include <osg/NodeVisitor>
#include <osg/PagedLOD>
#include <osg/PolygonMode>
#include <osg/Sequence>
#include <osg/ShadeModel>
#include <osg/ShapeDrawable>
#include <osg/Switch>
#include <osg/TexEnv>
#include <osg/TexGen>
#include <osg/Texture2D>
#include <osg/TextureCubeMap>
#include <osgDB/ReadFile>
#include <osgDB/Registry>
#include <osgDB/WriteFile>
#include <osgSim/DOFTransform>
#endif

namespace fs = std::filesystem;
using namespace sgfx;
using sgfx::test::pixelAt;

namespace {

fs::path assets() {
    return fs::path(SGFX_SOURCE_DIR) / ".." / "shared" / "assets" / "osg";
}

[[maybe_unused]] OsgOptions assetOptions() {
    OsgOptions o;
    o.databasePaths.push_back(assets());
    return o;
}

[[maybe_unused]] fs::path tempDir(const std::string& name) {
    auto d = fs::temp_directory_path() / ("sgfx_osg_" + name + "_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
}

/// Counts the way OSG's statistics do: each Geometry once per parent path.
struct Counted {
    std::size_t drawables = 0, vertices = 0, triangles = 0;
};
class CountGeometries : public NodeVisitor {
public:
    CountGeometries()
        : NodeVisitor(Mode::AllChildren) {}
    void apply(Geometry& g) override {
        ++c.drawables;
        c.vertices += g.positions.size();
        c.triangles += g.mode == PrimitiveMode::Triangles ? g.indices.size() / 3 : 0;
    }
    Counted c;
};

} // namespace

#ifdef SGFX_TEST_HAVE_OSG

// The README's table (../shared/assets/osg/README.md): what OpenSceneGraph 3.6.5 reports.
struct Expected {
    const char* file;
    std::size_t drawables, vertices, triangles;
    glm::vec3 min, max;
};
const Expected kExpected[] = {
    {"cessna.osgt", 1, 9680, 7446, {-22.152f, -18.166f, -5.120f}, {22.152f, 18.166f, 5.120f}},
    {"glider.osgt", 6, 676, 640, {-0.188f, -1.000f, -0.233f}, {0.458f, 1.000f, 0.225f}},
    {"lz.osgt", 107, 1966, 3006, {-277.514f, -284.961f, 0.000f}, {277.490f, 300.000f, 208.000f}},
    {"cow.osgt", 1, 7772, 5804, {-4.446f, -2.140f, -3.198f}, {5.998f, 1.263f, 3.198f}},
    {"glsl_simple.osgt", 6, 5336, 5200, {-1.000f, -2.000f, -1.000f}, {5.400f, 0.000f, 3.200f}},
    {"clock.osgt", 7, 42, 18, {-0.500f, -0.470f, 0.000f}, {0.500f, 0.470f, 1.000f}},
    {"torus.osgt", 1, 2300, 1152, {-2.500f, -2.500f, -1.000f}, {2.500f, 2.500f, 1.000f}},
    {"simpleroom.osgt", 1, 16, 8, {-64.000f, -64.000f, 0.000f}, {64.000f, 64.000f, 64.000f}},
    {"skydome.osgt", 1, 540, 180, {347.400f, 11277.400f, 0.000f}, {52920.602f, 63562.602f, 7467.480f}},
};

TEST(OsgLoader, EveryAssetLoadsWithOsgsOwnCountsAndBounds) {
    SGFX_REQUIRE(fs::exists(assets() / "README.md"), "../shared/assets/osg");
    for (const auto& e : kExpected) {
        SCOPED_TRACE(e.file);
        OsgStats stats;
        auto root = loadOsg(assets() / e.file, assetOptions(), &stats);
        // What osgDB read, counted by the bridge, and what the converted sgfx graph holds.
        EXPECT_EQ(stats.drawables, e.drawables);
        EXPECT_EQ(stats.vertices, e.vertices);
        EXPECT_EQ(stats.triangles, e.triangles);
        CountGeometries count;
        root->accept(count);
        EXPECT_EQ(count.c.vertices, e.vertices);
        EXPECT_EQ(count.c.triangles, e.triangles);
        ComputeBoundsVisitor bounds;
        root->accept(bounds);
        const float tol = 2e-3f * glm::length(e.max - e.min) + 1e-3f;
        for (int a = 0; a < 3; ++a) {
            // OSG's ComputeBoundsVisitor measures an osg::Billboard's drawables at their local
            // coordinates, without the per-drawable positions, so lz's trees count as standing
            // at z = 0; sgfx measures them where they stand (on the terrain, above 0).
            if (std::string(e.file) == "lz.osgt" && a == 2)
                EXPECT_GT(bounds.min[a], e.min[a]);
            else
                EXPECT_NEAR(bounds.min[a], e.min[a], tol) << "axis " << a;
            EXPECT_NEAR(bounds.max[a], e.max[a], tol) << "axis " << a;
        }
        // Every image the files name is found through the database path.
        for (const auto& w : stats.warnings)
            EXPECT_EQ(w.find("without an image"), std::string::npos) << w;
    }
}

TEST(OsgLoader, LoadModelDispatchesOsgFormats) {
    SGFX_REQUIRE(fs::exists(assets() / "torus.osgt"), "../shared/assets/osg");
    EXPECT_TRUE(osgSupported());
    auto root = loadModel(assets() / "torus.osgt");
    CountGeometries count;
    root->accept(count);
    EXPECT_EQ(count.c.triangles, 1152u);
}

namespace {

/// Writes an osg graph as .osgt with its images inside, and loads it back through loadOsg.
std::shared_ptr<Group> roundTrip(osg::Node& node, const std::string& name, OsgStats* stats = nullptr,
                                 const char* ext = ".osgt") {
    const auto file = tempDir("scene") / (name + ext);
    osg::ref_ptr<osgDB::Options> o = new osgDB::Options("WriteImageHint=IncludeData");
    EXPECT_TRUE(osgDB::writeNodeFile(node, file.string(), o.get()));
    return loadOsg(file, {}, stats);
}

osg::ref_ptr<osg::Geometry> osgQuad(float half) {
    osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
    auto* v = new osg::Vec3Array;
    for (auto [x, y] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
        v->push_back(osg::Vec3(x * half, y * half, 0));
    g->setVertexArray(v);
    auto* n = new osg::Vec3Array(osg::Array::BIND_OVERALL);
    n->push_back(osg::Vec3(0, 0, 1));
    g->setNormalArray(n);
    g->addPrimitiveSet(new osg::DrawArrays(GL_QUADS, 0, 4));
    return g;
}

double srgbToLinearByte(int b) {
    const double v = b / 255.0;
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

int differingPixels(const Image& a, const Image& b) {
    int n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            n += pixelAt(a, x, y) != pixelAt(b, x, y);
    return n;
}

/// The model under a sun and some ambient light (OSG's viewer adds a headlight; sgfx scenes carry
/// their lights).
std::shared_ptr<Group> lit(std::shared_ptr<Group> model) {
    auto world = Group::create();
    auto sun = Light::create(LightType::Directional);
    sun->direction = glm::normalize(glm::vec3(-0.3f, 0.6f, -0.7f));
    auto sky = Light::create(LightType::Ambient);
    sky->intensity = 0.3f;
    world->addChild(sun);
    world->addChild(sky);
    world->addChild(std::move(model));
    return world;
}

/// The world matrix of a node with one parent path.
glm::mat4 worldOf(const Node& n) {
    glm::mat4 m(1.0f);
    for (const Node* p = &n; p && !p->parents().empty(); p = p->parents().front())
        if (const auto* t = dynamic_cast<const Transform*>(p->parents().front())) m = t->matrix() * m;
    return m;
}

class FindBillboards : public NodeVisitor {
public:
    void apply(Billboard& b) override { found.push_back(&b); }
    std::vector<Billboard*> found;
};

} // namespace

// TexGen SPHERE_MAP (cow.osgt's reflection): each pixel shows the texel the OpenGL 2.1 formula
// (§2.12.4) picks from the eye-space reflection, computed here on the CPU.
TEST(OsgLoader, SphereMapSamplesTheTexelOfTheEyeSpaceReflection) {
    osg::ref_ptr<osg::Image> ramp = new osg::Image;
    ramp->allocateImage(256, 4, 1, GL_RGB, GL_UNSIGNED_BYTE);
    for (int t = 0; t < 4; ++t)
        for (int s = 0; s < 256; ++s) {
            unsigned char* p = ramp->data(unsigned(s), unsigned(t));
            p[0] = (unsigned char)s, p[1] = 0, p[2] = 0;
        }
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->addDrawable(osgQuad(8.0f));
    auto* ss = geode->getOrCreateStateSet();
    ss->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
    auto* tex = new osg::Texture2D(ramp.get());
    tex->setFilter(osg::Texture::MIN_FILTER, osg::Texture::LINEAR);
    tex->setWrap(osg::Texture::WRAP_S, osg::Texture::CLAMP_TO_EDGE);
    ss->setTextureAttributeAndModes(0, tex);
    auto* gen = new osg::TexGen;
    gen->setMode(osg::TexGen::SPHERE_MAP);
    ss->setTextureAttributeAndModes(0, gen);
    auto root = roundTrip(*geode, "spheremap");

    constexpr int size = 64;
    const Image img = test::renderTop(size, 8.0f, root);
    int checked = 0;
    for (int py : {8, 32, 55})
        for (int px : {4, 20, 32, 44, 60}) {
            // Pixel centre → world (x, y) on the quad; eye space: (x, y, -10), normal +Z.
            const double x = (px + 0.5) / size * 16.0 - 8.0, y = 8.0 - (py + 0.5) / size * 16.0;
            const glm::dvec3 u = glm::normalize(glm::dvec3(x, y, -10.0));
            const glm::dvec3 r(u.x, u.y, -u.z); // reflect about n = +Z
            const double m = 2.0 * std::sqrt(r.x * r.x + r.y * r.y + (r.z + 1.0) * (r.z + 1.0));
            const double s = r.x / m + 0.5;
            // Texel i holds byte i (sRGB-decoded, filtered, encoded back): s·256 − 0.5.
            EXPECT_NEAR(pixelAt(img, px, py).r, s * 256.0 - 0.5, 3.0) << px << "," << py;
            ++checked;
        }
    EXPECT_EQ(checked, 15);
}

// TexGen REFLECTION_MAP with a TextureCubeMap: on a sphere seen from above (orthographic), each
// pixel shows the face, and the half of it, that OpenGL's cube-map lookup (OpenGL 2.1 table 3.21)
// picks for the eye-space reflection, computed here on the CPU.
TEST(OsgLoader, CubeReflectionMapPicksTheFaceOfTheEyeSpaceReflection) {
    osg::ref_ptr<osg::TextureCubeMap> cube = new osg::TextureCubeMap;
    const auto colourOf = [](int face, int half) { return glm::ivec3(20 + face * 40, 30 + half * 200, 128); };
    for (unsigned f = 0; f < 6; ++f) {
        osg::ref_ptr<osg::Image> im = new osg::Image;
        im->allocateImage(16, 16, 1, GL_RGB, GL_UNSIGNED_BYTE);
        for (unsigned t = 0; t < 16; ++t)
            for (unsigned s = 0; s < 16; ++s) {
                const glm::ivec3 c = colourOf(int(f), s >= 8);
                unsigned char* p = im->data(s, t);
                p[0] = (unsigned char)c.r, p[1] = (unsigned char)c.g, p[2] = (unsigned char)c.b;
            }
        cube->setImage(f, im.get());
    }
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->addDrawable(new osg::ShapeDrawable(new osg::Sphere(osg::Vec3(), 1.0f)));
    auto* ss = geode->getOrCreateStateSet();
    ss->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
    ss->setTextureAttributeAndModes(0, cube.get());
    auto* gen = new osg::TexGen;
    gen->setMode(osg::TexGen::REFLECTION_MAP);
    ss->setTextureAttributeAndModes(0, gen);
    auto root = roundTrip(*geode, "cubemap");

    constexpr int size = 64;
    const Image img = test::renderTop(size, 1.0f, root);
    int checked = 0, faces = 0;
    std::set<int> seen;
    for (int py = 2; py < size; py += 3)
        for (int px = 2; px < size; px += 3) {
            const double x = (px + 0.5) / size * 2.0 - 1.0, y = 1.0 - (py + 0.5) / size * 2.0;
            if (x * x + y * y > 0.85) continue; // the sphere's tessellated rim
            const glm::dvec3 n(x, y, std::sqrt(1.0 - x * x - y * y));
            const glm::dvec3 u =
                glm::normalize(glm::dvec3(x, y, n.z - 10.0)); // eye space: view has no rotation
            const glm::dvec3 r = u - 2.0 * glm::dot(u, n) * n;
            const glm::dvec3 a = glm::abs(r);
            int face;
            double sc, ma;
            if (a.x >= a.y && a.x >= a.z)
                face = r.x > 0 ? 0 : 1, sc = r.x > 0 ? -r.z : r.z, ma = a.x;
            else if (a.y >= a.z)
                face = r.y > 0 ? 2 : 3, sc = r.x, ma = a.y;
            else
                face = r.z > 0 ? 4 : 5, sc = r.z > 0 ? r.x : -r.x, ma = a.z;
            // Away from face edges and the halves' border (tessellation and filtering blur them).
            double sorted[3] = {a.x, a.y, a.z};
            std::sort(sorted, sorted + 3);
            const double second = sorted[1]; // ties (the diagonals) count as edges
            if (second > 0.75 * ma || std::abs(sc / ma) < 0.25) continue;
            const glm::ivec3 expected = colourOf(face, sc > 0);
            const glm::ivec4 got = pixelAt(img, px, py);
            EXPECT_NEAR(got.r, expected.r, 6) << px << "," << py << " face " << face;
            EXPECT_NEAR(got.g, expected.g, 6) << px << "," << py << " face " << face;
            ++checked;
            seen.insert(face);
        }
    faces = int(seen.size());
    EXPECT_GT(checked, 60);
    EXPECT_GE(faces, 4); // +Z in the middle, and the four side faces towards the rim
}

// ShadeModel FLAT: each triangle takes its provoking vertex's colour (a quad's last vertex), where
// smooth shading blends the four; PolygonMode LINE: the quad's outline, not its diagonal.
TEST(OsgLoader, FlatShadingAndPolygonModeLineDrawAsOpenGLDoes) {
    const auto quadScene = [](bool flat, bool line) {
        auto g = osgQuad(0.5f);
        auto* c = new osg::Vec4Array(osg::Array::BIND_PER_VERTEX);
        for (const osg::Vec4& col :
             {osg::Vec4(1, 0, 0, 1), osg::Vec4(0, 1, 0, 1), osg::Vec4(0, 0, 1, 1), osg::Vec4(1, 1, 1, 1)})
            c->push_back(col);
        g->setColorArray(c);
        osg::ref_ptr<osg::Geode> geode = new osg::Geode;
        geode->addDrawable(g);
        auto* ss = geode->getOrCreateStateSet();
        ss->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
        if (flat) ss->setAttribute(new osg::ShadeModel(osg::ShadeModel::FLAT));
        if (line)
            ss->setAttribute(new osg::PolygonMode(osg::PolygonMode::FRONT_AND_BACK, osg::PolygonMode::LINE));
        return geode;
    };
    auto viewer = test::orthoTopViewer(64, 1.0f);
    const auto draw = [&](bool flat, bool line) {
        viewer->setSceneData(roundTrip(*quadScene(flat, line), flat ? "flat" : line ? "line" : "smooth"));
        viewer->frame();
        return viewer->capture();
    };
    const Image flat = draw(true, false), smooth = draw(false, false), line = draw(false, true);
    int white = 0, inside = 0;
    for (int y = 18; y < 46; ++y)
        for (int x = 18; x < 46; ++x) {
            ++inside;
            white += pixelAt(flat, x, y) == glm::ivec4(255, 255, 255, 255);
        }
    EXPECT_EQ(white, inside);                                    // one colour, the last vertex's
    EXPECT_NE(pixelAt(smooth, 20, 44), pixelAt(smooth, 44, 20)); // smooth: a blend of four
    EXPECT_EQ(pixelAt(line, 32, 32), glm::ivec4(0, 0, 0, 255));  // no fill
    EXPECT_EQ(pixelAt(line, 24, 40), glm::ivec4(0, 0, 0, 255));  // no diagonal near (-.25, -.25)
    EXPECT_EQ(pixelAt(line, 40, 24), glm::ivec4(0, 0, 0, 255));
    int outline = 0;
    for (int y = 18; y < 46; ++y)
        for (int x : {15, 16, 47, 48})
            outline += pixelAt(line, x, y) != glm::ivec4(0, 0, 0, 255);
    EXPECT_GT(outline, 40); // the left and right edges, one pixel wide each
}

// An osg::LightSource lights the file as sgfx's light does (directional from +Z, white: a surface
// facing it shows its Material's diffuse, a display value, as it is); TexEnv REPLACE shows the
// texture whatever the lighting; a state attribute the bridge does not read is named in a warning.
TEST(OsgLoader, LightSourcesMaterialsAndTexEnvReplace) {
    osg::ref_ptr<osg::Group> root = new osg::Group;
    osg::ref_ptr<osg::LightSource> sun = new osg::LightSource;
    sun->getLight()->setPosition(osg::Vec4(0, 0, 1, 0));
    sun->getLight()->setDiffuse(osg::Vec4(1, 1, 1, 1));
    sun->getLight()->setAmbient(osg::Vec4(0, 0, 0, 1));
    root->addChild(sun);
    const auto tile = [&](float x, float y) {
        auto g = osgQuad(0.4f);
        for (auto& v : *static_cast<osg::Vec3Array*>(g->getVertexArray()))
            v += osg::Vec3(x, y, 0);
        auto* uv = new osg::Vec2Array;
        for (auto [s, t] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}})
            uv->push_back(osg::Vec2(s, t));
        g->setTexCoordArray(0, uv);
        osg::ref_ptr<osg::Geode> geode = new osg::Geode;
        geode->addDrawable(g);
        root->addChild(geode);
        return geode->getOrCreateStateSet();
    };
    auto* material = new osg::Material;
    material->setDiffuse(osg::Material::FRONT_AND_BACK, osg::Vec4(0.5f, 0.25f, 0.75f, 1));
    material->setAmbient(osg::Material::FRONT_AND_BACK, osg::Vec4(0, 0, 0, 1));
    tile(-0.5f, 0)->setAttribute(material);
    osg::ref_ptr<osg::Image> im = new osg::Image;
    im->allocateImage(2, 2, 1, GL_RGB, GL_UNSIGNED_BYTE);
    for (unsigned i = 0; i < 4; ++i)
        im->data()[i * 3] = 200, im->data()[i * 3 + 1] = 100, im->data()[i * 3 + 2] = 50;
    auto* replaced = tile(0.5f, 0);
    replaced->setAttribute(material);
    replaced->setTextureAttributeAndModes(0, new osg::Texture2D(im.get()));
    replaced->setTextureAttribute(0, new osg::TexEnv(osg::TexEnv::REPLACE));
    root->getOrCreateStateSet()->setAttribute(new osg::Fog);
    OsgStats stats;
    auto loaded = roundTrip(*root, "lights", &stats);
    bool fogWarned = false;
    for (const auto& w : stats.warnings)
        fogWarned |= w.find("osg::Fog state attribute") != std::string::npos;
    EXPECT_TRUE(fogWarned);

    const Image img = test::renderTop(64, 1.0f, loaded);
    // Lambert under a white light of 1 from straight above: the diffuse itself (display values).
    const glm::ivec4 lit = pixelAt(img, 16, 32), tex = pixelAt(img, 48, 32);
    EXPECT_NEAR(lit.r, 128, 2);
    EXPECT_NEAR(lit.g, 64, 2);
    EXPECT_NEAR(lit.b, 191, 2);
    EXPECT_NEAR(tex.r, 200, 2);
    EXPECT_NEAR(tex.g, 100, 2);
    EXPECT_NEAR(tex.b, 50, 2);
}

// osg::Material's two faces: seen from above, the front face shows the FRONT diffuse; seen from
// below (OSG does not cull faces unless told), the back face shows the BACK diffuse, each lit by
// a light on its side.
TEST(OsgLoader, BackFacesShowTheBackMaterial) {
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->addDrawable(osgQuad(0.5f));
    auto* material = new osg::Material;
    material->setDiffuse(osg::Material::FRONT, osg::Vec4(0.5f, 0, 0, 1));
    material->setDiffuse(osg::Material::BACK, osg::Vec4(0, 0, 0.5f, 1));
    material->setAmbient(osg::Material::FRONT_AND_BACK, osg::Vec4(0, 0, 0, 1));
    geode->getOrCreateStateSet()->setAttribute(material);
    auto model = roundTrip(*geode, "faces");
    auto viewer = test::orthoTopViewer(32, 1.0f);
    auto scene = Group::create();
    auto light = Light::create(LightType::Directional);
    scene->addChild(light);
    scene->addChild(model);
    viewer->setSceneData(scene);
    light->direction = {0, 0, -1};
    const auto expectNear = [](glm::ivec4 got, glm::ivec4 want) {
        for (int c = 0; c < 4; ++c)
            EXPECT_NEAR(got[c], want[c], 1) << "channel " << c;
    };
    viewer->frame();
    expectNear(pixelAt(viewer->capture(), 16, 16), {128, 0, 0, 255});
    light->direction = {0, 0, 1};
    viewer->camera()->setLookAt({0, 0, -10}, {0, 0, 0}, {0, 1, 0});
    viewer->frame();
    expectNear(pixelAt(viewer->capture(), 16, 16), {0, 0, 128, 255});
}

// Every primitive set kind and mode, counted by hand: DrawArrays, DrawArrayLengths and DrawElements
// (ubyte, ushort, uint) of triangles, strips, fans, quads, quad strips, polygons, lines, line
// strips and loops, points; and a colour array bound per primitive set colours each set.
TEST(OsgLoader, EveryPrimitiveModeAndBinding) {
    osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
    auto* v = new osg::Vec3Array;
    for (int i = 0; i < 12; ++i)
        v->push_back(osg::Vec3(float(i % 4), float(i / 4), 0));
    g->setVertexArray(v);
    g->addPrimitiveSet(new osg::DrawArrays(GL_TRIANGLES, 0, 6));      // 2
    g->addPrimitiveSet(new osg::DrawArrays(GL_TRIANGLE_STRIP, 0, 7)); // 5
    g->addPrimitiveSet(new osg::DrawArrays(GL_TRIANGLE_FAN, 0, 6));   // 4
    g->addPrimitiveSet(new osg::DrawArrays(GL_QUADS, 0, 8));          // 4
    g->addPrimitiveSet(new osg::DrawArrays(GL_QUAD_STRIP, 0, 8));     // 6
    g->addPrimitiveSet(new osg::DrawArrays(GL_POLYGON, 0, 5));        // 3
    auto* lengths = new osg::DrawArrayLengths(GL_TRIANGLE_STRIP, 0);
    lengths->push_back(4), lengths->push_back(5); // 2 + 3
    g->addPrimitiveSet(lengths);
    auto* ub = new osg::DrawElementsUByte(GL_TRIANGLES);
    for (int i : {0, 1, 4, 1, 5, 4})
        ub->push_back((GLubyte)i); // 2
    g->addPrimitiveSet(ub);
    auto* us = new osg::DrawElementsUShort(GL_TRIANGLE_STRIP);
    for (int i : {4, 5, 8, 9, 10})
        us->push_back((GLushort)i); // 3
    g->addPrimitiveSet(us);
    auto* ui = new osg::DrawElementsUInt(GL_QUADS);
    for (int i : {5, 6, 10, 9})
        ui->push_back((GLuint)i); // 2
    g->addPrimitiveSet(ui);
    g->addPrimitiveSet(new osg::DrawArrays(GL_LINE_LOOP, 0, 4));  // 4 lines
    g->addPrimitiveSet(new osg::DrawArrays(GL_LINE_STRIP, 4, 4)); // 3 lines
    g->addPrimitiveSet(new osg::DrawArrays(GL_LINES, 8, 4));      // 2 lines
    g->addPrimitiveSet(new osg::DrawArrays(GL_POINTS, 0, 3));     // 3 points
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->addDrawable(g);
    OsgStats stats;
    auto root = roundTrip(*geode, "modes", &stats);
    const std::size_t triangles = 2 + 5 + 4 + 4 + 6 + 3 + 5 + 2 + 3 + 2;
    EXPECT_EQ(stats.triangles, triangles);
    class Kinds : public NodeVisitor {
    public:
        void apply(Geometry& geometry) override {
            const std::size_t per = geometry.mode == PrimitiveMode::Triangles ? 3
                                    : geometry.mode == PrimitiveMode::Lines   ? 2
                                                                              : 1;
            count[int(geometry.mode)] += geometry.indices.size() / per;
        }
        std::size_t count[6] = {};
    } kinds;
    root->accept(kinds);
    EXPECT_EQ(kinds.count[int(PrimitiveMode::Triangles)], triangles);
    EXPECT_EQ(kinds.count[int(PrimitiveMode::Lines)], 9u);
    EXPECT_EQ(kinds.count[int(PrimitiveMode::Points)], 3u);

    // Two triangles in two primitive sets, one colour each (BIND_PER_PRIMITIVE_SET), unlit.
    osg::ref_ptr<osg::Geometry> two = new osg::Geometry;
    auto* w = new osg::Vec3Array;
    for (auto [x, y] :
         {std::pair{-0.9f, -0.9f}, {-0.1f, -0.9f}, {-0.5f, 0.9f}, {0.1f, -0.9f}, {0.9f, -0.9f}, {0.5f, 0.9f}})
        w->push_back(osg::Vec3(x, y, 0));
    two->setVertexArray(w);
    auto* c = new osg::Vec4Array(osg::Array::BIND_PER_PRIMITIVE_SET);
    c->push_back(osg::Vec4(1, 0, 0, 1)), c->push_back(osg::Vec4(0, 0, 1, 1));
    two->setColorArray(c);
    two->addPrimitiveSet(new osg::DrawArrays(GL_TRIANGLES, 0, 3));
    two->addPrimitiveSet(new osg::DrawArrays(GL_TRIANGLES, 3, 3));
    osg::ref_ptr<osg::Geode> g2 = new osg::Geode;
    g2->addDrawable(two);
    g2->getOrCreateStateSet()->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
    const Image img = test::renderTop(64, 1.0f, roundTrip(*g2, "perset"));
    EXPECT_EQ(pixelAt(img, 16, 40), glm::ivec4(255, 0, 0, 255));
    EXPECT_EQ(pixelAt(img, 48, 40), glm::ivec4(0, 0, 255, 255));
}

TEST(OsgLoader, CowShowsItsReflectionMap) {
    SGFX_REQUIRE(fs::exists(assets() / "cow.osgt"), "../shared/assets/osg");
    auto root = loadOsg(assets() / "cow.osgt", assetOptions());
    auto viewer = Viewer::createHeadless(96, 64);
    viewer->camera()->setPerspective(40.0f, 0.5f, 100.0f);
    viewer->camera()->setLookAt({0.8f, -16.0f, 2.0f}, {0.8f, 0.0f, 0.0f});
    viewer->setSceneData(lit(root));
    viewer->frame();
    const Image front = viewer->capture();
    // The reflection follows the eye: the same cow seen from a little higher shows other texels.
    viewer->camera()->setLookAt({0.8f, -15.0f, 6.0f}, {0.8f, 0.0f, 0.0f});
    viewer->frame();
    const Image above = viewer->capture();
    EXPECT_GT(differingPixels(front, above), 400);
    std::set<std::uint32_t> colours;
    for (int y = 0; y < front.height; ++y)
        for (int x = 0; x < front.width; ++x) {
            const auto p = pixelAt(front, x, y);
            colours.insert(std::uint32_t(p.r << 16 | p.g << 8 | p.b));
        }
    EXPECT_GT(colours.size(), 200u); // the reflection map's detail, not one shade
}

// lz.osgt: the textured terrain, and billboard trees that face the camera from any side: a tree
// seen from two directions 90° apart covers about as many pixels both times (an unturned card
// would be edge-on in one of them).
TEST(OsgLoader, LzTreesFaceTheCameraFromEverySide) {
    SGFX_REQUIRE(fs::exists(assets() / "lz.osgt"), "../shared/assets/osg");
    auto root = loadOsg(assets() / "lz.osgt", assetOptions());
    FindBillboards boards;
    root->accept(boards);
    ASSERT_GE(boards.found.size(), 9u);
    Billboard* tree = boards.found.front();
    ASSERT_EQ(tree->parents().size(), 1u);
    const glm::vec3 centre = glm::vec3(worldOf(*tree) * glm::vec4(tree->bound().center, 1.0f));
    const float r = tree->bound().radius;

    auto viewer = Viewer::createHeadless(96, 96);
    viewer->camera()->setPerspective(40.0f, 0.1f, 2000.0f);
    viewer->camera()->clearColor = {0, 0, 0, 1};
    viewer->setSceneData(lit(root));
    int covered[2];
    for (int side = 0; side < 2; ++side) {
        const glm::vec3 dir = side == 0 ? glm::vec3(0, -1, 0) : glm::vec3(1, 0, 0);
        viewer->camera()->setLookAt(centre + dir * (4.0f * r), centre);
        tree->nodeMask = ~0u;
        viewer->frame();
        const Image with = viewer->capture();
        tree->nodeMask = 0;
        viewer->frame();
        covered[side] = differingPixels(with, viewer->capture());
    }
    EXPECT_GT(covered[0], 300);
    EXPECT_GT(covered[1], 300);
    EXPECT_NEAR(double(covered[1]) / covered[0], 1.0, 0.3);

    // From above the whole terrain: its texture gives many shades.
    viewer->camera()->setLookAt({0, -500, 400}, {0, 0, 80});
    viewer->frame();
    const Image overview = viewer->capture();
    std::set<std::uint32_t> colours;
    for (int y = 0; y < overview.height; ++y)
        for (int x = 0; x < overview.width; ++x) {
            const auto p = pixelAt(overview, x, y);
            colours.insert(std::uint32_t(p.r << 16 | p.g << 8 | p.b));
        }
    EXPECT_GT(colours.size(), 500u);

    // The tank: the geometry textured with Images/tank.rgb, seen close, covers its pixels.
    osg::ref_ptr<osg::Image> tankImage = osgDB::readRefImageFile((assets() / "Images" / "tank.rgb").string());
    ASSERT_TRUE(tankImage);
    class FindTextured : public NodeVisitor {
    public:
        explicit FindTextured(int w) : width(w) {}
        void apply(Geometry& g) override {
            const auto* holder = g.parents().empty() ? nullptr : g.parents().front();
            const auto& ss = holder ? holder->stateSet() : nullptr;
            const auto m = ss && ss->material.value ? *ss->material.value : nullptr;
            if (m && m->baseColorTexture && m->baseColorTexture->image->width == width) found.push_back(&g);
        }
        int width;
        std::vector<Geometry*> found;
    } findTank(tankImage->s());
    root->accept(findTank);
    ASSERT_EQ(findTank.found.size(), 1u); // one cylinder (a water tank), under the model's scale
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (Geometry* g : findTank.found) {
        const glm::mat4 w = worldOf(*g);
        const glm::vec3 c = glm::vec3(w * glm::vec4(g->bound().center, 1.0f));
        const float radius = g->bound().radius * glm::length(glm::vec3(w[0]));
        lo = glm::min(lo, c - radius), hi = glm::max(hi, c + radius);
    }
    const glm::vec3 tankCentre = (lo + hi) * 0.5f;
    const float tankRadius = glm::length(hi - lo) * 0.5f;
    viewer->camera()->setLookAt(tankCentre + glm::vec3(-1.2f, -1.8f, 0.9f) * tankRadius, tankCentre);
    viewer->frame();
    const Image withTank = viewer->capture();
    for (Geometry* g : findTank.found) g->nodeMask = 0;
    viewer->frame();
    EXPECT_GT(differingPixels(withTank, viewer->capture()), 1500); // a good part of the 96x96 view
}

// clock.osgt: the hands' AnimationPathCallbacks move sgfx's transforms exactly as OSG's own
// update traversal moves OSG's, at two times, and the hands are at different angles.
TEST(OsgLoader, ClockHandsFollowOsgsAnimationPaths) {
    SGFX_REQUIRE(fs::exists(assets() / "clock.osgt"), "../shared/assets/osg");
    auto root = loadOsg(assets() / "clock.osgt", assetOptions());
    class Animated : public NodeVisitor {
    public:
        void apply(Transform& t) override {
            if (t.updateCallback) found.push_back(&t);
            traverse(t);
        }
        std::vector<Transform*> found;
    } sg;
    root->accept(sg);
    osg::ref_ptr<osg::Node> reference = osgDB::readRefNodeFile((assets() / "clock.osgt").string());
    class OsgAnimated : public osg::NodeVisitor {
    public:
        OsgAnimated()
            : osg::NodeVisitor(TRAVERSE_ALL_CHILDREN) {}
        void apply(osg::MatrixTransform& t) override {
            if (dynamic_cast<osg::AnimationPathCallback*>(t.getUpdateCallback()) &&
                std::find(found.begin(), found.end(), &t) == found.end())
                found.push_back(&t);
            traverse(t);
        }
        std::vector<osg::MatrixTransform*> found;
    } os;
    reference->accept(os);
    // The hands are shared by the front and back faces; the back face's state differs, so sgfx
    // holds each hand twice (same name, same animation).
    ASSERT_EQ(sg.found.size(), 6u);
    ASSERT_EQ(os.found.size(), 3u);

    UpdateVisitor update;
    std::vector<glm::mat4> at[2];
    for (int k = 0; k < 2; ++k) {
        const double t = k == 0 ? 0.0 : 7.25;
        update.simulationTime = t;
        root->accept(update);
        // OSG's own update: its callbacks take the first time they see as their start, like sgfx's.
        osg::ref_ptr<osg::FrameStamp> stamp = new osg::FrameStamp;
        stamp->setSimulationTime(t);
        stamp->setReferenceTime(t);
        osg::NodeVisitor ou(osg::NodeVisitor::UPDATE_VISITOR, osg::NodeVisitor::TRAVERSE_ALL_CHILDREN);
        ou.setFrameStamp(stamp.get());
        for (auto* mt : os.found)
            (*dynamic_cast<osg::AnimationPathCallback*>(mt->getUpdateCallback()))(mt, &ou);
        for (std::size_t i = 0; i < 6; ++i) {
            const auto* same = *std::find_if(os.found.begin(), os.found.end(),
                                             [&](auto* o) { return o->getName() == sg.found[i]->name; });
            const glm::mat4 expected = glm::make_mat4(osg::Matrixf(same->getMatrix()).ptr());
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r)
                    EXPECT_NEAR(sg.found[i]->matrix()[c][r], expected[c][r], 1e-5f)
                        << sg.found[i]->name << " t " << t;
            at[k].push_back(sg.found[i]->matrix());
        }
    }
    int moved = 0;
    for (std::size_t i = 0; i < 6; ++i)
        moved += at[0][i] != at[1][i];
    EXPECT_GE(moved, 4); // at least the second and minute hands turned in 7.25 s
}

// glsl_simple.osgt's own GLSL programs (compatibility profile, translated) under a FogNode: each
// pixel of the first program's shapes is the fog formula (FogMath.h's CPU mirror) applied to the
// same pixel unfogged, at the world point a pick ray finds there; under an AmbientOcclusionNode
// the programs still compile, and the gap between the two rows of shapes darkens, nothing brightens.
TEST(OsgLoader, GlslSimplesOwnShadersRunUnderFogAndAmbientOcclusion) {
    SGFX_REQUIRE(fs::exists(assets() / "glsl_simple.osgt"), "../shared/assets/osg");
    OsgStats stats;
    auto model = loadOsg(assets() / "glsl_simple.osgt", assetOptions(), &stats);
    EXPECT_EQ(stats.programs, 2u);
    FogParameters fp;
    fp.density = 0.04f;
    fp.falloff = 0.0f;
    fp.color = {0.3f, 0.5f, 0.7f};
    fp.sky = FogSky::Off;
    const glm::vec3 eye(2.2f, -12.0f, 1.6f);
    // One viewer for all three images: the model's GL objects belong to its context.
    auto v = Viewer::createHeadless(128, 96);
    v->camera()->setPerspective(40.0f, 0.5f, 100.0f);
    v->camera()->setLookAt(eye, {2.2f, -1.0f, 1.1f});
    v->camera()->clearColor = {0, 0, 0, 1};
    auto render = [&](std::shared_ptr<Node> scene) {
        auto root = Group::create();
        root->addChild(Light::create(LightType::Ambient));
        root->addChild(std::move(scene));
        v->setSceneData(root);
        v->frame();
        return v->capture();
    };
    auto fog = FogNode::create(fp);
    fog->addChild(model);
    const Image plain = render(model);
    const Image fogged = render(fog);
    const auto decode = [](int b) { return srgbToLinearByte(b); };
    int checked = 0;
    for (int y = 2; y < plain.height - 2; y += 3)
        for (int x = 2; x < plain.width - 2; x += 3) {
            // Pixel centres whose ray and its neighbours' hit the first program's shapes (z < 1.1;
            // the second program moves its vertices in w, so its drawn surface is not the file's).
            bool inside = true;
            std::optional<PickResult> hit;
            for (auto [dx, dy] : {std::pair{0, 0}, {-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
                auto h = pick(*v->camera(), *model, x + dx + 0.5, y + dy + 0.5);
                inside &= h && h->hit.point.z < 1.1;
                if (dx == 0 && dy == 0) hit = h;
            }
            if (!inside) continue;
            const double d = glm::length(hit->hit.point - glm::dvec3(eye));
            const double k =
                fog::amount<double>(double(fp.density) * d, fog::Response::Exponential, fp.maxOpacity);
            for (int c = 0; c < 3; ++c) {
                const double expected = decode(pixelAt(plain, x, y)[c]) * (1 - k) + fp.color[c] * k;
                EXPECT_NEAR(pixelAt(fogged, x, y)[c], test::srgbByte(expected), 2.0)
                    << x << "," << y << " c" << c;
            }
            ++checked;
        }
    EXPECT_GT(checked, 40);

    // AO: the shapes standing on a ground (built-in material) at the sphere's base, seen from above.
    auto ground = Transform::create(glm::translate(glm::mat4(1.0f), {2.2f, -1.0f, -1.0f}));
    ground->addChild(shapes::quad(14.0f, 8.0f));
    auto standing = Group::create();
    standing->addChild(model);
    standing->addChild(ground);
    v->camera()->setLookAt({2.2f, -8.0f, 3.0f}, {2.2f, -1.0f, -0.6f});
    const Image onGround = render(standing);
    auto ao = AmbientOcclusionNode::create();
    ao->addChild(standing);
    const Image occluded = render(ao);
    int darker = 0, brighter = 0;
    for (int y = 0; y < onGround.height; ++y)
        for (int x = 0; x < onGround.width; ++x)
            for (int c = 0; c < 3; ++c) {
                const auto h = pick(*v->camera(), *model, x + 0.5, y + 0.5);
                if (!h || h->hit.point.z > 1.1) continue; // the first program's shapes only
                const int diff = pixelAt(occluded, x, y)[c] - pixelAt(onGround, x, y)[c];
                darker += diff <= -3;
                brighter += diff >= 2;
            }
    EXPECT_GT(darker, 30);
    EXPECT_LT(brighter, 10);
}

namespace {

/// A coloured, unlit square tile of `size` metres at (x, y, z), in an osg::Geode.
osg::ref_ptr<osg::Geode> osgTile(float x, float y, float z, float size, const osg::Vec4& colour) {
    auto g = osgQuad(size / 2);
    auto* c = new osg::Vec4Array(osg::Array::BIND_OVERALL);
    c->push_back(colour);
    g->setColorArray(c);
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->addDrawable(g);
    geode->getOrCreateStateSet()->setMode(GL_LIGHTING, osg::StateAttribute::OFF);
    for (auto& v : *static_cast<osg::Vec3Array*>(g->getVertexArray()))
        v += osg::Vec3(x, y, z);
    g->dirtyBound();
    return geode;
}

} // namespace

// Switch, Sequence, LOD by distance and DOFTransform convert with OSG's meaning: the same
// children on, the same frame at the same time, the same ranges, the same matrix.
TEST(OsgLoader, SwitchSequenceLodAndDofKeepOsgsMeaning) {
    osg::ref_ptr<osg::Group> root = new osg::Group;
    osg::ref_ptr<osg::Switch> sw = new osg::Switch;
    for (int i = 0; i < 3; ++i)
        sw->addChild(osgTile(float(i) * 3, 0, 0, 1, osg::Vec4(1, 0, 0, 1)), i != 1);
    osg::ref_ptr<osg::Sequence> seq = new osg::Sequence;
    for (int i = 0; i < 3; ++i)
        seq->addChild(osgTile(float(i) * 3, 5, 0, 1, osg::Vec4(0, 1, 0, 1)), i == 0   ? 0.5
                                                                             : i == 1 ? 1.0
                                                                                      : 0.25);
    seq->setInterval(osg::Sequence::LOOP, 0, -1);
    seq->setDuration(1.0f, -1);
    seq->setMode(osg::Sequence::START);
    osg::ref_ptr<osg::LOD> lod = new osg::LOD;
    lod->addChild(osgTile(0, 10, 0, 1, osg::Vec4(0, 0, 1, 1)), 0.0f, 50.0f);
    lod->addChild(osgTile(0, 10, 0, 2, osg::Vec4(0, 0, 1, 1)), 50.0f, 1e6f);
    osg::ref_ptr<osgSim::DOFTransform> dof = new osgSim::DOFTransform;
    dof->setPutMatrix(osg::Matrix::rotate(0.4, osg::Vec3(0, 0, 1)) * osg::Matrix::translate(1, 2, 3));
    dof->setInversePutMatrix(osg::Matrix::inverse(dof->getPutMatrix()));
    dof->setMinHPR(osg::Vec3(-1, -0.5, 0));
    dof->setMaxHPR(osg::Vec3(1, 0.5, 0));
    dof->setCurrentHPR(osg::Vec3(0.3f, 0.2f, 0.0f));
    dof->addChild(osgTile(0, 0, 0, 1, osg::Vec4(1, 1, 1, 1)));
    for (osg::Node* n : {static_cast<osg::Node*>(sw.get()), static_cast<osg::Node*>(seq.get()),
                         static_cast<osg::Node*>(lod.get()), static_cast<osg::Node*>(dof.get())})
        root->addChild(n);
    auto loaded = roundTrip(*root, "switches");
    ASSERT_EQ(loaded->numChildren(), 1u);
    auto top = std::dynamic_pointer_cast<Group>(loaded->child(0));
    ASSERT_TRUE(top && top->numChildren() == 4);

    auto s = std::dynamic_pointer_cast<Switch>(top->child(0));
    ASSERT_TRUE(s);
    EXPECT_EQ(s->values(), (std::vector<bool>{true, false, true}));

    auto q = std::dynamic_pointer_cast<Sequence>(top->child(1));
    ASSERT_TRUE(q);
    UpdateVisitor update;
    // Frames of 0.5, 1 and 0.25 s from the first update, looping: hand-computed.
    for (auto [t, frame] : {std::pair{0.0, 0}, {0.25, 0}, {1.0, 1}, {1.6, 2}, {1.8, 0}, {2.4, 1}}) {
        update.simulationTime = t;
        q->accept(update);
        EXPECT_EQ(q->value(), frame) << "t = " << t;
    }

    auto l = std::dynamic_pointer_cast<LOD>(top->child(2));
    ASSERT_TRUE(l);
    EXPECT_EQ(l->rangeMode(), LOD::RangeMode::DistanceFromEye);
    EXPECT_EQ(l->range(0).maxPixels, 50.0f);
    EXPECT_EQ(l->range(1).minPixels, 50.0f);

    auto d = std::dynamic_pointer_cast<DOFTransform>(top->child(3));
    ASSERT_TRUE(d);
    osg::Matrix expected;
    dof->computeLocalToWorldMatrix(expected, nullptr);
    const glm::mat4 e = glm::make_mat4(osg::Matrixf(expected).ptr());
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            EXPECT_NEAR(d->matrix()[c][r], e[c][r], 1e-5f) << c << "," << r;
    // Driving an axis moves it as osgSim does.
    d->set("heading", -0.7);
    dof->setCurrentHPR(osg::Vec3(-0.7f, 0.2f, 0.0f));
    dof->computeLocalToWorldMatrix(expected, nullptr);
    const glm::mat4 e2 = glm::make_mat4(osg::Matrixf(expected).ptr());
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            EXPECT_NEAR(d->matrix()[c][r], e2[c][r], 1e-5f) << c << "," << r;
}

// A three-level paged quadtree written by osgDB (PagedLOD files naming their children's files):
// the coarse level draws at once, finer levels stream in on the pager's thread and are drawn,
// and they are unloaded when the camera leaves.
TEST(OsgLoader, PagedLodFilesStreamInAndExpire) {
    const auto dir = tempDir("paged");
    const osg::Vec4 colours[3] = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}};
    // Level k covers the square of side 64 / 2^k at (x, y); its finer level is in "tile_k_i.osgt".
    std::function<osg::ref_ptr<osg::Node>(int, float, float, int)> level = [&](int k, float x, float y,
                                                                               int id) {
        const float size = 64.0f / float(1 << k);
        osg::ref_ptr<osg::Node> tile = osgTile(x, y, 0, size, colours[k]);
        if (k == 2) return tile;
        osg::ref_ptr<osg::PagedLOD> plod = new osg::PagedLOD;
        plod->setCenterMode(osg::LOD::USER_DEFINED_CENTER);
        plod->setCenter(osg::Vec3(x, y, 0));
        plod->setRadius(size * 0.75f);
        plod->addChild(tile.get(), size * 2.0f, 1e7f);
        osg::ref_ptr<osg::Group> finer = new osg::Group;
        for (int i = 0; i < 4; ++i)
            finer->addChild(
                level(k + 1, x + size / 4 * (i % 2 ? 1 : -1), y + size / 4 * (i / 2 ? 1 : -1), id * 4 + i));
        const std::string name = "tile_" + std::to_string(k + 1) + "_" + std::to_string(id) + ".osgt";
        EXPECT_TRUE(osgDB::writeNodeFile(*finer, (dir / name).string()));
        plod->setFileName(1, name);
        plod->setRange(1, 0.0f, size * 2.0f);
        return osg::ref_ptr<osg::Node>(plod);
    };
    auto rootTile = level(0, 0, 0, 0);
    ASSERT_TRUE(osgDB::writeNodeFile(*rootTile, (dir / "terrain.osgt").string()));

    auto scene = loadOsg(dir / "terrain.osgt", {});
    auto v = Viewer::createHeadless(32, 32);
    v->camera()->setPerspective(30.0f, 0.1f, 1000.0f);
    v->camera()->clearColor = {0, 0, 0, 1};
    v->setSceneData(scene);
    const auto centre = [&] { return pixelAt(v->capture(), 16, 16); };
    // Far away: only the root tile, red.
    v->camera()->setLookAt({8, 8, 400}, {8, 8, 0}, {0, 1, 0});
    v->frame();
    EXPECT_EQ(centre(), glm::ivec4(255, 0, 0, 255));
    // Close over the point (8, 8): each level's file streams in, the coarser level shows meanwhile.
    v->camera()->setLookAt({8, 8, 20}, {8, 8, 0}, {0, 1, 0});
    glm::ivec4 seen[2];
    for (int k = 0; k < 2; ++k) {
        v->frame(); // requests the next level
        ASSERT_TRUE(v->databasePager()->waitUntilIdle(std::chrono::seconds(30)));
        v->frame(); // attaches it (between frames) and draws it
        v->frame();
        seen[k] = centre();
    }
    EXPECT_EQ(seen[0], glm::ivec4(0, 255, 0, 255));
    EXPECT_EQ(seen[1], glm::ivec4(0, 0, 255, 255));
    EXPECT_EQ(v->databasePager()->stats().failed, 0u);
    EXPECT_GE(v->databasePager()->stats().live, 2u);
    // Far again: the streamed levels go once they have been unused long enough.
    v->camera()->setLookAt({8, 8, 400}, {8, 8, 0}, {0, 1, 0});
    for (int i = 0; i < 40; ++i)
        v->frame(0.5);
    EXPECT_EQ(v->databasePager()->stats().live, 0u);
    EXPECT_EQ(centre(), glm::ivec4(255, 0, 0, 255));
}

// What the bridge does not convert gives one warning per class, naming the first node path, and
// the rest loads.
TEST(OsgLoader, UnconvertedClassesWarnOncePerClassAndTheRestLoads) {
    osg::ref_ptr<osg::Group> root = new osg::Group;
    root->setName("world");
    for (int i = 0; i < 2; ++i) {
        osg::ref_ptr<osg::ClipNode> clip = new osg::ClipNode;
        clip->setName("clip" + std::to_string(i));
        osg::ref_ptr<osg::Geode> geode = new osg::Geode;
        geode->addDrawable(osgQuad(1.0f + float(i)));
        clip->addChild(geode);
        root->addChild(clip);
    }
    OsgStats stats;
    auto loaded = roundTrip(*root, "warnings", &stats);
    ASSERT_EQ(stats.warnings.size(), 1u);
    EXPECT_NE(stats.warnings[0].find("osg::ClipNode"), std::string::npos) << stats.warnings[0];
    EXPECT_NE(stats.warnings[0].find("/world/clip0"), std::string::npos) << stats.warnings[0];
    EXPECT_NE(stats.warnings[0].find("2 in all"), std::string::npos) << stats.warnings[0];
    CountGeometries count;
    loaded->accept(count);
    EXPECT_EQ(count.c.triangles, 4u);
}

namespace {
osg::ref_ptr<osg::Geode> osgTileGeode() {
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->addDrawable(osgQuad(1.0f));
    return geode;
}
} // namespace

// Truncated and garbage files in each format: a LoadError naming the file, never a crash.
TEST(OsgLoader, TruncatedAndGarbageFilesGiveLoadErrorNamingTheFile) {
    SGFX_REQUIRE(fs::exists(assets() / "cessna.osgt"), "../shared/assets/osg");
    const auto dir = tempDir("bad");
    std::vector<fs::path> files;
    // Real files of each format written by osgDB, then cut.
    auto model = osgDB::readRefNodeFile((assets() / "glider.osgt").string());
    ASSERT_TRUE(model);
    for (const char* ext : {".osgt", ".osgb", ".osgx", ".ive", ".osg"}) {
        const auto whole = dir / (std::string("whole") + ext);
        ASSERT_TRUE(osgDB::writeNodeFile(*model, whole.string())) << ext;
        std::ifstream in(whole, std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), {});
        for (double keep : {0.0, 0.1, 0.5, 0.9}) {
            const auto cut = dir / ("cut" + std::to_string(int(keep * 100)) + ext);
            std::ofstream(cut, std::ios::binary) << bytes.substr(0, std::size_t(double(bytes.size()) * keep));
            files.push_back(cut);
        }
    }
    for (const char* ext : {".osgt", ".osgb", ".osgx", ".ive", ".osg", ".flt"}) {
        const auto garbage = dir / (std::string("garbage") + ext);
        std::ofstream out(garbage, std::ios::binary);
        for (int i = 0; i < 4096; ++i)
            out.put(char((i * 2654435761u) >> 13));
        files.push_back(garbage);
    }
    files.push_back(dir / "missing.osgt");
    // Values an sgfx setter refuses (a NaN matrix) and values the bridge leaves out (a NaN uniform, a
    // NaN animation path): a LoadError naming the node path, or a warning and the rest loads.
    {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        osg::ref_ptr<osg::Group> top = new osg::Group;
        osg::ref_ptr<osg::MatrixTransform> bad = new osg::MatrixTransform(osg::Matrix::translate(nan, 0, 0));
        bad->setName("broken");
        top->addChild(bad);
        try {
            (void)roundTrip(*top, "nan_matrix", nullptr, ".osgb"); // binary: NaN survives the file
            ADD_FAILURE() << "a NaN matrix loaded";
        } catch (const LoadError& e) {
            EXPECT_NE(std::string(e.what()).find("broken"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("non-finite"), std::string::npos) << e.what();
        }
        osg::ref_ptr<osg::MatrixTransform> moving = new osg::MatrixTransform;
        osg::ref_ptr<osg::AnimationPath> path = new osg::AnimationPath;
        path->insert(0.0, osg::AnimationPath::ControlPoint(osg::Vec3d(0, 0, 0)));
        path->insert(1.0, osg::AnimationPath::ControlPoint(osg::Vec3d(nan, 0, 0)));
        moving->setUpdateCallback(new osg::AnimationPathCallback(path.get()));
        moving->getOrCreateStateSet()->addUniform(new osg::Uniform("gain", float(nan)));
        moving->addChild(osgTileGeode());
        OsgStats stats;
        auto loaded = roundTrip(*moving, "nan_values", &stats, ".osgb");
        std::string all;
        for (const auto& w : stats.warnings)
            all += w + "\n";
        EXPECT_NE(all.find("osg::AnimationPath with a non-finite"), std::string::npos) << all;
        EXPECT_NE(all.find("osg::Uniform 'gain' with a non-finite value"), std::string::npos) << all;
        CountGeometries count;
        loaded->accept(count);
        EXPECT_EQ(count.c.triangles, 2u);
    }
    // A node made its own child through its UniqueID (a corrupt file's cycle): refused, not recursed.
    {
        osg::ref_ptr<osg::MatrixTransform> top = new osg::MatrixTransform;
        top->addChild(new osg::Group);
        std::stringstream text;
        osg::ref_ptr<osgDB::Options> ascii = new osgDB::Options;
        ascii->setPluginStringData("fileType", "Ascii");
        osgDB::Registry::instance()->getReaderWriterForExtension("osgt")->writeNode(*top, text, ascii.get());
        std::string doc = text.str();
        const auto at = doc.find("Children 1 {");
        ASSERT_NE(at, std::string::npos);
        doc.replace(at, 12, "Children 2 {\n    osg::MatrixTransform {\n      UniqueID 1\n    }");
        const auto cycle = dir / "cycle.osgt";
        std::ofstream(cycle) << doc;
        try {
            (void)loadOsg(cycle);
            ADD_FAILURE() << "a cycle loaded";
        } catch (const LoadError& e) {
            EXPECT_NE(std::string(e.what()).find("cycle"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("cycle.osgt"), std::string::npos) << e.what();
        }
    }
    for (const auto& f : files) {
        SCOPED_TRACE(f.string());
        try {
            OsgStats stats;
            auto root = loadOsg(f, {}, &stats);
            // osgDB may recover part of a cut file; then what it read converts like any graph.
            CountGeometries count;
            root->accept(count);
            SUCCEED();
        } catch (const LoadError& e) {
            EXPECT_NE(std::string(e.what()).find(f.filename().string()), std::string::npos) << e.what();
        }
    }
}

#else

TEST(OsgLoader, WithoutTheBridgeLoadModelSaysHowToGetIt) {
    EXPECT_FALSE(osgSupported());
    const auto file = tempDir("absent") / "model.osgt";
    std::ofstream(file) << "#Ascii Scene\n";
    try {
        loadModel(file);
        FAIL() << "no LoadError";
    } catch (const LoadError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("model.osgt"), std::string::npos) << m;
        EXPECT_NE(m.find("libopenscenegraph-dev"), std::string::npos) << m;
    }
}

#endif

// The OpenSceneGraph bridge (loadOsg): OSG's own sample data loads with OSG's counts and bounds,
// renders as OSG draws it (textures, billboards, sphere maps, animation paths, the file's own
// shaders under fog), and bad files give LoadError naming the file.
#include "TestUtil.h"

#include <sgfx/Billboard.h>
#include <sgfx/Geometry.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/OsgLoader.h>
#include <sgfx/Viewer.h>
#include <sgfx/Visitors.h>

#include <glm/gtc/type_ptr.hpp>

#include <filesystem>
#include <fstream>
#include <set>

#ifdef SGFX_TEST_HAVE_OSG
#include <osg/AnimationPath>
#include <osg/ClipNode>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/MatrixTransform>
#include <osg/NodeVisitor>
#include <osg/TexGen>
#include <osg/Texture2D>
#include <osgDB/ReadFile>
#include <osgDB/WriteFile>
#endif

namespace fs = std::filesystem;
using namespace sgfx;
using sgfx::test::pixelAt;

namespace {

fs::path assets() {
    return fs::path(SGFX_SOURCE_DIR) / ".." / "shared" / "assets" / "osg";
}

OsgOptions assetOptions() {
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
std::shared_ptr<Group> roundTrip(osg::Node& node, const std::string& name, OsgStats* stats = nullptr) {
    const auto file = tempDir("scene") / (name + ".osgt");
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
    auto viewer = test::orthoTopViewer(size, 8.0f);
    viewer->setSceneData(root);
    viewer->frame();
    const Image img = viewer->capture();
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

// PagedLOD and the DatabasePager: requests from the cull (once each), the coarser level drawn
// while a file loads, attachment between frames, expiry by frames and time, load errors reported
// once; and a three-level paged terrain rendered headless, whose loads never hold up a frame and
// whose memory and GL objects go when the camera leaves.
#include "TestUtil.h"

#include <sgfx/CullVisitor.h>
#include <sgfx/DatabasePager.h>
#include <sgfx/Geometry.h>
#include <sgfx/GltfLoader.h>
#include <sgfx/GltfWriter.h>
#include <sgfx/Intersection.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/PagedLOD.h>
#include <sgfx/Queries.h>
#include <sgfx/Shapes.h>
#include <sgfx/gl/Objects.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <future>
#include <limits>
#include <mutex>
#include <string>
#include <thread>
#include <unistd.h>

using namespace sgfx;
using namespace sgfx::test;
namespace fs = std::filesystem;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr auto kWait = std::chrono::seconds(30); // a bound on waiting for loads, not a timing check

std::shared_ptr<Geometry> namedBox(const std::string& name) {
    auto g = shapes::box(glm::vec3(1.0f));
    g->name = name;
    return g;
}

std::shared_ptr<Camera> camera90() {
    auto c = Camera::create();
    c->setViewport(0, 0, 100, 100);
    c->setPerspective(90.0f, 0.1f, 1000.0f);
    return c;
}

std::string cullNames(Camera& cam, DatabasePager* pager) {
    RenderQueue q;
    CullVisitor cv(cam, q);
    cv.setDatabasePager(pager);
    cv.run(cam);
    std::string names;
    for (const auto& it : q.opaque)
        names += it.geometry->name + " ";
    return names;
}

// A temporary directory, removed with everything in it.
struct TempDir {
    fs::path path = fs::temp_directory_path() / ("sgfx_paged_" + std::to_string(::getpid()));
    TempDir() { fs::create_directories(path); }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

} // namespace

TEST(PagedLod, CullRequestsOnceDrawsCoarserMeanwhileAndAttachesBetweenFrames) {
    DatabasePager pager;
    std::mutex seenMutex;
    std::vector<fs::path> seen;
    pager.setLoader([&](const fs::path& p) -> NodePtr {
        std::lock_guard lock(seenMutex);
        seen.push_back(p);
        return namedBox(p.stem().string());
    });
    auto lod = PagedLOD::create();
    lod->name = "tile";
    lod->setRangeMode(LOD::RangeMode::DistanceFromEye);
    lod->setDatabasePath("/tiles");
    lod->addChild(namedBox("coarse"), 10.0f, kInf);
    lod->addChild("mid.tile", 5.0f, 10.0f);
    lod->addChild("fine.tile", 0.0f, 5.0f);
    lod->setUserSphere({0, 0, 0}, 1.0f);
    auto cam = camera90();
    cam->addChild(lod);
    cam->setLookAt({0, -3, 0}, {0, 0, 0});
    // Neither finer level is loaded: the coarse one is drawn, and fine asked for once.
    EXPECT_EQ(cullNames(*cam, &pager), "coarse ");
    EXPECT_EQ(cullNames(*cam, &pager), "coarse ");
    EXPECT_EQ(cullNames(*cam, nullptr), "coarse ");
    EXPECT_EQ(pager.stats().requested, 1u);
    // Queries see what the cull draws, not the placeholders (the coarse box's top is at 0.5).
    EXPECT_NEAR(heightOfTerrain(*lod, 0.1, 0.1).value_or(-1.0), 0.5, 1e-6);
    RayIntersector ray(glm::dvec3(0, -3, 0), glm::dvec3(0, 1, 0));
    IntersectionVisitor shown(ray);
    shown.lodSelection = IntersectionVisitor::LodSelection::Shown;
    shown.view = QueryView::of(*cam);
    shown.visit(*lod);
    ASSERT_NE(ray.nearest(), nullptr);
    EXPECT_EQ(ray.nearest()->geometry->name, "coarse");
    ASSERT_TRUE(pager.waitUntilIdle(kWait));
    EXPECT_EQ(cullNames(*cam, &pager), "coarse ") << "loaded, but attached only between frames";
    EXPECT_EQ(pager.stats().pending, 1u);
    EXPECT_EQ(pager.updateSceneGraph(1, 0.25).size(), 0u);
    EXPECT_TRUE(lod->loaded(2));
    EXPECT_EQ(lod->child(2)->name, "fine");
    {
        std::lock_guard lock(seenMutex);
        ASSERT_EQ(seen.size(), 1u);
        EXPECT_EQ(seen[0], fs::path("/tiles/fine.tile"));
    }
    EXPECT_EQ(cullNames(*cam, &pager), "fine ");
    const DatabasePager::Stats s = pager.stats();
    EXPECT_EQ(s.pending, 0u);
    EXPECT_EQ(s.loaded, 1u);
    EXPECT_EQ(s.live, 1u);
    std::weak_ptr<Node> fine = lod->child(2);

    // At 7 m mid is wanted: coarse meanwhile (fine is finer, not a stand-in). fine goes unused and
    // expires after more than 2 frames and at least 1 s: frame f is at 0.25 f s, fine was last
    // drawn in frame 1 (0.25 s), so frames allow it from frame 4 and time from frame 5.
    pager.setExpiry(2, 1.0);
    cam->setLookAt({0, -7, 0}, {0, 0, 0});
    EXPECT_EQ(cullNames(*cam, &pager), "coarse ");
    ASSERT_TRUE(pager.waitUntilIdle(kWait));
    for (std::uint64_t f = 2; f <= 4; ++f) {
        pager.updateSceneGraph(f, 0.25 * double(f));
        EXPECT_TRUE(lod->loaded(2)) << "frame " << f;
        EXPECT_EQ(cullNames(*cam, &pager), "mid ") << "frame " << f;
    }
    EXPECT_FALSE(fine.expired());
    const std::vector<NodePtr> unloaded = pager.updateSceneGraph(5, 1.25);
    ASSERT_EQ(unloaded.size(), 1u);
    EXPECT_EQ(unloaded[0]->name, "fine");
    EXPECT_FALSE(lod->loaded(2));
    EXPECT_TRUE(lod->loaded(1)) << "mid is drawn every frame";
    EXPECT_EQ(pager.stats().expired, 1u);
    EXPECT_EQ(pager.stats().live, 1u);
}

TEST(PagedLod, LoadErrorsAreReportedOnceNamingNodeAndFile) {
    TempDir dir;
    DatabasePager pager;
    pager.setLoader([](const fs::path& p) -> NodePtr { return loadModel(p); });
    auto lod = PagedLOD::create();
    lod->name = "broken";
    lod->setDatabasePath(dir.path);
    lod->addChild(namedBox("coarse"), 0.0f, 10.0f);
    lod->addChild("missing.gltf", 10.0f, kInf);
    auto noLoader = PagedLOD::create();
    noLoader->name = "orphan";
    noLoader->addChild("any.tile", 0.0f, kInf);
    DatabasePager bare; // no loader anywhere
    auto cam = camera90();
    cam->addChild(lod);
    cam->setLookAt({0, -3, 0}, {0, 0, 0}); // 1 m box: ~57 px
    for (std::uint64_t f = 1; f <= 4; ++f) {
        EXPECT_EQ(cullNames(*cam, &pager), "coarse ") << "frame " << f;
        ASSERT_TRUE(pager.waitUntilIdle(kWait));
        pager.updateSceneGraph(f, double(f));
    }
    EXPECT_EQ(pager.stats().requested, 1u);
    EXPECT_EQ(pager.stats().failed, 1u);
    EXPECT_EQ(pager.stats().pending, 0u);
    EXPECT_TRUE(lod->failed(1));
    const std::vector<std::string> errors = pager.errors();
    ASSERT_EQ(errors.size(), 1u);
    EXPECT_NE(errors[0].find("'broken'"), std::string::npos) << errors[0];
    EXPECT_NE(errors[0].find((dir.path / "missing.gltf").string()), std::string::npos) << errors[0];
    // Setting the name again asks again.
    lod->setFileName(1, "missing.gltf");
    EXPECT_FALSE(lod->failed(1));
    cullNames(*cam, &pager);
    EXPECT_EQ(pager.stats().requested, 2u);

    bare.request(*noLoader, 0);
    ASSERT_TRUE(bare.waitUntilIdle(kWait));
    bare.updateSceneGraph(1, 0.0);
    ASSERT_EQ(bare.errors().size(), 1u);
    EXPECT_NE(bare.errors()[0].find("no loader"), std::string::npos) << bare.errors()[0];
    EXPECT_NE(bare.errors()[0].find("any.tile"), std::string::npos) << bare.errors()[0];
}

TEST(PagedLod, BadSettersAreRefusedAndKeepTheOldState) {
    auto lod = PagedLOD::create();
    lod->name = "tile";
    lod->addChild("a.tile", 0.0f, 10.0f);
    EXPECT_THROW(lod->addChild(fs::path(), 0.0f, 1.0f), std::invalid_argument);
    try {
        lod->addChild("b.tile", 5.0f, 1.0f);
        ADD_FAILURE() << "a reversed range was taken";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("'tile'"), std::string::npos) << e.what();
    }
    EXPECT_THROW(lod->setFileName(3, "c.tile"), std::out_of_range);
    EXPECT_EQ(lod->numChildren(), 1u);
    EXPECT_EQ(lod->fileName(0), fs::path("a.tile"));
    EXPECT_FALSE(lod->loaded(0));
    EXPECT_EQ(lod->coarserLoaded(0), PagedLOD::npos);
    DatabasePager pager;
    pager.setExpiry(5, 2.0);
    EXPECT_THROW(pager.setExpiry(1, -1.0), std::invalid_argument);
    EXPECT_THROW(pager.setExpiry(1, std::nan("")), std::invalid_argument);
    EXPECT_EQ(pager.expiryFrames(), 5u);
    EXPECT_EQ(pager.expiryDelay(), 2.0);
}

// ---------------------------------------------------------------- a three-level paged terrain
namespace {

// Level L tiles are 16 / 2^L m squares over [-8, 8]^2 at z = 0: red, green, blue. Levels 0 and 1
// are PagedLODs by distance: their own quad beyond kRange[L] of the tile's centre, and within it
// the file with their four children, "L<L+1>_<ix>_<iy>.tile" (ix, iy: the parent's cell). The
// loader builds level-1 tiles itself and reads level-2 tiles from glTF files written up front.
constexpr float kRange[2] = {30.0f, 12.0f};
const glm::vec3 kColour[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

float edgeOf(int level) {
    return 16.0f / float(1 << level);
}
glm::vec3 centreOf(int level, int ix, int iy) {
    const float e = edgeOf(level);
    return {-8.0f + e * (float(ix) + 0.5f), -8.0f + e * (float(iy) + 0.5f), 0.0f};
}

NodePtr quadTile(int level, int ix, int iy) {
    auto q = shapes::quad(edgeOf(level), edgeOf(level));
    q->name = "quad " + std::to_string(level);
    auto m = Material::create();
    m->ambient = glm::vec3(0);
    m->diffuse = glm::vec4(0, 0, 0, 1);
    m->emissive = kColour[level];
    q->getOrCreateStateSet().material.set(m);
    auto t = Transform::create(glm::translate(glm::mat4(1.0f), centreOf(level, ix, iy)));
    t->addChild(q);
    return t;
}

std::shared_ptr<PagedLOD> pagedTile(int level, int ix, int iy, const fs::path& dir) {
    auto lod = PagedLOD::create();
    lod->name = "tile " + std::to_string(level) + " " + std::to_string(ix) + " " + std::to_string(iy);
    lod->setRangeMode(LOD::RangeMode::DistanceFromEye);
    lod->setDatabasePath(dir);
    lod->setUserSphere(centreOf(level, ix, iy), edgeOf(level) * 0.75f);
    lod->addChild(quadTile(level, ix, iy), kRange[level], kInf);
    lod->addChild("L" + std::to_string(level + 1) + "_" + std::to_string(ix) + "_" + std::to_string(iy) +
                      ".tile",
                  0.0f, kRange[level]);
    return lod;
}

fs::path leafFile(const fs::path& dir, int ix, int iy) {
    return dir / ("leaf_" + std::to_string(ix) + "_" + std::to_string(iy) + ".gltf");
}

// The four children of the file's parent cell.
NodePtr loadTiles(const fs::path& file) {
    int level = 0, px = 0, py = 0;
    if (std::sscanf(file.filename().string().c_str(), "L%d_%d_%d.tile", &level, &px, &py) != 3)
        throw std::runtime_error("not a tile name");
    auto group = Group::create();
    for (int k = 0; k < 4; ++k) {
        const int ix = 2 * px + (k & 1), iy = 2 * py + (k >> 1);
        if (level < 2)
            group->addChild(pagedTile(level, ix, iy, file.parent_path()));
        else
            group->addChild(loadModel(leafFile(file.parent_path(), ix, iy)));
    }
    return group;
}

// Opens the gate when the test leaves, however it leaves, so the pager's thread can join.
struct Gate {
    std::promise<void> promise;
    std::shared_future<void> future = promise.get_future().share();
    bool open = false;
    void release() {
        if (!open) promise.set_value();
        open = true;
    }
    ~Gate() { release(); }
};

glm::ivec4 centrePixel(Viewer& v) {
    const Image img = v.capture();
    return pixelAt(img, img.width / 2, img.height / 2);
}

// The pixel is the level's colour: its channel bright, the others dark.
void expectLevel(Viewer& v, int level, const std::string& when) {
    const glm::ivec4 p = centrePixel(v);
    for (int c = 0; c < 3; ++c) {
        if (kColour[level][c] > 0.5f)
            EXPECT_GT(p[c], 150) << when << ": channel " << c;
        else
            EXPECT_LT(p[c], 60) << when << ": channel " << c;
    }
}

long meshObjects() {
    return gl::liveObjects()[gl::Kind::Buffer] + gl::liveObjects()[gl::Kind::VertexArray];
}

} // namespace

TEST(PagedTerrain, LoadsNeverHoldFramesTilesAttachAndMemoryReturns) {
    TempDir dir;
    for (int iy = 0; iy < 4; ++iy)
        for (int ix = 0; ix < 4; ++ix) {
            const NodePtr leaf = quadTile(2, ix, iy);
            writeGltf(*leaf, leafFile(dir.path, ix, iy));
        }
    auto v = Viewer::createHeadless(64, 64);
    Gate gate; // after the viewer: released before the viewer's pager joins its thread
    auto entered = std::make_shared<std::atomic<bool>>(false);
    v->databasePager()->setLoader([future = gate.future, entered](const fs::path& file) {
        if (file.filename() == "L1_0_0.tile") { // the first load waits until the test lets it go
            *entered = true;
            future.wait();
        }
        return loadTiles(file);
    });
    v->databasePager()->setExpiry(3, 0.0);
    auto root = pagedTile(0, 0, 0, dir.path);
    v->setSceneData(root);
    auto look = [&](glm::vec3 eye) { v->camera()->setLookAt(eye, eye - glm::vec3(0, 0, 1), {0, 1, 0}); };

    look({2, 2, 100}); // 100 m from the root's centre: the red tile alone
    for (int i = 0; i < 3; ++i)
        v->frame();
    expectLevel(*v, 0, "far");
    EXPECT_EQ(v->databasePager()->stats().requested, 0u);
    const long baseline = meshObjects();

    // 20 m: level 1 is wanted, and its load blocks. Frames go on, the red tile in its place.
    look({2, 2, 20});
    v->frame();
    for (int i = 0; i < 1000 && !*entered; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ASSERT_TRUE(*entered) << "the pager never started the load";
    for (int i = 0; i < 5; ++i) {
        v->frame();
        expectLevel(*v, 0, "while level 1 loads, frame " + std::to_string(i));
        EXPECT_EQ(v->databasePager()->stats().pending, 1u);
        EXPECT_EQ(v->databasePager()->stats().loaded, 0u);
    }
    gate.release();
    ASSERT_TRUE(v->databasePager()->waitUntilIdle(kWait));
    v->frame(); // attached in this frame's update
    expectLevel(*v, 1, "level 1 attached");
    ASSERT_TRUE(root->loaded(1));
    std::weak_ptr<Node> level1 = root->child(1);
    EXPECT_EQ(v->databasePager()->stats().loaded, 1u);

    // 5 m above (3, 3): tile (1, 1) of level 1 wants its children; green until they arrive.
    look({3, 3, 5});
    v->frame();
    expectLevel(*v, 1, "while level 2 loads");
    ASSERT_TRUE(v->databasePager()->waitUntilIdle(kWait));
    v->frame();
    expectLevel(*v, 2, "level 2 attached");
    auto tile11 = std::dynamic_pointer_cast<PagedLOD>(static_cast<Group&>(*root->child(1)).child(3));
    ASSERT_TRUE(tile11);
    ASSERT_TRUE(tile11->loaded(1));
    std::weak_ptr<Node> level2 = tile11->child(1);
    tile11.reset();
    EXPECT_GT(meshObjects(), baseline);
    EXPECT_TRUE(v->databasePager()->errors().empty());

    // Back to 100 m: after more than 3 frames unused, both levels go, with their GL objects.
    look({2, 2, 100});
    for (int i = 0; i < 6; ++i)
        v->frame();
    expectLevel(*v, 0, "far again");
    EXPECT_TRUE(level1.expired());
    EXPECT_TRUE(level2.expired());
    EXPECT_FALSE(root->loaded(1));
    const DatabasePager::Stats s = v->databasePager()->stats();
    EXPECT_GE(s.expired, 2u);
    EXPECT_EQ(s.live, 0u);
    EXPECT_EQ(s.pending, 0u);
    EXPECT_EQ(meshObjects(), baseline);
    expectNoGlErrors(*v);
}

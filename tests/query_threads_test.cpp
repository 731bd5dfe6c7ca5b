// Queries on two threads while the viewer culls and draws, for 100 frames, with a part of the scene
// moved by an update callback every frame. Built with ThreadSanitizer by scripts/test.sh as well.
// The pattern under test (docs/queries.md): update() changes the scene; prepareForQueries() on
// that thread; then queries on other threads run alongside renderFrame().
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Queries.h>
#include <sgfx/Shapes.h>
#include <sgfx/Viewer.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <atomic>
#include <barrier>
#include <random>
#include <thread>

using namespace sgfx;

namespace {

// Terrain z = x/64 + y/32 (exact at the integer vertices), 64 m square.
std::shared_ptr<Geometry> slope() {
    auto g = Geometry::create();
    const int n = 32;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = float(i * 2), y = float(j * 2);
            g->positions.push_back({x, y, x / 64.0f + y / 32.0f});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const auto v = std::uint32_t(j * (n + 1) + i), w = v + std::uint32_t(n) + 1;
            g->indices.insert(g->indices.end(), {v, v + 1, w + 1, v, w + 1, w});
        }
    return g;
}

double slopeHeight(double x, double y) {
    return x / 64.0 + y / 32.0;
}

// The moving box's x at frame f; it is 2 m tall with its base at z = 10.
double boxX(std::uint64_t f) {
    return 8.0 + double(f % 40);
}

} // namespace

TEST(QueryThreads, TwoThreadsDuringHundredFrames) {
    auto root = Group::create();
    root->addChild(slope());
    auto mover = Transform::create();
    mover->addChild(shapes::box({2, 2, 2}));
    mover->updateCallback = [](Node& n, UpdateVisitor& uv) {
        static_cast<Transform&>(n).setMatrix(
            glm::translate(glm::mat4(1.0f), {float(boxX(uv.frameNumber)), 32.0f, 11.0f}));
    };
    root->addChild(mover);
    for (int i = 0; i < 6; ++i) // obstacles for the lines of sight
        root->addChild(
            Transform::create(glm::translate(glm::mat4(1.0f), {10.0f * float(i) + 5.0f, 10.0f, 1.0f})));
    for (int i = 0; i < 6; ++i)
        static_cast<Group&>(*root->child(std::size_t(2 + i))).addChild(shapes::box({1, 1, 4}));

    auto viewer = Viewer::createHeadless(96, 64);
    viewer->setSceneData(root);
    viewer->camera()->setLookAt({-20, -20, 40}, {32, 32, 0});

    constexpr int kFrames = 100, kThreads = 2;
    std::atomic<std::uint64_t> frame{0};
    std::atomic<int> wrong{0}, queries{0};
    std::barrier sync(kThreads + 1);
    auto worker = [&](int seed) {
        std::mt19937 rng{std::uint32_t(seed)};
        std::uniform_real_distribution<double> u(0.5, 63.5);
        for (int f = 0; f < kFrames; ++f) {
            sync.arrive_and_wait(); // update done, scene prepared
            const std::uint64_t now = frame.load();
            for (int k = 0; k < 50; ++k) {
                const double x = u(rng), y = u(rng);
                const auto h = heightOfTerrain(*root, x, y);
                const double bx = boxX(now);
                const bool onBox = std::abs(x - bx) < 0.99 && std::abs(y - 32.0) < 0.99;
                const double r = std::fmod(x + 5.0, 10.0); // 0 or 10 at a post's axis
                const bool onPost = std::abs(y - 10.0) < 0.51 && (r < 0.51 || r > 9.49);
                const bool nearEdge =
                    std::abs(std::abs(x - bx) - 1.0) < 0.02 || std::abs(std::abs(y - 32) - 1.0) < 0.02;
                if (onPost || nearEdge) continue; // the posts stand on the slope; edges are ambiguous
                const double expected = onBox ? 12.0 : slopeHeight(x, y);
                if (!h || std::abs(*h - expected) > 1e-9) ++wrong;
                // Above the slope at 20 m: nothing is that high, so every line is clear.
                if (!lineOfSight(*root, {x, y, 20.0}, {64.0 - x, 64.0 - y, 20.0})) ++wrong;
                queries += 2;
            }
            sync.arrive_and_wait(); // frame drawn
        }
    };
    std::thread a(worker, 1), b(worker, 2);
    for (int f = 0; f < kFrames; ++f) {
        viewer->update();
        frame.store(std::uint64_t(f + 1)); // UpdateVisitor::frameNumber after this update
        prepareForQueries(*root);
        sync.arrive_and_wait();
        viewer->renderFrame();
        sync.arrive_and_wait();
    }
    a.join();
    b.join();
    EXPECT_EQ(wrong.load(), 0);
    EXPECT_GT(queries.load(), kFrames * kThreads * 60);
    // A line through a post is blocked; one over it is clear.
    EXPECT_FALSE(lineOfSight(*root, {5, 0, 1}, {5, 20, 1}));
    EXPECT_TRUE(lineOfSight(*root, {5, 0, 4}, {5, 20, 4}));
}

// Scene queries against closed forms and against a brute-force reference that shares none of the
// query code (its own traversal, every triangle, a plane-and-edge-sign test instead of
// Möller–Trumbore).
#include <sgfx/Billboard.h>
#include <sgfx/Camera.h>
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Intersection.h>
#include <sgfx/LOD.h>
#include <sgfx/Queries.h>
#include <sgfx/Shapes.h>
#include <sgfx/Viewer.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

using namespace sgfx;

namespace {

constexpr double kTol = 1e-6;

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tol, const char* what) {
    EXPECT_LE(glm::length(a - b), tol) << what << ": (" << a.x << ", " << a.y << ", " << a.z << ") against ("
                                       << b.x << ", " << b.y << ", " << b.z << ")";
}

std::shared_ptr<Transform> placed(NodePtr child, const glm::mat4& m, const std::string& name = {}) {
    auto t = Transform::create(m);
    t->name = name;
    t->addChild(std::move(child));
    return t;
}

// Runs `intersector` over `scene` with and without the subtree index; both must agree.
template <class I>
std::vector<Intersection>
run(I intersector, Node& scene, Intersector::Limit limit = Intersector::Limit::All,
    std::optional<QueryView> view = {},
    IntersectionVisitor::LodSelection lods = IntersectionVisitor::LodSelection::Finest,
    NodeMask mask = ~NodeMask{0}) {
    std::vector<Intersection> results[2];
    for (int indexed = 0; indexed < 2; ++indexed) {
        I copy = intersector;
        copy.limit = limit;
        IntersectionVisitor iv(copy, mask);
        iv.useSubtreeIndex = indexed == 1;
        iv.view = view;
        iv.lodSelection = lods;
        iv.visit(scene);
        results[indexed] = copy.intersections();
    }
    EXPECT_EQ(results[0].size(), results[1].size()) << "the subtree index changes the number of hits";
    if (limit == Intersector::Limit::Any) return results[1]; // any one hit: which is not specified
    for (std::size_t i = 0; i < std::min(results[0].size(), results[1].size()); ++i) {
        EXPECT_EQ(results[0][i].geometry, results[1][i].geometry);
        EXPECT_EQ(results[0][i].primitiveIndex, results[1][i].primitiveIndex);
        EXPECT_EQ(results[0][i].nodePath, results[1][i].nodePath);
        expectNear(results[0][i].point, results[1][i].point, 1e-9, "indexed point");
    }
    return results[1];
}

} // namespace

TEST(Query, BoxFaceHitExactly) {
    auto box = shapes::box({2, 2, 2});
    box->name = "box";
    auto root = Group::create();
    root->addChild(box);
    const auto hits = run(LineSegmentIntersector({5.0, 0.3, 0.2}, {-5.0, 0.3, 0.2}), *root);
    ASSERT_EQ(hits.size(), 2u); // in at +X, out at -X
    expectNear(hits[0].point, {1.0, 0.3, 0.2}, kTol, "entry point");
    expectNear(hits[0].geometricNormal, {1, 0, 0}, kTol, "entry normal");
    expectNear(hits[0].normal, {1, 0, 0}, kTol, "interpolated normal");
    EXPECT_NEAR(hits[0].distance, 4.0, kTol);
    EXPECT_NEAR(hits[0].ratio, 0.4, kTol);
    expectNear(hits[1].point, {-1.0, 0.3, 0.2}, kTol, "exit point");
    expectNear(hits[1].geometricNormal, {-1, 0, 0}, kTol, "exit normal (the face's front is outwards)");
    ASSERT_EQ(hits[0].nodePath.size(), 2u);
    EXPECT_EQ(hits[0].nodePath.back(), box.get());
    EXPECT_EQ(hits[0].geometry, box.get());
    // The +X face spans y and z from -1 to 1 with texture u along +y: u = (y + 1) / 2.
    ASSERT_TRUE(hits[0].texcoord.has_value());
    const auto& t = hits[0].vertexIndices;
    const glm::dvec3 b = hits[0].barycentric;
    const glm::dvec3 rebuilt = b.x * glm::dvec3(box->positions[t[0]]) +
                               b.y * glm::dvec3(box->positions[t[1]]) +
                               b.z * glm::dvec3(box->positions[t[2]]);
    expectNear(rebuilt, hits[0].point, kTol, "barycentric reconstruction");
    EXPECT_NEAR(b.x + b.y + b.z, 1.0, 1e-12);
}

TEST(Query, RayHasNoEndSegmentHas) {
    auto root = Group::create();
    root->addChild(placed(shapes::box({2, 2, 2}), glm::translate(glm::mat4(1.0f), {100, 0, 0})));
    EXPECT_TRUE(run(LineSegmentIntersector({0, 0, 0}, {10, 0, 0}), *root).empty());
    const auto hits = run(RayIntersector({0, 0, 0}, {10, 0, 0}), *root, Intersector::Limit::Nearest);
    ASSERT_EQ(hits.size(), 1u);
    expectNear(hits[0].point, {99, 0, 0}, kTol, "ray hit");
    EXPECT_NEAR(hits[0].distance, 99.0, kTol);
}

TEST(Query, PlaneObliqueRay) {
    auto ground = shapes::quad(20, 20);
    auto root = Group::create();
    root->addChild(placed(ground, glm::translate(glm::mat4(1.0f), {0, 0, 3})));
    const glm::dvec3 a(-2, 1, 10), b(4, -2, -5);
    const auto hits = run(LineSegmentIntersector(a, b), *root);
    ASSERT_EQ(hits.size(), 1u);
    const double t = (10.0 - 3.0) / 15.0; // z(t) = 10 - 15 t = 3
    expectNear(hits[0].point, a + t * (b - a), kTol, "plane point");
    expectNear(hits[0].geometricNormal, {0, 0, 1}, kTol, "plane normal");
    ASSERT_TRUE(hits[0].texcoord.has_value());
}

TEST(Query, MirroredBoxKeepsFrontNormalsOutwards) {
    auto root = Group::create();
    const glm::mat4 mirror =
        glm::scale(glm::mat4(1.0f), {-1, 1, 1}) * glm::translate(glm::mat4(1.0f), {3, 0, 0});
    root->addChild(placed(shapes::box({2, 2, 2}), mirror));
    const auto hits = run(LineSegmentIntersector({-10, 0.25, -0.5}, {10, 0.25, -0.5}), *root);
    ASSERT_EQ(hits.size(), 2u);
    expectNear(hits[0].point, {-4, 0.25, -0.5}, kTol, "mirrored entry");
    expectNear(hits[0].geometricNormal, {-1, 0, 0}, kTol, "mirrored entry normal points out");
    expectNear(hits[0].normal, {-1, 0, 0}, kTol, "mirrored interpolated normal");
    expectNear(hits[1].point, {-2, 0.25, -0.5}, kTol, "mirrored exit");
    expectNear(hits[1].geometricNormal, {1, 0, 0}, kTol, "mirrored exit normal points out");
}

TEST(Query, InstancedBoxHitsEveryInstance) {
    auto box = shapes::box({2, 2, 2});
    box->instances = {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), {10, 0, 0}),
                      glm::translate(glm::mat4(1.0f), {0, 50, 0})};
    box->dirty();
    auto root = Group::create();
    root->addChild(box);
    // Off the faces' diagonals (a line through an edge hits both triangles).
    const auto hits = run(LineSegmentIntersector({-5, 0.2, 0.1}, {20, 0.2, 0.1}), *root);
    ASSERT_EQ(hits.size(), 4u);
    const double xs[] = {-1, 1, 9, 11};
    const std::uint32_t inst[] = {0, 0, 1, 1};
    for (int i = 0; i < 4; ++i) {
        expectNear(hits[std::size_t(i)].point, {xs[i], 0.2, 0.1}, kTol, "instance hit");
        EXPECT_EQ(hits[std::size_t(i)].instanceIndex, inst[i]);
    }
    expectNear(hits[2].geometricNormal, {-1, 0, 0}, kTol, "instance normal");
}

TEST(Query, SphereThroughTriangleCentres) {
    const double radius = 2.0;
    auto sphere = shapes::sphere(float(radius), 32, 16);
    auto root = Group::create();
    root->addChild(placed(sphere, glm::translate(glm::mat4(1.0f), {1, 2, 3})));
    const glm::dvec3 centre(1, 2, 3);
    const auto tris = triangleIndices(*sphere);
    std::mt19937 rng(7);
    int tested = 0;
    for (int k = 0; k < 200; ++k) {
        const auto& t = tris[std::uniform_int_distribution<std::size_t>(0, tris.size() - 1)(rng)];
        const glm::dvec3 a(sphere->positions[t[0]]), b(sphere->positions[t[1]]), c(sphere->positions[t[2]]);
        if (glm::length(glm::cross(b - a, c - a)) < 1e-3) continue; // the poles' slivers
        const glm::dvec3 target = (a + b + c) / 3.0 + centre;
        // From outside, straight at the centroid: the hit is the centroid itself.
        const glm::dvec3 from = centre + glm::normalize(target - centre) * 10.0;
        const auto hits = run(LineSegmentIntersector(from, centre), *root, Intersector::Limit::Nearest);
        ASSERT_EQ(hits.size(), 1u);
        expectNear(hits[0].point, target, kTol, "centroid");
        // The vertex normals of a sphere are radial: the interpolated normal is their mean.
        const glm::dvec3 mean = glm::normalize(glm::normalize(a) + glm::normalize(b) + glm::normalize(c));
        expectNear(hits[0].normal, mean, kTol, "interpolated normal");
        expectNear(hits[0].geometricNormal, glm::normalize(glm::cross(b - a, c - a)), kTol, "face normal");
        EXPECT_GT(glm::dot(hits[0].geometricNormal, target - centre), 0.0) << "front faces look outwards";
        ++tested;
    }
    EXPECT_GT(tested, 150);
}

TEST(Query, SphereIntersectorFindsNearestPointOfFace) {
    auto root = Group::create();
    root->addChild(shapes::box({2, 2, 2}));
    const auto hits = run(SphereIntersector({1.5, 0.2, -0.3}, 0.6), *root);
    ASSERT_FALSE(hits.empty());
    for (const Intersection& h : hits) {
        EXPECT_NEAR(h.distance, 0.5, kTol);
        expectNear(h.point, {1.0, 0.2, -0.3}, kTol, "nearest point on the +X face");
    }
    EXPECT_TRUE(run(SphereIntersector({1.5, 0.2, -0.3}, 0.49), *root).empty());
    // Corner region: the nearest point is the corner (1, 1, 1).
    const auto corner = run(SphereIntersector({2, 2, 2}, 1.8), *root, Intersector::Limit::Nearest);
    ASSERT_EQ(corner.size(), 1u);
    EXPECT_NEAR(corner[0].distance, std::sqrt(3.0), kTol);
    expectNear(corner[0].point, {1, 1, 1}, kTol, "corner");
}

// A 100 km square terrain whose heights are exactly representable: z = x/1024 + y/512 + 100 at
// integer kilometre vertices, so every triangle lies in that plane.
TEST(Query, HundredKilometreTerrainToTheMillimetre) {
    auto g = Geometry::create();
    const int n = 100;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = float(i * 1000), y = float(j * 1000);
            g->positions.push_back({x, y, x / 1024.0f + y / 512.0f + 100.0f});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const auto v = std::uint32_t(j * (n + 1) + i);
            g->indices.insert(g->indices.end(),
                              {v, v + 1, v + n + 2, v, v + n + 2, v + std::uint32_t(n) + 1});
        }
    auto root = Group::create();
    root->addChild(g);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 100000.0);
    double worst = 0.0;
    for (int k = 0; k < 2000; ++k) {
        const double x = u(rng), y = u(rng);
        const auto h = heightOfTerrain(*root, x, y);
        ASSERT_TRUE(h.has_value()) << x << ", " << y;
        worst = std::max(worst, std::abs(*h - (x / 1024.0 + y / 512.0 + 100.0)));
    }
    EXPECT_LT(worst, 1e-6) << "metres";
    EXPECT_FALSE(heightOfTerrain(*root, -1.0, 500.0).has_value()) << "off the terrain";
}

TEST(Query, NodeMasksHideSubtrees) {
    auto root = Group::create();
    auto near = placed(shapes::box({2, 2, 2}), glm::translate(glm::mat4(1.0f), {5, 0, 0}), "near");
    auto far = placed(shapes::box({2, 2, 2}), glm::translate(glm::mat4(1.0f), {10, 0, 0}), "far");
    near->nodeMask = 0x2;
    root->addChild(near);
    root->addChild(far);
    const LineSegmentIntersector line({0, 0, 0}, {20, 0, 0});
    auto all = run(line, *root, Intersector::Limit::Nearest);
    ASSERT_EQ(all.size(), 1u);
    EXPECT_NEAR(all[0].point.x, 4.0, kTol);
    auto masked =
        run(line, *root, Intersector::Limit::Nearest, {}, IntersectionVisitor::LodSelection::Finest, 0x1);
    ASSERT_EQ(masked.size(), 1u);
    EXPECT_NEAR(masked[0].point.x, 9.0, kTol);
    EXPECT_EQ(masked[0].nodePath[1], far.get());
    // A mask changed after the index was built is honoured: masks are read per query.
    far->nodeMask = 0x4;
    EXPECT_TRUE(run(line, *root, Intersector::Limit::All, {}, IntersectionVisitor::LodSelection::Finest, 0x1)
                    .empty());
}

TEST(Query, LodFinestOrShown) {
    auto lod = LOD::create();
    lod->addChild(shapes::box({4, 4, 4}), 0.0f, 100.0f);                                   // coarse
    lod->addChild(shapes::box({2, 2, 2}), 100.0f, std::numeric_limits<float>::infinity()); // fine
    auto root = Group::create();
    root->addChild(lod);
    const LineSegmentIntersector line({10, 0.1, 0.1}, {0, 0.1, 0.1});
    auto finest = run(line, *root, Intersector::Limit::Nearest);
    ASSERT_EQ(finest.size(), 1u);
    EXPECT_NEAR(finest[0].point.x, 1.0, kTol) << "the finest level";
    // A camera far away: the LOD is a few pixels tall, so the coarse level is shown.
    auto camera = Camera::create();
    camera->setViewport(0, 0, 640, 480);
    camera->setPerspective(60.0f, 1.0f, 10000.0f);
    camera->setLookAt({3000, 0, 0}, {0, 0, 0});
    auto shown = run(line, *root, Intersector::Limit::Nearest, QueryView::of(*camera),
                     IntersectionVisitor::LodSelection::Shown);
    ASSERT_EQ(shown.size(), 1u);
    EXPECT_NEAR(shown[0].point.x, 2.0, kTol) << "the level this view shows";
    camera->setLookAt({15, 0, 0}, {0, 0, 0}); // about 190 px
    shown = run(line, *root, Intersector::Limit::Nearest, QueryView::of(*camera),
                IntersectionVisitor::LodSelection::Shown);
    ASSERT_EQ(shown.size(), 1u);
    EXPECT_NEAR(shown[0].point.x, 1.0, kTol) << "close up, the fine level is shown";
    LineSegmentIntersector l2 = line;
    IntersectionVisitor iv(l2);
    iv.lodSelection = IntersectionVisitor::LodSelection::Shown;
    EXPECT_THROW(iv.visit(*root), std::invalid_argument);
}

TEST(Query, BillboardTurnsTowardsTheView) {
    // A card in the XZ plane facing -Y (OSG's default normal), 2 m wide and 2 m tall.
    auto card = Geometry::create();
    card->positions = {{-1, 0, 0}, {1, 0, 0}, {1, 0, 2}, {-1, 0, 2}};
    card->indices = {0, 1, 2, 0, 2, 3};
    auto bb = Billboard::create(Billboard::Mode::AxialRotation);
    bb->addChild(card);
    auto root = Group::create();
    root->addChild(placed(bb, glm::translate(glm::mat4(1.0f), {5, 5, 0})));
    // Along +X at the card's height: in the rest pose the line runs in the card's plane.
    const LineSegmentIntersector line({20, 5, 1}, {-20, 5, 1});
    EXPECT_TRUE(run(line, *root).empty());
    auto camera = Camera::create();
    camera->setViewport(0, 0, 640, 480);
    camera->setPerspective(60.0f, 0.1f, 1000.0f);
    camera->setLookAt({20, 5, 1}, {5, 5, 1});
    const auto hits = run(line, *root, Intersector::Limit::All, QueryView::of(*camera));
    ASSERT_EQ(hits.size(), 1u);
    expectNear(hits[0].point, {5, 5, 1}, kTol, "the turned card");
    expectNear(hits[0].geometricNormal, {1, 0, 0}, kTol, "the card faces the eye");
}

TEST(Query, SharedSubgraphOneHitPerPath) {
    auto box = shapes::box({2, 2, 2});
    auto left = placed(box, glm::translate(glm::mat4(1.0f), {-3, 0, 0}), "left");
    auto right = placed(box, glm::translate(glm::mat4(1.0f), {3, 0, 0}), "right");
    auto root = Group::create();
    root->addChild(left);
    root->addChild(right);
    const auto hits = run(LineSegmentIntersector({-10, 0.2, 0.1}, {10, 0.2, 0.1}), *root);
    ASSERT_EQ(hits.size(), 4u);
    EXPECT_EQ(hits[0].nodePath[1], left.get());
    EXPECT_EQ(hits[3].nodePath[1], right.get());
    EXPECT_EQ(hits[0].geometry, hits[3].geometry);
}

TEST(Query, PolytopeSelectsAKnownSetOfBoxes) {
    auto root = Group::create();
    auto box = shapes::box({1, 1, 1});
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i)
            root->addChild(placed(box, glm::translate(glm::mat4(1.0f), {i * 3.0f, j * 3.0f, 0.0f}),
                                  std::to_string(i) + "," + std::to_string(j)));
    auto names = [](const std::vector<Intersection>& hits) {
        std::set<std::string> s;
        for (const auto& h : hits)
            s.insert(h.nodePath[1]->name);
        return s;
    };
    // x in [2.6, 6.2] touches the boxes at x = 3 (faces at 2.5..3.5) and x = 6 (5.5..6.5);
    // y in [-1, 0.4] only the row at y = 0.
    const auto hits = run(PolytopeIntersector::box({2.6, -1, -1}, {6.2, 0.4, 1}), *root);
    EXPECT_EQ(names(hits), (std::set<std::string>{"1,0", "2,0"}));
    for (const auto& h : hits)
        EXPECT_TRUE(h.point.x >= 2.6 - kTol && h.point.x <= 6.2 + kTol && h.point.y <= 0.4 + kTol);
    // A window rectangle around the projection of box (2, 3)'s centre selects it alone.
    auto camera = Camera::create();
    camera->setViewport(0, 0, 800, 600);
    camera->setPerspective(50.0f, 1.0f, 200.0f);
    camera->setLookAt({6, 6, 40}, {6, 6, 0}, {0, 1, 0});
    const glm::dvec4 clip =
        glm::dmat4(camera->projectionMatrix) * glm::dmat4(camera->viewMatrix) * glm::dvec4(6, 9, 0, 1);
    const double px = (clip.x / clip.w + 1) * 400, py = (1 - clip.y / clip.w) * 300;
    const auto picked = run(PolytopeIntersector::windowRect(*camera, px - 3, py - 3, px + 3, py + 3), *root);
    EXPECT_EQ(names(picked), (std::set<std::string>{"2,3"}));
    EXPECT_THROW(PolytopeIntersector::windowRect(*camera, 5, 5, 5, 9), std::invalid_argument);
}

TEST(Query, LimitsNearestAndAny) {
    auto root = Group::create();
    for (int i = 0; i < 20; ++i)
        root->addChild(
            placed(shapes::box({1, 1, 1}), glm::translate(glm::mat4(1.0f), {i * 2.0f + 2.0f, 0, 0})));
    const LineSegmentIntersector line({60, 0.1, 0.2}, {0, 0.1, 0.2});
    const auto all = run(line, *root);
    ASSERT_EQ(all.size(), 40u);
    for (std::size_t i = 1; i < all.size(); ++i)
        EXPECT_LE(all[i - 1].distance, all[i].distance) << "sorted by distance";
    const auto nearest = run(line, *root, Intersector::Limit::Nearest);
    ASSERT_EQ(nearest.size(), 1u);
    EXPECT_NEAR(nearest[0].distance, all[0].distance, 1e-12);
    EXPECT_NEAR(nearest[0].point.x, 40.5, kTol);
    EXPECT_EQ(run(line, *root, Intersector::Limit::Any).size(), 1u);
    EXPECT_FALSE(lineOfSight(*root, {60, 0.1, 0.2}, {0, 0.1, 0.2}));
    EXPECT_TRUE(lineOfSight(*root, {60, 0, 5}, {0, 0, 5}));
    // Any stops early: it tests fewer geometries than All.
    LineSegmentIntersector a = line, b = line;
    a.limit = Intersector::Limit::Any;
    IntersectionVisitor ia(a), ib(b);
    ia.useSubtreeIndex = ib.useSubtreeIndex = false;
    ia.visit(*root);
    ib.visit(*root);
    EXPECT_LT(ia.geometriesTested(), ib.geometriesTested());
}

TEST(Query, ChangesAreSeen) {
    auto root = Group::create();
    auto box = shapes::box({2, 2, 2});
    auto t = placed(box, glm::mat4(1.0f));
    root->addChild(t);
    const LineSegmentIntersector line({10, 0, 0}, {-10, 0, 0});
    EXPECT_NEAR(run(line, *root, Intersector::Limit::Nearest).at(0).point.x, 1.0, kTol);
    t->setMatrix(glm::translate(glm::mat4(1.0f), {2, 0, 0}));
    EXPECT_NEAR(run(line, *root, Intersector::Limit::Nearest).at(0).point.x, 3.0, kTol)
        << "a moved transform";
    for (auto& p : box->positions)
        p.x *= 2.0f;
    box->dirty();
    EXPECT_NEAR(run(line, *root, Intersector::Limit::Nearest).at(0).point.x, 4.0, kTol) << "edited vertices";
    root->addChild(placed(shapes::box({2, 2, 2}), glm::translate(glm::mat4(1.0f), {8, 0, 0})));
    EXPECT_NEAR(run(line, *root, Intersector::Limit::Nearest).at(0).point.x, 9.0, kTol) << "an added child";
}

TEST(Query, PickThroughThePixel) {
    auto root = Group::create();
    root->addChild(shapes::box({2, 2, 2}));
    auto camera = Camera::create();
    camera->setViewport(0, 0, 640, 480);
    camera->setPerspective(45.0f, 0.5f, 100.0f);
    camera->setLookAt({10, 0, 0}, {0, 0, 0});
    const auto hit = pick(*camera, *root, 320, 240);
    ASSERT_TRUE(hit.has_value());
    expectNear(hit->hit.point, {1, 0, 0}, kTol, "the centre pixel");
    // A pixel 60 rows up from the centre: the ray leaves the eye at atan(60 / f) with
    // f = 240 / tan(22.5°) pixels, and meets the face x = 1 at z = 9 · 60 / f.
    const double f = 240.0 / std::tan(glm::radians(22.5));
    const auto up = pick(*camera, *root, 320, 180);
    ASSERT_TRUE(up.has_value());
    expectNear(up->hit.point, {1, 0, 9.0 * 60.0 / f}, kTol, "60 px above the centre");
    EXPECT_FALSE(pick(*camera, *root, 5, 5).has_value());
}

TEST(Query, BadInputIsNamed) {
    try {
        LineSegmentIntersector({1, 2, 3}, {1, 2, 3});
        FAIL() << "no throw";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("same point"), std::string::npos) << e.what();
    }
    EXPECT_THROW(RayIntersector({0, 0, 0}, {0, 0, 0}), std::invalid_argument);
    EXPECT_THROW(LineSegmentIntersector({0, 0, NAN}, {1, 0, 0}), std::invalid_argument);
    EXPECT_THROW(SphereIntersector({0, 0, 0}, -1.0), std::invalid_argument);
    EXPECT_THROW(PolytopeIntersector(std::vector<Plane>{}), std::invalid_argument);
    auto g = Geometry::create();
    g->name = "broken";
    g->positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    g->indices = {0, 1, 7};
    auto root = Group::create();
    root->addChild(g);
    LineSegmentIntersector line({0.2, 0.2, 1}, {0.2, 0.2, -1});
    IntersectionVisitor iv(line);
    try {
        iv.visit(*root);
        FAIL() << "no throw";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("broken"), std::string::npos) << e.what();
    }
}

// A vehicle driving in a large scene rebuilds its own small index and the root's, not the
// terrain's: large child groups keep indices of their own.
TEST(Query, MovingPartLeavesStaticIndicesAlone) {
    auto root = Group::create();
    auto terrain = Group::create();
    for (int i = 0; i < 40; ++i)
        terrain->addChild(placed(shapes::box({1, 1, 1}), glm::translate(glm::mat4(1.0f), {i * 2.0f, 0, 0})));
    auto vehicle = Transform::create();
    for (int i = 0; i < 20; ++i)
        vehicle->addChild(
            placed(shapes::box({0.5f, 0.5f, 0.5f}), glm::translate(glm::mat4(1.0f), {0, 0, i * 1.0f})));
    auto tree = LOD::create(); // walked at query time, inside the indexed root
    tree->addChild(placed(shapes::box({1, 1, 1}), glm::translate(glm::mat4(1.0f), {0, 10, 0})));
    root->addChild(terrain);
    root->addChild(vehicle);
    root->addChild(tree);
    prepareForQueries(*root);
    const auto terrainIndex = terrain->subtreeIndex();
    const auto rootIndex = root->subtreeIndex();
    vehicle->setMatrix(glm::translate(glm::mat4(1.0f), {11, 0, 0}));
    const LineSegmentIntersector line({11.1, 0.1, 30}, {11.1, 0.1, -30});
    const auto hits = run(line, *root, Intersector::Limit::Nearest);
    ASSERT_EQ(hits.size(), 1u);
    EXPECT_NEAR(hits[0].point.z, 19.25, kTol) << "the top of the moved vehicle's highest box";
    EXPECT_EQ(terrain->subtreeIndex(), terrainIndex) << "the terrain's index was rebuilt";
    EXPECT_NE(root->subtreeIndex(), rootIndex);
    const auto treeHits = run(LineSegmentIntersector({0.1, 10.1, 5}, {0.1, 10.1, -5}), *root);
    ASSERT_EQ(treeHits.size(), 2u);
    EXPECT_EQ(treeHits[0].nodePath[1], tree.get());
}

// Through the viewer: a headless context has no size of its own, so the target is the camera's
// viewport (pixels from its top left); a pixel outside it hits nothing.
TEST(Query, PickThroughAHeadlessViewer) {
    auto root = Group::create();
    root->addChild(shapes::box({2, 2, 2}));
    auto viewer = Viewer::createHeadless(64, 48);
    viewer->setSceneData(root);
    viewer->camera()->setPerspective(45.0f, 0.5f, 100.0f);
    viewer->camera()->setLookAt({10, 0, 0}, {0, 0, 0});
    const auto hit = pick(*viewer, 32, 24);
    ASSERT_TRUE(hit.has_value());
    expectNear(hit->hit.point, {1, 0, 0}, kTol, "the centre pixel");
    EXPECT_EQ(hit->camera, viewer->camera().get());
    EXPECT_FALSE(pick(*viewer, 32, 60).has_value()) << "below the viewport";
}

TEST(Query, MemoryCountsSharedCachesOnce) {
    auto box = shapes::box({2, 2, 2});
    auto root = Group::create();
    root->addChild(placed(box, glm::translate(glm::mat4(1.0f), {-3, 0, 0})));
    root->addChild(placed(box, glm::translate(glm::mat4(1.0f), {3, 0, 0})));
    const QueryMemory m = queryMemory(*root);
    EXPECT_EQ(m.triangles, 12u) << "one box's BVH, shared by both placements";
    EXPECT_EQ(m.bvhBytes, box->triangleBvh()->memoryBytes());
    EXPECT_GT(m.indexBytes, 0u);
}

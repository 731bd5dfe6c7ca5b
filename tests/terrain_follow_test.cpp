// The proving ground's vehicle follows the ground: each frame its update callback makes four height
// queries, under the ends of the tracks, and poses the vehicle on the plane through them. Checked
// against the terrain's analytic height function (polygon::Terrain), not the mesh the queries hit.
#include "PolygonScene.h"
#include "VehicleDrive.h"

#include <sgfx/Group.h>
#include <sgfx/Queries.h>
#include <sgfx/Viewer.h>

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>

namespace {

// PolygonScene.cpp's roads: 9 m wide along both axes and a ring at 45 % of the half-extent.
constexpr double kRoadHalfWidth = 4.5;
double roadDistance(glm::dvec2 p, double extent) {
    return std::min({std::abs(p.x), std::abs(p.y), std::abs(glm::length(p) - 0.45 * 0.5 * extent)});
}

} // namespace

TEST(TerrainFollow, FourQueriesAFramePutEveryTrackEndOnTheGround) {
    const polygon::SceneOptions so; // the demo's scene: 2.3 m terrain cells
    const polygon::PolygonScene scene = polygon::buildPolygonScene(so);
    const polygon::Terrain terrain(so.seed);
    const polygon::DriveRoute route = polygon::provingGroundRoute();
    std::uint64_t counted = 0;
    polygon::DriveOptions options;
    options.ground = [&](double x, double y) {
        ++counted;
        return sgfx::heightOfTerrain(*scene.ground, x, y);
    };
    const auto drive = polygon::driveVehicle(scene, route, options);

    auto viewer = sgfx::Viewer::createHeadless(32, 32);
    viewer->setSceneData(scene.root);
    viewer->camera()->setPerspective(30.0f, 1.0f, 100.0f);
    viewer->camera()->setLookAt({0, 0, 200}, {0, 50, 400}, {0, 0, 1}); // the sky: frames stay cheap

    // One lap in 48 frames, about 9 m apart.
    const int frames = 48;
    const double dt = route.length() / options.speed / frames;
    int offRoad = 0, onRoad = 0, flat = 0, hills = 0;
    double worstQuery = 0.0, worstPose = 0.0, steepest = 0.0;
    for (int f = 0; f < frames; ++f) {
        const std::uint64_t before = counted;
        viewer->frame(dt);
        ASSERT_EQ(counted - before, 4u) << "frame " << f;
        EXPECT_EQ(drive->queries, counted);
        EXPECT_NEAR(drive->distance, double(f) * dt * options.speed, 1e-6);
        const glm::dmat4 pose(scene.vehiclePose->matrix());
        bool clear = true;
        for (const glm::dvec3& c : drive->contacts)
            clear = clear && roadDistance(c, so.extent) > kRoadHalfWidth + 0.5;
        for (std::size_t i = 0; i < 4; ++i) {
            const glm::dvec3 hit = drive->contacts[i];
            const glm::dvec3 posed = pose * glm::dvec4(polygon::kTrackContacts[i], 0.0, 1.0);
            const double hitAbove = hit.z - double(terrain.height(float(hit.x), float(hit.y)));
            const double posedAbove = posed.z - double(terrain.height(float(posed.x), float(posed.y)));
            const double r = glm::length(glm::dvec2(hit));
            flat += r < polygon::Terrain::kFlatRadius;
            hills += r > polygon::Terrain::kBlendRadius;
            if (clear) {
                ++offRoad;
                EXPECT_NEAR(hitAbove, 0.0, 0.02) << "frame " << f << " contact " << i << " query";
                EXPECT_NEAR(posedAbove, 0.0, 0.02) << "frame " << f << " contact " << i << " pose";
                worstQuery = std::max(worstQuery, std::abs(hitAbove));
                worstPose = std::max(worstPose, std::abs(posedAbove));
            } else if (roadDistance(hit, so.extent) < kRoadHalfWidth - 0.5) {
                ++onRoad; // the road lies a few centimetres over the terrain: the track rides on it
                EXPECT_GT(hitAbove, 0.03) << "frame " << f << " contact " << i;
                EXPECT_LT(hitAbove, 0.15) << "frame " << f << " contact " << i;
                EXPECT_GT(posedAbove, -0.02) << "frame " << f << " contact " << i;
            }
        }
        steepest = std::max({steepest, std::abs(drive->slope.x), std::abs(drive->slope.y)});
    }
    EXPECT_EQ(drive->frames, std::uint64_t(frames));
    EXPECT_GT(offRoad, 150);
    EXPECT_GT(onRoad, 0);
    EXPECT_GT(flat, 0);
    EXPECT_GT(hills, 40);
    EXPECT_GT(steepest, 0.05) << "the route crosses hills: the vehicle pitches or rolls";
    std::printf("%d contacts off the roads: query within %.4f m, pose within %.4f m; %d on roads; steepest "
                "slope %.3f\n",
                offRoad, worstQuery, worstPose, onRoad, steepest);

    // Without the vehicle left out, the query under it would find its own deck.
    const glm::dvec3 centre =
        0.25 * (drive->contacts[0] + drive->contacts[1] + drive->contacts[2] + drive->contacts[3]);
    const auto withVehicle = sgfx::heightOfTerrain(*scene.root, centre.x, centre.y);
    ASSERT_TRUE(withVehicle);
    EXPECT_GT(*withVehicle, centre.z + 1.0);
}

TEST(TerrainFollow, TheRouteKeepsClearOfBuildingsTreesAndGlass) {
    // Each object's bounding sphere, seen from above: whole for buildings (tall ones reach wider
    // than their footprint) and the glass, 0.6 of it for trees, whose sphere also spans their
    // height (leaf cards 3 m from the trunk per unit of scale, sphere radius about 5.1).
    const polygon::PolygonScene scene = polygon::buildPolygonScene({});
    struct Obstacle {
        glm::dvec2 centre;
        double radius;
        const char* kind;
    };
    std::vector<Obstacle> obstacles;
    std::function<void(const sgfx::Node&, double, const char*)> collect = [&](const sgfx::Node& n, double k,
                                                                              const char* kind) {
        if (dynamic_cast<const sgfx::Transform*>(&n)) {
            const sgfx::BoundingSphere& b = n.bound();
            obstacles.push_back({glm::dvec2(b.center), k * double(b.radius), kind});
            return;
        }
        if (const auto* g = dynamic_cast<const sgfx::Group*>(&n))
            for (const auto& c : g->children())
                collect(*c, k, kind);
    };
    collect(*scene.buildings, 1.0, "building");
    collect(*scene.glass, 1.0, "glass");
    collect(*scene.trees, 0.6, "tree");
    ASSERT_GT(obstacles.size(), 1000u);
    const polygon::DriveRoute route = polygon::provingGroundRoute();
    const double halfWidth = 2.1; // the road wheels' outer faces, with a margin
    for (double s = 0.0; s < route.length(); s += 0.5) {
        const glm::dvec2 p = route.at(s).position;
        for (const Obstacle& o : obstacles)
            ASSERT_GT(glm::length(p - o.centre) - o.radius, halfWidth)
                << "the route at " << s << " m (" << p.x << ", " << p.y << ") runs into a " << o.kind
                << " at (" << o.centre.x << ", " << o.centre.y << ")";
    }
}

#pragma once
// The proving ground: a procedural test site for simulator-style rendering, built from
// sgfx::shapes and plain sgfx nodes. Everything is deterministic for a given seed.
//
// World: Z up, metres. The ground spans [-extent/2, extent/2]^2 around the origin:
//   terrain   heightfield tiles (one Geometry each, so frustum culling has something to cull)
//   roads     a ring road and two cross roads, flat strips following the terrain height
//   buildings instances of a few shared building prototypes, grouped by area
//   trees     one shared tree (trunk + alpha-masked leaf cards) under many Transforms
//   vehicle   a tracked robot vehicle near the centre (VehicleDrive.h drives it over the hills)
//   glass     two alpha-blended glass panes near the centre
//   lights    a directional sun and an ambient light
#include <sgfx/Camera.h>
#include <sgfx/Group.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sgfx {
class TransparencyBin;
}

namespace polygon {

// Small deterministic PRNG (splitmix64): the same seed gives the same scene everywhere.
class SplitMix64 {
public:
    explicit SplitMix64(std::uint64_t seed)
        : state_(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    // Uniform in [0, 1).
    float uniform() { return float(next() >> 40) * (1.0f / 16777216.0f); }
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    // Uniform integer in [0, n).
    std::size_t index(std::size_t n) { return n ? std::size_t(next() % n) : 0; }
    // Standard normal (Box-Muller).
    float normal();

private:
    std::uint64_t state_;
};

// Gentle rolling hills (|height| <= 8 m), flattened to 0 around the central test area.
class Terrain {
public:
    explicit Terrain(std::uint64_t seed);
    float height(float x, float y) const;
    glm::vec3 normal(float x, float y) const;

    static constexpr float kMaxAmplitude = 8.0f;
    static constexpr float kFlatRadius = 45.0f;   // fully flat inside
    static constexpr float kBlendRadius = 110.0f; // full hills outside

private:
    struct Wave {
        glm::vec2 dir;
        float k, amplitude, phase;
    };
    std::vector<Wave> waves_;
};

struct SceneOptions {
    float extent = 800.0f; // metres, side of the square ground
    float scale = 1.0f;    // scales the triangle count roughly linearly, in (0, 16]
    std::uint64_t seed = 1;
    // Levels of detail: distant terrain tiles at half and quarter resolution (with skirts),
    // distant buildings with flat window panes. Off: every object at full detail.
    bool lod = true;
    // The many-drawables benchmark scene: every window of every building its own drawable (a
    // shared window box under its own Transform), some 30,000 drawables.
    bool manyDrawables = false;
};

struct SceneInfo {
    int terrainTiles = 0;
    int terrainCellsPerTile = 0;
    int terrainLods = 0; // tiles with levels of detail
    int roadPieces = 0;
    int buildings = 0;
    int buildingsRequested = 0; // fewer are placed when the ground is full
    int buildingPrototypes = 0;
    int windows = 0; // over all placed buildings
    int trees = 0;
    int treesRequested = 0; // likewise for trees
};

struct PolygonScene {
    std::shared_ptr<sgfx::Group> root;
    // Named subgraphs, also reachable from root (handy for tests and tools).
    std::shared_ptr<sgfx::Group> terrain, roads, buildings, trees, vehicle, glass;
    std::shared_ptr<sgfx::Transform> vehiclePose; // "vehicle_pose", the vehicle's only child
    // Terrain and roads again under one group that is not in root: what the vehicle stands on, for
    // ground queries that skip everything else and whose cached index the moving vehicle never
    // invalidates (a second parent of both; root's subtree changes whenever the vehicle moves).
    std::shared_ptr<sgfx::Group> ground;
    std::shared_ptr<sgfx::TransparencyBin> glassBin; // == glass: its mode is the demo's choice
    // The side of the square ground (SceneOptions::extent) and the ring road's centreline
    // radius; the cross roads run along the axes.
    float extent = 0.0f, ringRadius = 0.0f;
    SceneInfo info;
};

// Builds the whole proving ground. Throws std::invalid_argument for a scale outside (0, 16]
// or a non-finite or non-positive extent.
PolygonScene buildPolygonScene(const SceneOptions& options = {});

// The tracked robot vehicle alone, at the origin, facing +X (for figures and tests).
std::shared_ptr<sgfx::Group> buildVehicle();

// The vehicle's articulated parts, sgfx::DOFTransforms reached with sgfx::findNode. At rest they
// pose the vehicle as it always stood: the turret turned 0.35 rad, the gun raised 0.04 rad.
inline constexpr const char* kTurretNode = "vehicle.turret"; // axis "yaw": RotateZ, wraps in [-pi, pi)
inline constexpr double kTurretRestYaw = 0.35;
// Axis "elevation": RotateX in a frame whose X axis is the trunnion (the vehicle's -Y), so a
// positive value raises the muzzle; clamped to [kGunMinElevation, kGunMaxElevation].
inline constexpr const char* kGunNode = "vehicle.gun";
inline constexpr double kGunRestElevation = 0.04, kGunMinElevation = -0.12, kGunMaxElevation = 0.35;
// Road wheels and sprockets: axis "spin", RotateY about the wheel's centre (positive rolls the
// vehicle forward), wrapped into [0, 2 pi).
struct VehicleWheel {
    std::string name; // "vehicle.wheel.l1" (left, first from the front) .. "vehicle.sprocket.rr"
    glm::vec3 centre; // in the vehicle frame (x forward, y left, ground at z = 0)
    float radius;     // metres
};
std::vector<VehicleWheel> vehicleWheels();

// `world` and a rain of `count` drops over an area x area square that follows the camera, emitted
// `above` metres over the eye and falling long enough to reach height `lowest`.
sgfx::NodePtr withRainFollowing(sgfx::NodePtr world, std::shared_ptr<const sgfx::Camera> camera, float area,
                                std::uint32_t count, float above, float lowest);

} // namespace polygon

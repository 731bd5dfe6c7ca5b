#pragma once
// The robot vehicle driving a closed route over the proving ground. Each frame an update callback
// asks the ground for its height under the four ends of the tracks (four queries) and sets the
// vehicle's pose from the plane that fits them best: height, pitch and roll. It also turns the
// wheels with the distance driven and slews the turret and gun towards a target (the vehicle's
// sgfx::DOFTransforms, PolygonScene.h).
#include "PolygonScene.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace polygon {

// Where the route puts the vehicle: world position (Z up ignored) and heading, radians from +X
// counter-clockwise.
struct RoutePose {
    glm::dvec2 position{0.0};
    double heading = 0.0;
};

// An ellipse around `centre` with semi-axes `radii`, its first axis turned `angle` radians from +X,
// driven counter-clockwise at constant speed from its point nearest the world's origin.
class DriveRoute {
public:
    DriveRoute(glm::dvec2 centre, glm::dvec2 radii, double angle = 0.0);
    double length() const { return arc_.back(); }
    // The pose after `s` metres (any s: the route is closed).
    RoutePose at(double s) const;

private:
    glm::dvec2 point(double t) const; // at the ellipse's parameter t
    glm::dvec2 centre_, radii_, axis_;
    double start_ = 0.0;      // the parameter t at s = 0
    std::vector<double> arc_; // arc length at t = start_ + 2 pi i / n, i = 0..n
};

// The proving ground's route, 250 m: from the flat centre (28 m from the origin) through the
// blend ring into the hills (122 m), crossing the Y cross road at both ends, clear of every
// building and tree of the default scene (seed 1 at scale 1; other seeds may put some on it).
DriveRoute provingGroundRoute();

// Ground contact points in the vehicle frame (x forward, y left, ground at z = 0): under the first
// and last road wheels of each track. Symmetric about both axes, which the plane fit relies on.
inline constexpr std::array<glm::dvec2, 4> kTrackContacts = {glm::dvec2{2.2, 1.55}, glm::dvec2{2.2, -1.55},
                                                             glm::dvec2{-2.2, 1.55}, glm::dvec2{-2.2, -1.55}};

// The ground height at world (x, y), or nullopt where there is no ground.
using GroundQuery = std::function<std::optional<double>(double x, double y)>;

struct DriveOptions {
    double speed = 6.0; // m/s
    // Default: sgfx::heightOfTerrain over scene.ground (terrain and roads only).
    GroundQuery ground;
    // The world point the turret and gun follow: by default the glass cabin's centre
    // (PolygonScene.cpp's makeGlass), on the flat centre, in view from all of the route.
    glm::dvec3 target{29.0, 22.0, 1.25};
    // The most the turret's yaw and the gun's elevation turn per second of simulation time
    // (rad/s): they follow smoothly, and lag behind a target that moves across them faster.
    double turretSlewRate = 0.6, gunSlewRate = 0.3;
};

// What the callback did last frame (read it between frames).
struct DriveState {
    double distance = 0.0;                // metres along the route
    std::array<glm::dvec3, 4> contacts{}; // world points the queries found, in kTrackContacts' order
    glm::dvec2 slope{0.0};                // of the fitted plane: dz per metre forward, and to the left
    // Where the turret's yaw and the gun's elevation head for (radians, in the hull's and the
    // turret's frames; the elevation within the gun's limits) and where they are.
    double aimYaw = 0.0, aimElevation = 0.0, turretYaw = 0.0, gunElevation = 0.0;
    std::uint64_t frames = 0, queries = 0; // since installed
};

// Installs the update callback on scene.vehicle that moves scene.vehiclePose along the route at
// options.speed, starting at the route's start on its first frame, and returns its state. Ground
// the queries miss (off the terrain) keeps the last height found there. Each wheel's "spin" is the
// distance over its radius; the turret and gun (found by name) turn towards options.target at
// most at their slew rates, from their rest pose on the first frame. Throws std::invalid_argument
// for a negative or non-finite speed or slew rate, a non-finite target, or a vehicle without
// its turret, gun or wheels.
std::shared_ptr<const DriveState> driveVehicle(const PolygonScene& scene, const DriveRoute& route,
                                               DriveOptions options = {});

} // namespace polygon

#include "VehicleDrive.h"

#include <sgfx/DOFTransform.h>
#include <sgfx/FindNode.h>
#include <sgfx/Queries.h>
#include <sgfx/Visitors.h>

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace polygon {

namespace {
constexpr int kRouteSamples = 2048; // the arc-length table: under a millimetre of error on 440 m
} // namespace

DriveRoute::DriveRoute(glm::dvec2 centre, glm::dvec2 radii, double angle)
    : centre_(centre)
    , radii_(radii)
    , axis_(std::cos(angle), std::sin(angle)) {
    if (!(radii.x > 0.0 && radii.y > 0.0)) throw std::invalid_argument("polygon: route radii must be > 0");
    const double step = glm::two_pi<double>() / kRouteSamples;
    for (int i = 1; i < kRouteSamples; ++i)
        if (glm::length(point(step * i)) < glm::length(point(start_))) start_ = step * i;
    arc_.reserve(kRouteSamples + 1);
    arc_.push_back(0.0);
    for (int i = 1; i <= kRouteSamples; ++i)
        arc_.push_back(arc_.back() + glm::length(point(start_ + step * i) - point(start_ + step * (i - 1))));
}

glm::dvec2 DriveRoute::point(double t) const {
    const glm::dvec2 e = radii_ * glm::dvec2(std::cos(t), std::sin(t));
    return centre_ + e.x * axis_ + e.y * glm::dvec2(-axis_.y, axis_.x);
}

RoutePose DriveRoute::at(double s) const {
    s = std::fmod(s, length());
    if (s < 0.0) s += length();
    const auto i = std::size_t(std::upper_bound(arc_.begin(), arc_.end(), s) - arc_.begin());
    const std::size_t k = std::clamp<std::size_t>(i, 1, arc_.size() - 1);
    const double f = (s - arc_[k - 1]) / std::max(arc_[k] - arc_[k - 1], 1e-12);
    const double t = start_ + glm::two_pi<double>() * (double(k - 1) + f) / kRouteSamples;
    // Counter-clockwise: along the parameter's derivative.
    const glm::dvec2 d = radii_ * glm::dvec2(-std::sin(t), std::cos(t));
    const glm::dvec2 tangent = d.x * axis_ + d.y * glm::dvec2(-axis_.y, axis_.x);
    return {point(t), std::atan2(tangent.y, tangent.x)};
}

DriveRoute provingGroundRoute() {
    return DriveRoute({1.9, -74.7}, {47.2, 31.6}, 1.67);
}

namespace {

// The vehicle's pose on the plane z = a + b u + c v (u forward, v left, from the route point):
// the body's x axis along the plane under the heading, its z axis the plane's normal.
glm::mat4 poseOnPlane(const RoutePose& p, double a, double b, double c) {
    const glm::dvec2 fwd(std::cos(p.heading), std::sin(p.heading)), left(-fwd.y, fwd.x);
    const glm::dvec3 x = glm::normalize(glm::dvec3(fwd, b));
    const glm::dvec3 z = glm::normalize(glm::cross(x, glm::dvec3(left, c)));
    const glm::dvec3 y = glm::cross(z, x);
    return glm::mat4(glm::dmat4(glm::dvec4(x, 0.0), glm::dvec4(y, 0.0), glm::dvec4(z, 0.0),
                                glm::dvec4(p.position, a, 1.0)));
}

// The vehicle's DOFTransforms, and each wheel's radius.
struct Articulation {
    std::vector<std::pair<std::shared_ptr<sgfx::DOFTransform>, double>> wheels;
    std::shared_ptr<sgfx::DOFTransform> turret, gun;
};

std::shared_ptr<sgfx::DOFTransform> dofNamed(sgfx::Node& vehicle, const std::string& name) {
    auto dof = sgfx::findNode<sgfx::DOFTransform>(vehicle, name);
    if (!dof)
        throw std::invalid_argument("polygon: driveVehicle: the vehicle has no DOFTransform '" + name + "'");
    return dof;
}

Articulation findArticulation(sgfx::Node& vehicle) {
    Articulation a{{}, dofNamed(vehicle, kTurretNode), dofNamed(vehicle, kGunNode)};
    for (const VehicleWheel& w : vehicleWheels())
        a.wheels.emplace_back(dofNamed(vehicle, w.name), double(w.radius));
    return a;
}

// From `current` towards `aim` by at most `step`; around the shorter way for an angle that wraps.
double slew(double current, double aim, double step, bool wraps) {
    double d = aim - current;
    if (wraps) d -= glm::two_pi<double>() * std::floor((d + glm::pi<double>()) / glm::two_pi<double>());
    return current + std::clamp(d, -step, step);
}

// Wheels from the distance (rolling without slip); turret and gun towards the target from the
// hull's pose, `dt` seconds after the last frame.
void articulate(Articulation& a, const glm::dmat4& hull, double dt, const DriveOptions& o, DriveState& s) {
    for (auto& [wheel, radius] : a.wheels)
        wheel->set("spin", s.distance / radius);
    // Yaw: the target's bearing in the hull frame from the turret ring's axis.
    const glm::dvec3 fromRing =
        glm::dvec3(glm::inverse(hull) * glm::dvec4(o.target, 1.0)) - glm::dvec3(a.turret->frame()[3]);
    s.aimYaw = std::atan2(fromRing.y, fromRing.x);
    s.turretYaw = a.turret->set("yaw", slew(a.turret->value("yaw"), s.aimYaw, o.turretSlewRate * dt, true));
    // Elevation: in the turret's frame, as it now stands, from the trunnion.
    const glm::dmat4 turret = hull * glm::dmat4(a.turret->matrix());
    const glm::dvec3 fromTrunnion =
        glm::dvec3(glm::inverse(turret) * glm::dvec4(o.target, 1.0)) - glm::dvec3(a.gun->frame()[3]);
    s.aimElevation = std::clamp(std::atan2(fromTrunnion.z, glm::length(glm::dvec2(fromTrunnion))),
                                kGunMinElevation, kGunMaxElevation);
    s.gunElevation =
        a.gun->set("elevation", slew(a.gun->value("elevation"), s.aimElevation, o.gunSlewRate * dt, false));
}

} // namespace

std::shared_ptr<const DriveState> driveVehicle(const PolygonScene& scene, const DriveRoute& route,
                                               DriveOptions options) {
    if (!scene.vehicle || !scene.vehiclePose || !scene.ground)
        throw std::invalid_argument("polygon: driveVehicle needs the scene's vehicle and ground");
    if (!(options.speed >= 0.0) || !std::isfinite(options.speed))
        throw std::invalid_argument("polygon: the vehicle's speed must be finite and >= 0");
    for (double rate : {options.turretSlewRate, options.gunSlewRate})
        if (!(rate >= 0.0) || !std::isfinite(rate))
            throw std::invalid_argument("polygon: the turret's and gun's slew rates must be finite and >= 0");
    if (!std::isfinite(options.target.x) || !std::isfinite(options.target.y) ||
        !std::isfinite(options.target.z))
        throw std::invalid_argument("polygon: the turret's target must be finite");
    auto parts = std::make_shared<Articulation>(findArticulation(*scene.vehicle));
    if (!options.ground) {
        // The BVHs are built lazily, tile by tile as the vehicle reaches them: 25 ms on the first
        // frame where sgfx::prepareForQueries would take half a second for every tile and level.
        options.ground = [ground = scene.ground](double x, double y) {
            return sgfx::heightOfTerrain(*ground, x, y);
        };
    }
    auto state = std::make_shared<DriveState>();
    std::optional<double> start, last; // simulation time of the first frame and of the last
    // Weak: the vehicle group owns this callback and the pose (no cycle either way). The parts are
    // below the vehicle and own nothing above it.
    scene.vehicle->updateCallback = [state, start, last, route, options, parts,
                                     weakPose = std::weak_ptr<sgfx::Transform>(scene.vehiclePose)](
                                        sgfx::Node&, sgfx::UpdateVisitor& uv) mutable {
        const auto pose = weakPose.lock();
        if (!pose) return;
        if (!start) start = uv.simulationTime;
        const double dt = std::max(0.0, uv.simulationTime - last.value_or(uv.simulationTime));
        last = uv.simulationTime;
        state->distance = options.speed * (uv.simulationTime - *start);
        const RoutePose p = route.at(state->distance);
        const glm::dvec2 fwd(std::cos(p.heading), std::sin(p.heading)), left(-fwd.y, fwd.x);
        // Least squares over the symmetric layout: the mean, and one slope per axis.
        double a = 0.0, b = 0.0, c = 0.0, uu = 0.0, vv = 0.0;
        for (std::size_t i = 0; i < kTrackContacts.size(); ++i) {
            const glm::dvec2 local = kTrackContacts[i];
            const glm::dvec2 xy = p.position + local.x * fwd + local.y * left;
            const std::optional<double> h = options.ground(xy.x, xy.y);
            ++state->queries;
            state->contacts[i] = glm::dvec3(xy, h.value_or(state->contacts[i].z));
            a += state->contacts[i].z;
            b += state->contacts[i].z * local.x;
            c += state->contacts[i].z * local.y;
            uu += local.x * local.x;
            vv += local.y * local.y;
        }
        a /= double(kTrackContacts.size());
        state->slope = {b / uu, c / vv};
        pose->setMatrix(poseOnPlane(p, a, state->slope.x, state->slope.y));
        articulate(*parts, glm::dmat4(pose->matrix()), dt, options, *state);
        ++state->frames;
    };
    return state;
}

} // namespace polygon

#include "VehicleDrive.h"

#include <sgfx/Queries.h>
#include <sgfx/Visitors.h>

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

} // namespace

std::shared_ptr<const DriveState> driveVehicle(const PolygonScene& scene, const DriveRoute& route,
                                               DriveOptions options) {
    if (!scene.vehicle || !scene.vehiclePose || !scene.ground)
        throw std::invalid_argument("polygon: driveVehicle needs the scene's vehicle and ground");
    if (!(options.speed >= 0.0) || !std::isfinite(options.speed))
        throw std::invalid_argument("polygon: the vehicle's speed must be finite and >= 0");
    if (!options.ground) {
        // The BVHs are built lazily, tile by tile as the vehicle reaches them: 25 ms on the first
        // frame where sgfx::prepareForQueries would take half a second for every tile and level.
        options.ground = [ground = scene.ground](double x, double y) {
            return sgfx::heightOfTerrain(*ground, x, y);
        };
    }
    auto state = std::make_shared<DriveState>();
    std::optional<double> start; // simulation time of the first frame
    // Weak: the vehicle group owns this callback and the pose (no cycle either way).
    scene.vehicle->updateCallback = [state, start, route, options,
                                     weakPose = std::weak_ptr<sgfx::Transform>(scene.vehiclePose)](
                                        sgfx::Node&, sgfx::UpdateVisitor& uv) mutable {
        const auto pose = weakPose.lock();
        if (!pose) return;
        if (!start) start = uv.simulationTime;
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
        ++state->frames;
    };
    return state;
}

} // namespace polygon

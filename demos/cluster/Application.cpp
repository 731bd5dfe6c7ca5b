#include "Application.h"

#include "CameraPath.h"
#include "PolygonScene.h"
#include "VehicleDrive.h"

#include <sgfx/DOFTransform.h>
#include <sgfx/FindNode.h>
#include <sgfx/Visitors.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace sgfxcluster {
namespace {

// Packet ids of what the application changes (DOF i of the vehicle: kVehicleDofs + i).
enum Id : std::uint32_t { kFogDensity = 1, kRainPlace = 2, kVehiclePose = 3, kVehicleDofs = 100 };
constexpr float kRainAbove = 20.0f, kRainLowest = -10.0f, kPathHighest = 42.0f;
constexpr long kPathFrames = 3600; // one lap of the camera path in a minute at 60 Hz

std::vector<float> flat(const glm::mat4& m) {
    std::vector<float> v(16);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            v[std::size_t(4 * c + r)] = m[c][r];
    return v;
}

glm::mat4 matrix(const std::vector<float>& v) {
    glm::mat4 m;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            m[c][r] = v[std::size_t(4 * c + r)];
    return m;
}

} // namespace

struct Application::Scene {
    polygon::PolygonScene polygon;
    std::shared_ptr<sgfx::FogNode> fog;
    std::shared_ptr<sgfx::Transform> rainPlace;
    std::vector<std::shared_ptr<sgfx::DOFTransform>> dofs;
    sgfx::Node::UpdateCallback drive; // the vehicle's drive, run by step() only (rank 0)
    float fogDensity = 0.0f;
};

Application::Application(const ApplicationOptions& options)
    : options_(options)
    , scene_(std::make_unique<Scene>()) {
    polygon::SceneOptions so;
    so.scale = options.sceneScale;
    Scene& s = *scene_;
    s.polygon = polygon::buildPolygonScene(so);
    s.polygon.glassBin->setMode(sgfx::TransparencyMode::Sorted);
    // Rain around the eye (a tetrahedron per drop: triangles, clipped like any surface at a
    // channel's edge, unlike point sprites). Its lifetime covers the highest eye on the path, so
    // it never changes with the eye.
    s.rainPlace = sgfx::Transform::create();
    if (options.rainDrops > 0) {
        auto rain = sgfx::ParticleSystemNode::rain({80.0f, 80.0f}, options.rainDrops);
        sgfx::particles::Emitter e = rain->settings().emitter;
        e.lifetime = (kPathHighest + kRainAbove - kRainLowest) / -e.velocity.z;
        rain->setEmitter(e);
        // Simulated on every rank every frame, seen or not: a system culled on one rank would make
        // up the missed frames in one longer step and drift from the ranks that saw it.
        rain->setCullingActive(false);
        s.rainPlace->addChild(rain);
    }
    s.fog = sgfx::FogNode::create(sgfx::FogParameters::ground());
    s.fogDensity = sgfx::FogParameters::ground().density;
    s.fog->addChild(s.polygon.root);
    s.fog->addChild(s.rainPlace);
    root_ = s.fog;
    if (options.drive) {
        polygon::driveVehicle(s.polygon, polygon::provingGroundRoute());
        // The drive runs in step() on rank 0 alone; the other ranks get its results.
        s.drive = std::move(s.polygon.vehicle->updateCallback);
        s.polygon.vehicle->updateCallback = nullptr;
    }
    for (const sgfx::NodePtr& n : sgfx::findNodesIf(
             *s.polygon.vehicle, [](sgfx::Node& node) { return dynamic_cast<sgfx::DOFTransform*>(&node); }))
        s.dofs.push_back(std::static_pointer_cast<sgfx::DOFTransform>(n));
    track();
}

Application::~Application() = default;

void Application::track() {
    Scene& s = *scene_;
    tracked_[kFogDensity] = {[&s] { return std::vector<float>{s.fogDensity}; },
                             [&s](const std::vector<float>& v) {
                                 s.fogDensity = v[0];
                                 sgfx::FogParameters p = s.fog->parameters();
                                 p.density = v[0];
                                 s.fog->setParameters(p);
                             }};
    tracked_[kRainPlace] = {[&s] { return flat(s.rainPlace->matrix()); },
                            [&s](const std::vector<float>& v) { s.rainPlace->setMatrix(matrix(v)); }};
    tracked_[kVehiclePose] = {
        [&s] { return flat(s.polygon.vehiclePose->matrix()); },
        [&s](const std::vector<float>& v) { s.polygon.vehiclePose->setMatrix(matrix(v)); }};
    for (std::size_t i = 0; i < s.dofs.size(); ++i) {
        sgfx::DOFTransform* d = s.dofs[i].get();
        tracked_[kVehicleDofs + std::uint32_t(i)] = {[d] {
                                                         std::vector<float> v;
                                                         for (const sgfx::DOFTransform::Axis& a : d->axes())
                                                             v.push_back(float(a.value));
                                                         return v;
                                                     },
                                                     [d](const std::vector<float>& v) {
                                                         for (std::size_t a = 0; a < v.size(); ++a)
                                                             d->set(d->axes()[a].name, double(v[a]));
                                                     }};
    }
}

FramePacket Application::step(std::uint64_t frame, double dt) {
    Scene& s = *scene_;
    simulationTime_ += dt;
    FramePacket p;
    p.frame = frame;
    p.dt = dt;
    p.simulationTime = simulationTime_;
    const float lap = float(std::fmod(double(options_.pathStart) + double(frame) / kPathFrames, 1.0));
    polygon::CameraPose pose = polygon::cameraPose(lap, s.polygon.extent);
    if (options_.look.size() == 6) {
        pose.eye = {options_.look[0], options_.look[1], options_.look[2]};
        pose.target = {options_.look[3], options_.look[4], options_.look[5]};
    }
    p.eyeView = glm::lookAt(pose.eye, pose.target, pose.up);
    // The application's update: the rain follows the eye, the fog breathes, the vehicle drives.
    s.rainPlace->setMatrix(glm::translate(glm::mat4(1.0f), pose.eye + glm::vec3(0.0f, 0.0f, kRainAbove)));
    s.fogDensity = sgfx::FogParameters::ground().density * float(1.0 + 0.5 * std::sin(0.5 * simulationTime_));
    if (s.drive) {
        sgfx::UpdateVisitor uv;
        uv.deltaTime = dt;
        uv.simulationTime = simulationTime_;
        uv.frameNumber = frame + 1;
        s.drive(*s.polygon.vehicle, uv);
    }
    for (const auto& [id, t] : tracked_) {
        std::vector<float> now = t.read();
        auto it = sent_.find(id);
        if (it != sent_.end() && it->second == now) continue;
        p.changes.push_back({id, now});
        sent_[id] = std::move(now);
    }
    return p;
}

void Application::apply(const FramePacket& packet) {
    for (const FramePacket::Change& c : packet.changes) {
        const auto it = tracked_.find(c.id);
        if (it == tracked_.end())
            throw std::invalid_argument("frame packet " + std::to_string(packet.frame) +
                                        ": unknown change id " + std::to_string(c.id));
        const std::size_t want = it->second.read().size();
        if (c.values.size() != want)
            throw std::invalid_argument("frame packet " + std::to_string(packet.frame) + ": change id " +
                                        std::to_string(c.id) + " has " + std::to_string(c.values.size()) +
                                        " values, expected " + std::to_string(want));
        it->second.write(c.values);
    }
}

} // namespace sgfxcluster

#pragma once
// The proving ground as sgfx-cluster shows it: the scene with ground fog, sorted glass and
// camera-following rain, the driving vehicle, and the state rank 0 sends each frame. Rank 0 (or
// the single-process reference) runs step(); every rank applies the packet's changes.
#include "FramePacket.h"

#include <sgfx/Group.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <vector>

namespace sgfx {
class DOFTransform;
class FogNode;
class Camera;
} // namespace sgfx

namespace sgfxcluster {

struct ApplicationOptions {
    float sceneScale = 0.25f; ///< polygon::SceneOptions::scale
    float pathStart = 0.1f;   ///< where on the camera path's lap frame 0 is (0..1)
    std::uint32_t rainDrops = 20000;
    bool drive = true; ///< the vehicle drives its loop
    /// A fixed eye and target (x, y, z each) instead of the camera path; empty: the path.
    std::vector<float> look;
};

class Application {
public:
    explicit Application(const ApplicationOptions& options);
    ~Application();

    /// The scene to give each rank's viewer (fog around everything) and the sky colour.
    const sgfx::NodePtr& scene() const { return root_; }
    static glm::vec4 skyColor() { return {0.42f, 0.60f, 0.85f, 1.0f}; }

    /// Rank 0: advances the application by dt to frame `frame` and returns the packet (the eye's
    /// view and everything that changed since the last packet; all of it on frame 0).
    FramePacket step(std::uint64_t frame, double dt);
    /// Every rank: makes the scene match the packet's changes (throws std::invalid_argument for
    /// an unknown id or a wrong number of values).
    void apply(const FramePacket& packet);

private:
    struct Tracked {
        std::function<std::vector<float>()> read;
        std::function<void(const std::vector<float>&)> write;
    };
    void track();

    ApplicationOptions options_;
    sgfx::NodePtr root_;
    struct Scene;
    std::unique_ptr<Scene> scene_;
    std::map<std::uint32_t, Tracked> tracked_;
    std::map<std::uint32_t, std::vector<float>> sent_;
    double simulationTime_ = 0.0;
};

} // namespace sgfxcluster

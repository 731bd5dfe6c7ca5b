#pragma once
#include "sgfx/Camera.h"
#include "sgfx/DatabasePager.h"
#include "sgfx/DisplayChannel.h"
#include "sgfx/Export.h"
#include "sgfx/GraphicsContext.h"
#include "sgfx/Renderer.h"
#include "sgfx/Visitors.h"

#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

namespace sgfx {

class ViewerChannels;

/// One context, one camera, one scene: update → cull → render → present, each frame.
/// Destroy the scene before or with the Viewer; GL objects die with their owners while the
/// Viewer's context is current.
class SGFX_API Viewer {
public:
    explicit Viewer(std::unique_ptr<GraphicsContext> context);
    /// Headless viewer with the given target size: on OSMesa (software), or through EGL on a GPU.
    /// Default is Osmesa, or Egl when the environment variable SGFX_HEADLESS is `egl` (read once
    /// per process; `osmesa` or unset: Osmesa; anything else throws std::invalid_argument naming
    /// it): scripts/gpu-check.sh runs the test suite and the demos on a GPU so. An explicit
    /// Osmesa or Egl is kept whatever the environment says.
    enum class Headless : std::uint8_t { Default, Osmesa, Egl };
    static std::unique_ptr<Viewer> createHeadless(int width, int height, Headless kind = Headless::Default);
    ~Viewer();

    void setSceneData(NodePtr scene);
    const NodePtr& sceneData() const { return scene_; }
    const std::shared_ptr<Camera>& camera() const { return camera_; }

    /// Advances the clock by dt seconds, then updates, culls and renders one frame:
    /// update(dt) then renderFrame().
    void frame(double dt = 1.0 / 60.0);
    /// The update traversal alone (clock, update callbacks): the part of a frame that changes
    /// the scene. First the database pager attaches the PagedLOD files that finished loading
    /// and unloads the slots left unused (their GL objects released here).
    void update(double dt = 1.0 / 60.0);
    /// Cull, draw and present. It only reads the scene graph, so scene queries (Queries.h) may
    /// run on other threads meanwhile, once prepareForQueries(scene) has run after update().
    void renderFrame();
    /// The last frame: the view, or with channels their composite (docs/multi-view.md).
    Image capture();
    void writeScreenshot(const std::filesystem::path& png) { writePng(png, capture()); }

    /// Several views of the camera's eye in one frame (a wall of screens, the projectors of a
    /// cylinder or dome; docs/multi-view.md): each channel renders the scene through a camera of
    /// its own (channelCamera) with its view offset and off-axis frustum, into its rectangle of
    /// one composite image, which capture() returns and a window shows. The camera stays the eye:
    /// move it as before. Checked with validateChannels (std::invalid_argument naming the channel
    /// and field; the previous channels kept); an empty vector returns to the single view.
    void setChannels(std::vector<DisplayChannel> channels);
    /// The channels set (empty: the single view).
    const std::vector<DisplayChannel>& channels() const;
    /// Channel i's camera (throws std::out_of_range): its view, projection, viewport and
    /// settings are copied from the eye each frame; what the renderer keeps per camera (TAA and
    /// SMAA T2x history, per-triangle orders, anti-aliasing targets) is kept per channel.
    Camera& channelCamera(std::size_t i);
    /// Channel i's image of the last frame (its rectangle of the composite).
    Image captureChannel(std::size_t i);
    /// Channel i's statistics of the last frame (throws std::out_of_range).
    const FrameStats& channelStats(std::size_t i) const;

    Renderer& renderer() { return *renderer_; }
    GraphicsContext& context() { return *context_; }
    /// The last frame's statistics; with channels, the sums over the channels (counts and
    /// times added, pass times listed channel after channel).
    const FrameStats& stats() const;
    double simulationTime() const { return update_.simulationTime; }

    /// The pager PagedLODs load through (one per viewer, its thread started at the first
    /// request). Several viewers may share one; null turns paging off (slots not loaded show
    /// their coarser level).
    const std::shared_ptr<DatabasePager>& databasePager() const { return pager_; }
    void setDatabasePager(std::shared_ptr<DatabasePager> pager);

    /// Windows only: called each frame after the scene is copied to the back buffer and before
    /// the swap, with the window's framebuffer bound, its viewport set and sRGB writes off (OSG's
    /// final draw callback), to draw a user interface over the view. Captures do not include it.
    std::function<void(Viewer&)> finalDrawCallback;

private:
    std::unique_ptr<GraphicsContext> context_;
    std::shared_ptr<Camera> camera_;
    NodePtr scene_;
    UpdateVisitor update_;
    std::unique_ptr<Renderer> renderer_;
    std::shared_ptr<DatabasePager> pager_;
    std::unique_ptr<ViewerChannels> channels_; // null: the single view
};

} // namespace sgfx

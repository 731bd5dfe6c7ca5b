#pragma once
#include "sgfx/Camera.h"
#include "sgfx/DatabasePager.h"
#include "sgfx/Export.h"
#include "sgfx/GraphicsContext.h"
#include "sgfx/Renderer.h"
#include "sgfx/Visitors.h"

#include <filesystem>
#include <functional>
#include <memory>

namespace sgfx {

/// One context, one camera, one scene: update → cull → render → present, each frame.
/// Destroy the scene before or with the Viewer; GL objects die with their owners while the
/// Viewer's context is current.
class SGFX_API Viewer {
public:
    explicit Viewer(std::unique_ptr<GraphicsContext> context);
    /// Headless viewer with the given target size: on OSMesa (software), or through EGL on a GPU.
    enum class Headless : std::uint8_t { Osmesa, Egl };
    static std::unique_ptr<Viewer> createHeadless(int width, int height, Headless kind = Headless::Osmesa);
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
    Image capture() { return renderer_->readPixels(); }
    void writeScreenshot(const std::filesystem::path& png) { writePng(png, capture()); }

    Renderer& renderer() { return *renderer_; }
    GraphicsContext& context() { return *context_; }
    const FrameStats& stats() const { return renderer_->stats(); }
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
};

} // namespace sgfx

#pragma once
// Renderer::Impl, the renderer's private state, shared by the files of scenegraph/src/render/:
//   Renderer.cpp        construction, small accessors
//   StateCache.*        the redundant-state filter (program, blend, cull, depth, texture units and
//                       their sampler objects)
//   GpuUpload.*         geometry, texture and render-target uploads, GL enum mappings
//   DrawList.cpp        drawing a list of render items (Renderer::drawItems), full-screen draws
//   ViewRenderer.cpp    a frame: cull, sub-cameras, frame block, passes, main pass, resolve
//   Diagnostics.*       GL error sites, debug output, pass timers, warnings
//   Readback.cpp        reading the scene target back, presenting it to a window
#include "AntiAliasing.h"
#include "render/Diagnostics.h"
#include "render/LightList.h"
#include "render/Occlusion.h"
#include "render/ResourcePool.h"
#include "render/StateCache.h"
#include "sgfx/Renderer.h"
#include "sgfx/TriangleSort.h"
#include "sgfx/gl/Objects.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace sgfx {

namespace render {
// std140 mirror of shaders/frame_block.glsl.
struct FrameBlock {
    glm::mat4 view, projection, viewProjection, invViewProjection;
    glm::vec4 eye, viewport, ambientLight, time;
    glm::ivec4 lightCount;
    glm::vec4 lightVector[8];
    glm::vec4 lightColor[8];
};
constexpr int kMaxLights = 8;
} // namespace render

struct Renderer::Impl {
    explicit Impl(std::size_t& stateChanges)
        : cache(stateChanges) {}

    gl::RenderTarget scene;
    struct CameraTarget {
        std::weak_ptr<Node> owner;
        gl::RenderTarget target;
    };
    std::unordered_map<const Camera*, CameraTarget> cameraTargets;
    // Per-triangle back-to-front orders, one per (mesh, view); dropped when the mesh or the view's
    // camera dies (a display channel removed), the mesh is edited, or was not drawn for a while.
    struct SortedMesh {
        std::weak_ptr<const Node> owner;
        std::weak_ptr<const Node> view; // tracked when the camera is shared-owned (viewTracked)
        bool viewTracked = false;
        std::uint64_t revision = 0;
        std::uint64_t lastUse = 0;
        std::unique_ptr<TriangleDepthSort> sort;
        gl::BufferObject indices;
    };
    std::map<std::pair<const Geometry*, const Camera*>, SortedMesh> sortedMeshes;
    const Camera* camera = nullptr;                           // the view being drawn
    std::unordered_map<const Camera*, aa::ViewState> aaViews; // per camera, dropped with it
    std::vector<std::string> warnings;
    // RendererOptions::occlusionCulling: per camera what it saw last frame, dropped with it; the
    // items culled this frame (Renderer::occlusionCulledItems).
    std::unordered_map<const Camera*, render::OcclusionState> occlusionViews;
    std::vector<RenderItem> occlusionCulled;
    // SGFX_GL_ERRORS at construction: the policy while RendererOptions::glErrors is unset.
    RendererOptions::GlErrorPolicy glErrorsDefault = RendererOptions::GlErrorPolicy::Collect;
    std::uint64_t frames = 0;
    render::PassTimers timers;          // RendererOptions::timePasses: queries of this frame
    gl::RenderTarget* current = &scene; // target of the view being drawn
    gl::BufferObject frameUbo;
    render::FrameBlock frameBlock{}; // what frameUbo holds for the view being drawn
    // Frame blocks of passes that draw from another view (PassCommands::setView), one per call
    // in a frame; the view's own block is bound again after such a pass.
    std::vector<gl::BufferObject> passViewBlocks;
    std::size_t passViewBlocksUsed = 0;
    bool passViewBound = false;
    // PassCommands::blendedCasters: blended items in depth passes cut out below this opacity.
    std::optional<float> blendedCutoff;
    // Model matrices of automatic instance batches (Renderer::DrawList), a shader storage
    // buffer at kBatchBinding.
    gl::BufferObject batchModels;
    // The view's lights (kLightsBinding) and light list tiles (kLightTilesBinding), rewritten
    // by every view that needs them; the list is the CPU side, kept for its capacity.
    gl::BufferObject lightBuffer, lightTiles;
    render::LightList lightList;
    std::vector<glm::mat4> batchScratch;
    std::uint64_t submittedTriangles = 0; // FrameStats::triangles at the last glFlush
    std::uint64_t submitEvery = 0;        // this frame's interval (RendererOptions::submitsPerFrame)
    // Triangles of each camera's last frame (display channels render once per channel a frame).
    // Cameras not owned by a shared_ptr share one count: nothing says when they are gone.
    struct LastFrame {
        std::weak_ptr<const Node> owner;
        std::uint64_t triangles = 0;
    };
    std::unordered_map<const Camera*, LastFrame> lastFrames;
    LastFrame untrackedLastFrame;
    // This frame's submission interval for `view`; its entry, to record the frame's triangles.
    LastFrame& startSubmissions(const Camera& view, const RendererOptions& options);
    gl::VertexArrayObject emptyVao;       // full-screen passes take their vertices from gl_VertexID
    render::DebugLog log;
    gl::StateCache cache;              // every real change is counted as a state change
    render::ResourcePool pool;         // frame-graph textures and their framebuffers
    const FrameGraph* graph = nullptr; // the graph being executed (material samplers read it)
    // This frame's graphs, one per view, with the range of pass timers each started: the graph
    // picture is drawn once the times are known (Renderer::lastFrameGraphDot).
    struct ViewGraph {
        std::string name;
        FrameGraph graph;
        std::size_t firstTimer = 0, timers = 0;
    };
    std::vector<ViewGraph> graphs;
    // The depth-comparison sampler object of SnippetSampler::comparison and
    // PassCommands::bindComparison, made at its first use (GL current); 0 until then.
    gl::SamplerObject comparison;
    unsigned comparisonSampler() {
        if (!comparison) comparison = gl::createComparisonSampler();
        return comparison.get();
    }
    unsigned nextResourceUnit = 0;  // the next unit bindFrameResource gives in the item being drawn
    unsigned firstResourceUnit = 0; // after the snippet samplers of the current effect set
};

} // namespace sgfx

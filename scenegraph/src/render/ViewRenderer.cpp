// A frame: Renderer::render, and each view it draws (the camera's, and first the render-to-texture
// cameras it sees) in steps: cull, sub-cameras, projection and anti-aliasing, the frame block, the
// passes and the main pass, the resolve and post passes. The frame plan's passes run here.
#include "render/GpuUpload.h"
#include "render/OcclusionDraw.h"
#include "render/RendererImpl.h"
#include "sgfx/Camera.h"
#include "sgfx/CullVisitor.h"
#include "sgfx/Drawable.h"
#include "sgfx/Effect.h"
#include "sgfx/FrameSetup.h"
#include "sgfx/GraphicsContext.h"
#include "sgfx/PassCommands.h"

#include <glm/gtc/matrix_transform.hpp>
#include <sgfx_glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace sgfx {

/// One view being drawn, step by step (Renderer::renderView runs the steps in order).
class Renderer::View {
public:
    View(Renderer& r, Camera& camera, gl::RenderTarget& target, RenderQueue& queue, FramePlan& plan)
        : r_(r)
        , s_(*r.impl_)
        , camera_(camera)
        , target_(target)
        , queue_(queue)
        , plan_(plan) {}

    void cull();
    void renderSubCameras(int depth);
    void beginProjection();
    void uploadFrameBlock();
    void uploadLightList(render::FrameBlock& fb);
    void buildGraph(int depth);
    void compileNodes();
    void executeGraph();

private:
    void declare(const FrameSetup& setup, PassPhase phase);
    void declareSceneDepth(const FrameSetup::DepthNeeds& needs);
    void drawSceneDepth(PassCommands& c, const FrameSetup::DepthNeeds& needs);
    void declareMain(bool opaque);
    void declareTransmission();
    void declareResolve();
    void declarePostAa();
    void legacyState(bool invalidate, const gl::RenderTarget& target);
    void drawOpaque();
    void drawOpaqueTwoPhase();
    void drawTransmissive();
    void drawTransparent();
    void bindDrawTarget();
    void clearTarget();
    void resolve();

    using clock = std::chrono::steady_clock;
    Renderer& r_;
    Impl& s_;
    Camera& camera_;
    gl::RenderTarget& target_;
    RenderQueue& queue_;
    FramePlan& plan_;
    const clock::time_point t0_ = clock::now();
    float computedNear_ = 0.0f, computedFar_ = 0.0f; // the cull's depth range of what it kept
    glm::mat4 unjittered_{1.0f};                     // the projection before TAA's jitter
    aa::ViewState* aa_ = nullptr;
    gl::RenderTarget* draw_ = nullptr; // where the view is drawn (target_, or a larger/multisample one)
    FrameGraph graph_;
    glm::vec4 clearColour_{0.0f};        // the camera's, or what an effect set (FrameSetup::setClearColour)
    std::vector<std::string> mainReads_; // resources drawables bind in the main pass
    std::vector<std::pair<std::string, TextureDesc>> mainTargets_; // and those they draw into
    gl::QueryObject fragments_; // RendererOptions::countFragments, over the main pass
};

Renderer::Impl::LastFrame& Renderer::Impl::startSubmissions(const Camera& view,
                                                            const RendererOptions& options) {
    std::erase_if(lastFrames, [](const auto& e) { return e.second.owner.expired(); });
    const std::weak_ptr<const Node> self = view.weak_from_this();
    LastFrame& last = self.expired() ? untrackedLastFrame : lastFrames[&view];
    if (!self.expired() && last.owner.expired()) last.owner = self; // first seen
    submittedTriangles = 0;
    submitEvery = options.submitTriangles;
    if (options.submitTriangles && options.submitsPerFrame)
        submitEvery = std::max<std::uint64_t>(submitEvery, last.triangles / options.submitsPerFrame);
    return last;
}

void Renderer::render(Camera& camera, double time, std::uint64_t frameNumber) {
    using clock = std::chrono::steady_clock;
    context_.assertOwnerThread();
    const auto t0 = clock::now();
    stats_ = {};
    Impl::LastFrame& last = impl_->startSubmissions(camera, options_);
    frame_.time = time;
    frame_.frameNumber = frameNumber;
    // Forget the targets of render-to-texture cameras that no longer exist.
    std::erase_if(impl_->cameraTargets, [](const auto& e) { return e.second.owner.expired(); });
    std::erase_if(impl_->aaViews, [](const auto& e) { return e.second.owner.expired(); });
    std::erase_if(impl_->occlusionViews, [](const auto& e) { return e.second.owner.expired(); });
    impl_->occlusionCulled.clear();
    ++impl_->frames;
    std::erase_if(impl_->sortedMeshes, [&](const auto& e) {
        return e.second.owner.expired() || (e.second.viewTracked && e.second.view.expired()) ||
               impl_->frames - e.second.lastUse > 600;
    });
    impl_->timers.clear();
    impl_->graphs.clear();
    impl_->passViewBlocksUsed = 0;
    renderView(camera, impl_->scene, queue_, plan_, 0);
    last.triangles = stats_.triangles;
    impl_->log.stage = "outside a frame";
    impl_->timers.collect(stats_.passTimes);
    if (options_.glErrors.value_or(impl_->glErrorsDefault) == RendererOptions::GlErrorPolicy::Throw) {
        const std::vector<std::string> errors = takeGlErrors();
        if (!errors.empty()) {
            std::string what = "sgfx: GL errors in frame " + std::to_string(frameNumber) + ":";
            for (const std::string& e : errors)
                what += "\n  " + e;
            throw std::runtime_error(what);
        }
    }
    if (camera.renderTarget) render::copyToTexture(impl_->scene, *camera.renderTarget);
    stats_.drawMs = std::chrono::duration<double, std::milli>(clock::now() - t0).count() - stats_.cullMs;
}

// The frame's graphs as one DOT digraph, a cluster per view, with the GPU times of its passes.
std::string Renderer::lastFrameGraphDot() const {
    std::string dot = "digraph frame {\n  rankdir=LR;\n  node [fontname=\"Helvetica\", fontsize=10];\n";
    for (const Impl::ViewGraph& g : impl_->graphs) {
        std::map<std::string, double> ms;
        for (std::size_t i = g.firstTimer; i < g.firstTimer + g.timers && i < stats_.passTimes.size(); ++i)
            ms[stats_.passTimes[i].name] += stats_.passTimes[i].gpuMs;
        dot += g.graph.dotCluster(g.name, ms);
    }
    return dot + "}\n";
}

const std::vector<RenderItem>& Renderer::occlusionCulledItems() const {
    return impl_->occlusionCulled;
}

void Renderer::renderView(Camera& camera, gl::RenderTarget& target, RenderQueue& queue, FramePlan& plan,
                          int depth) {
    View view(*this, camera, target, queue, plan);
    view.cull();
    view.renderSubCameras(depth);
    view.beginProjection();
    view.uploadFrameBlock();
    view.buildGraph(depth);
    view.compileNodes();
    view.executeGraph();
}

void Renderer::View::cull() {
    const Viewport vp = camera_.viewport;
    static const GLenum formats[] = {GL_SRGB8_ALPHA8, GL_RGBA16F, GL_RGBA32F, GL_RGBA8};
    const RendererOptions& options = r_.options_;
    const auto colorTarget = std::size_t(options.colorTarget);
    if (colorTarget >= std::size(formats))
        throw std::invalid_argument("sgfx: RendererOptions::colorTarget has an invalid value " +
                                    std::to_string(colorTarget));
    if (std::uint8_t(options.lighting) > std::uint8_t(RendererOptions::Lighting::PerVertex))
        throw std::invalid_argument("sgfx: RendererOptions::lighting has an invalid value " +
                                    std::to_string(int(options.lighting)));
    if (std::uint8_t(options.occlusionCulling) >
        std::uint8_t(RendererOptions::OcclusionCulling::DebugUnsafeMinDepth))
        throw std::invalid_argument("sgfx: RendererOptions::occlusionCulling has an invalid value " +
                                    std::to_string(int(options.occlusionCulling)));
    if (!(options.maxUnrolledLights >= 0 && options.maxUnrolledLights <= render::kMaxLights))
        throw std::invalid_argument("sgfx: RendererOptions::maxUnrolledLights = " +
                                    std::to_string(options.maxUnrolledLights) + " is outside 0..8");
    target_.resize(vp.width, vp.height, formats[colorTarget]);

    queue_.clear();
    plan_.clear();
    CullVisitor visitor(camera_, queue_, &plan_);
    visitor.setDatabasePager(r_.pager_);
    visitor.run(camera_);
    queue_.sort();
    computedNear_ = visitor.computedNear;
    computedFar_ = visitor.computedFar;
    r_.stats_.culledNodes += visitor.culledNodes;
    r_.stats_.items += queue_.size();
    r_.stats_.cullMs += std::chrono::duration<double, std::milli>(clock::now() - t0_).count();
}

// Nested render-to-texture cameras first, each with its own queue and target.
void Renderer::View::renderSubCameras(int depth) {
    constexpr int kMaxCameraDepth = 4; // a camera seen inside its own subgraph stops here
    if (depth >= kMaxCameraDepth) return;
    for (Camera* sub : queue_.subCameras) {
        auto& entry = s_.cameraTargets[sub];
        entry.owner = sub->weak_from_this();
        RenderQueue subQueue;
        FramePlan subPlan;
        r_.renderView(*sub, entry.target, subQueue, subPlan, depth + 1);
        render::copyToTexture(entry.target, *sub->renderTarget);
    }
}

// The projection (its depth range fitted to what was culled, when the camera asks), and
// anti-aliasing: where the view is drawn (a multisample or larger target, else the view's own), and
// TAA's sub-pixel jitter.
void Renderer::View::beginProjection() {
    const Viewport vp = camera_.viewport;
    glm::mat4 projection = camera_.projectionMatrix;
    if (camera_.computeNearFar && camera_.perspective() && computedFar_ > 0.0f) {
        const float zFar = computedFar_ * 1.01f;
        const float zNear = std::max(computedNear_ * 0.99f, zFar * camera_.nearFarRatio);
        projection = glm::perspective(glm::radians(camera_.fovy()), vp.aspect(), zNear, zFar);
    }
    aa::ViewState& aa = s_.aaViews[&camera_];
    if (aa.owner.expired()) aa = {}, aa.owner = camera_.weak_from_this();
    aa::begin(aa, camera_, projection * camera_.viewMatrix, target_.width, target_.height,
              r_.frame_.frameNumber, s_.warnings);
    aa_ = &aa;
    draw_ = &aa::drawTarget(aa, target_);
    unjittered_ = projection;
    projection = aa.jitter * projection;
    FrameData& frame = r_.frame_;
    frame.view = camera_.viewMatrix;
    frame.projection = projection;
    frame.viewProjection = projection * camera_.viewMatrix;
    frame.inverseViewProjection = glm::inverse(frame.viewProjection);
    frame.eye = glm::vec3(glm::inverse(camera_.viewMatrix)[3]);
    frame.width = draw_->width;
    frame.height = draw_->height;
}

// Per-view uniforms, shared by every program through binding 0; the variant bits that hold for the
// whole view.
void Renderer::View::uploadFrameBlock() {
    const FrameData& frame = r_.frame_;
    render::FrameBlock fb{};
    fb.view = frame.view;
    fb.projection = frame.projection;
    fb.viewProjection = frame.viewProjection;
    fb.invViewProjection = frame.inverseViewProjection;
    fb.eye = glm::vec4(frame.eye, 1.0f);
    fb.viewport = glm::vec4(0.0f, 0.0f, float(draw_->width), float(draw_->height));
    fb.ambientLight = glm::vec4(queue_.ambientLight, 0.0f);
    fb.time = glm::vec4(float(frame.time), 0, 0, 0);
    FeatureMask& features = r_.viewFeatures_;
    features = r_.options_.lighting == RendererOptions::Lighting::PerVertex
                   ? FeatureMask(FeatureVertexLighting)
                   : 0u;
    if (r_.options_.debugConstantShading) features |= FeatureDebugConstant;
    for (const LightInfo& l : queue_.lights)
        if (l.vector.w != 0.0f) features |= FeaturePointLights;
    if (int(queue_.lights.size()) > r_.options_.maxUnrolledLights) {
        uploadLightList(fb);
        features |= FeatureLightList;
    } else {
        const int nLights = int(queue_.lights.size());
        fb.lightCount = glm::ivec4(nLights, 0, 0, 0);
        bool attenuated = false;
        for (int i = 0; i < nLights; ++i) {
            const LightInfo& l = queue_.lights[std::size_t(i)];
            fb.lightVector[i] = l.vector;
            fb.lightColor[i] = glm::vec4(l.color, 0.0f);
            attenuated = attenuated || l.attenuated();
        }
        features |= FeatureMask(nLights) << FeatureLightCountShift;
        // Range, cone and falloff come from the lights' buffer.
        if (attenuated) {
            std::vector<render::GpuLight>& packed = s_.lightList.lights;
            packed.clear();
            for (std::size_t i = 0; i < queue_.lights.size(); ++i)
                packed.push_back(render::packLight(queue_.lights[i], int(i)));
            glNamedBufferData(s_.lightBuffer.get(), GLsizeiptr(packed.size() * sizeof(render::GpuLight)),
                              packed.data(), GL_STREAM_DRAW);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kLightsBinding, s_.lightBuffer.get());
            features |= FeatureLightAttenuation;
        }
    }
    glNamedBufferSubData(s_.frameUbo.get(), 0, sizeof fb, &fb);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, s_.frameUbo.get());
    s_.frameBlock = fb;
    s_.cache.invalidate();
    r_.current_ = &queue_;
    s_.current = draw_;
    s_.camera = &camera_;
}

// More lights than the unrolled loop takes: all of them in one buffer, the ranged ones sorted
// into screen tiles of the draw target (lights.glsl reads them by gl_FragCoord).
void Renderer::View::uploadLightList(render::FrameBlock& fb) {
    render::LightList& list = s_.lightList;
    list.build(queue_.lights, r_.frame_.view, r_.frame_.projection, draw_->width, draw_->height);
    // The frame block keeps the first 8 lights as without the list: foreign shaders read them.
    const int inBlock = std::min(int(queue_.lights.size()), render::kMaxLights);
    for (int i = 0; i < inBlock; ++i) {
        fb.lightVector[i] = queue_.lights[std::size_t(i)].vector;
        fb.lightColor[i] = glm::vec4(queue_.lights[std::size_t(i)].color, 0.0f);
    }
    fb.lightCount = glm::ivec4(inBlock, list.global, list.tilesX, render::LightList::kTileSize);
    // A buffer is never empty: GL would refuse to bind a zero-sized one.
    if (list.lights.empty()) list.lights.push_back(render::GpuLight{});
    glNamedBufferData(s_.lightBuffer.get(), GLsizeiptr(list.lights.size() * sizeof(render::GpuLight)),
                      list.lights.data(), GL_STREAM_DRAW);
    glNamedBufferData(s_.lightTiles.get(), GLsizeiptr(list.tiles.size() * sizeof(std::uint32_t)),
                      list.tiles.data(), GL_STREAM_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kLightsBinding, s_.lightBuffer.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kLightTilesBinding, s_.lightTiles.get());
}

// ---- the view's frame graph

namespace {

// The draw (or view) target's textures as graph resources.
void importTarget(FrameGraph& g, const gl::RenderTarget& t, std::string_view colour, std::string_view depth) {
    const SizeRule size = SizeRule::fixedSize(t.width, t.height);
    g.blackboard.put(std::string(colour),
                     g.import(std::string(colour), {t.colorFormat, size, t.samples}, t.color.get()));
    g.blackboard.put(std::string(depth),
                     g.import(std::string(depth), {format::Depth32F, size, t.samples}, t.depth.get()));
}

// An assigned perspective projection (glm::frustum: a display channel's off-axis frustum) as the
// nominal planes and the smallest symmetric perspective that contains it, so what splits the view
// by distance (shadow cascades) covers it; orthographic projections are left as they are.
void nominalOffAxis(const glm::mat4& p, ViewInfo& info) {
    if (p[2][3] != -1.0f || p[3][3] != 0.0f || p[0][0] <= 0.0f || p[1][1] <= 0.0f) return;
    // glm::frustum: P22 = −(f + n)/(f − n), P32 = −2fn/(f − n); P00 = 2n/(r − l), P20 = (r + l)/(r − l).
    const double n = double(p[3][2]) / (double(p[2][2]) - 1.0), f = double(p[3][2]) / (double(p[2][2]) + 1.0);
    if (!(n > 0.0 && f > n && std::isfinite(f))) return;
    const double halfW = (1.0 + std::abs(double(p[2][0]))) / double(p[0][0]); // max(|l|, |r|) / n
    const double halfH = (1.0 + std::abs(double(p[2][1]))) / double(p[1][1]);
    info.perspective = true;
    info.nominalNear = float(n);
    info.nominalFar = float(f);
    info.fovy = float(glm::degrees(2.0 * std::atan(halfH)));
    info.aspect = float(halfW / halfH);
}

} // namespace

// What the visible effects declare, interleaved with the renderer's own passes in frame order.
void Renderer::View::buildGraph(int depth) {
    ViewInfo info{{draw_->width, draw_->height},
                  {target_.width, target_.height},
                  draw_->samples,
                  r_.frame_.frameNumber,
                  depth};
    info.view = camera_.viewMatrix;
    info.projection = unjittered_;
    info.nominalNear = camera_.zNear();
    info.nominalFar = camera_.zFar();
    info.fovy = camera_.fovy();
    info.aspect = camera_.viewport.aspect();
    info.perspective = camera_.perspective();
    info.clearsColour = camera_.clearColorEnabled;
    info.clearColour = camera_.clearColor;
    info.clearsDepth = camera_.clearDepthEnabled;
    if (!info.perspective) nominalOffAxis(camera_.projectionMatrix, info);
    FrameSetup setup(info, queue_, &plan_);
    for (const EffectNode* e : plan_.effects)
        e->setupFrame(setup);
    for (const Drawable* d : plan_.drawables)
        d->setupFrame(setup);
    importTarget(graph_, *draw_, resources::DrawColour, resources::DrawDepth);
    if (draw_ != &target_) {
        importTarget(graph_, target_, resources::ViewColour, resources::ViewDepth);
    } else {
        graph_.blackboard.put(std::string(resources::ViewColour),
                              graph_.blackboard.get(resources::DrawColour));
        graph_.blackboard.put(std::string(resources::ViewDepth), graph_.blackboard.get(resources::DrawDepth));
    }
    clearColour_ = setup.clearColourOverride().value_or(camera_.clearColor);
    mainReads_ = setup.mainPassReads();
    mainTargets_ = setup.mainPassTargets();
    declare(setup, PassPhase::Compute);
    if (setup.depthNeeds().beforeMain) declareSceneDepth(setup.depthNeeds());
    declare(setup, PassPhase::BeforeMain);
    declareMain(true);
    if (setup.depthNeeds().any && !setup.depthNeeds().beforeMain) declareSceneDepth(setup.depthNeeds());
    declare(setup, PassPhase::AfterOpaque);
    declareTransmission();
    declare(setup, PassPhase::Transparent);
    declareMain(false);
    if (draw_ != &target_) declareResolve();
    declare(setup, PassPhase::AfterResolve);
    declarePostAa();
    graph_.present(graph_.blackboard.get(resources::ViewColour));
    graph_.compile(info.drawSize, info.viewSize);
}

// The effects' passes of one phase, in the order they were declared.
void Renderer::View::declare(const FrameSetup& setup, PassPhase phase) {
    for (const FrameSetup::DeclaredPass& p : setup.passes()) {
        if (p.phase != phase) continue;
        graph_.addPass(
            p.name,
            [&](FrameGraph::Builder& b) {
                PassBuilder pb(b, graph_.blackboard, &queue_);
                if (p.setup) p.setup(pb);
            },
            p.execute, std::string(phaseName(phase)));
    }
}

// One depth of the opaque scene for every effect of the view: a pre-pass before the main pass, or
// a copy of the main pass's depth after its opaque items.
void Renderer::View::declareSceneDepth(const FrameSetup::DepthNeeds& needs) {
    const TextureDesc desc{.format = format::Depth32F};
    if (needs.beforeMain) {
        graph_.addPass(
            "scene depth",
            [&](FrameGraph::Builder& b) {
                PassBuilder pb(b, graph_.blackboard, &queue_);
                pb.publish(std::string(resources::SceneDepth),
                           pb.depth(pb.create("scene.depth", desc), false));
                // The G-buffer outputs at their locations in gbuffer_flat.frag and the material's
                // G-buffer variant: 0 normal, 1 linear depth, 2 position.
                const std::pair<bool, std::string_view> outputs[] = {
                    {needs.normals, resources::SceneNormals},
                    {needs.linearDepth, resources::SceneLinearDepth},
                    {needs.positions, resources::ScenePositions}};
                const unsigned formats[] = {format::Rgba16F, format::R32F, format::Rgba16F};
                const bool gbuffer = needs.normals || needs.linearDepth || needs.positions;
                for (int i = 0; gbuffer && i < 3; ++i)
                    if (outputs[i].first || i < 2) { // the G-buffer always has normal and linear depth
                        const std::string name(outputs[i].second);
                        pb.publish(name, pb.colour(pb.create(name, {.format = formats[i]}), i, false));
                    }
            },
            [this, needs](PassCommands& c) { drawSceneDepth(c, needs); }, "before main");
        return;
    }
    graph_.addPass(
        "scene depth copy",
        [&](FrameGraph::Builder& b) {
            PassBuilder pb(b, graph_.blackboard, &queue_);
            pb.sample(resources::DrawDepth);
            pb.publish(std::string(resources::SceneDepth), pb.depth(pb.create("scene.depth", desc), false));
        },
        [this](PassCommands& c) {
            c.copyDepth(graph_.blackboard.get(resources::DrawDepth),
                        graph_.blackboard.get(resources::SceneDepth));
        },
        "after opaque");
}

// The opaque items' depth, and their G-buffer outputs when an effect asked for them (cleared to 0:
// a linear depth of 0 means nothing was drawn there).
void Renderer::View::drawSceneDepth(PassCommands& c, const FrameSetup::DepthNeeds& needs) {
    const Blackboard& board = graph_.blackboard;
    const bool gbuffer = needs.normals || needs.linearDepth || needs.positions;
    const auto at = [&](std::string_view name) { return board.has(name) ? board.get(name) : ResourceId{}; };
    if (gbuffer)
        c.target(
            {at(resources::SceneNormals), at(resources::SceneLinearDepth), at(resources::ScenePositions)},
            board.get(resources::SceneDepth));
    else
        c.target({}, board.get(resources::SceneDepth));
    for (int i = 0; gbuffer && i < (board.has(resources::ScenePositions) ? 3 : 2); ++i)
        c.clearColour(glm::vec4(0.0f), i);
    c.clearDepth();
    c.drawQueue(queue_.opaque, gbuffer ? DrawMode::GBuffer : DrawMode::DepthOnly);
}

// The main pass's opaque or transparent items: they read what their effects' snippets sample.
void Renderer::View::declareMain(bool opaque) {
    graph_.addPass(
        opaque ? "main: opaque" : "main: transparent",
        [&](FrameGraph::Builder& b) {
            PassBuilder pb(b, graph_.blackboard, &queue_);
            pb.sampleMaterials(opaque ? queue_.opaque : queue_.transparent);
            // What drawables bind in their draw (FrameSetup::sampleInMainPass): the opaque half
            // reads what is made before it, the transparent half everything, so a producer after
            // the opaque items lives through the Transparent passes and the transparent items.
            if (!opaque && graph_.blackboard.has(resources::TransmissionColour))
                pb.sample(resources::TransmissionColour);
            for (const std::string& resource : mainReads_) {
                if (opaque && !graph_.blackboard.has(resource)) continue;
                if (!graph_.blackboard.has(resource))
                    throw std::logic_error("sgfx: a drawable samples '" + resource +
                                           "' in the main pass, which no pass of the frame makes");
                pb.sample(pb.get(resource), resource);
            }
            // What drawables draw into in their draw (FrameSetup::offscreenTargetInMainPass): made
            // for the transparent half (blended volumes are transparent items), never kept, read
            // by nothing after it, so they live for this pass alone and keep nothing alive.
            if (!opaque)
                for (const auto& [name, desc] : mainTargets_)
                    pb.publish(name, pb.colour(pb.create(name, desc), 0, false));
            pb.write(resources::DrawColour, !(opaque && camera_.clearColorEnabled));
            if (opaque)
                pb.write(resources::DrawDepth, !camera_.clearDepthEnabled);
            else
                pb.depthTest(pb.get(resources::DrawDepth));
        },
        [this, opaque](PassCommands&) {
            if (opaque)
                drawOpaque();
            else
                drawTransparent();
        },
        "main");
}

// Transmissive materials (Material::transmission), as three.js and Filament draw them: a copy of
// the opaque scene (after the AfterOpaque passes: fog's sky, ...) with a mip chain that rough
// surfaces read blurred, then the transmissive items, which sample it along their refracted rays
// and write depth as opaque items do. The Transparent passes (OIT bins) and the transparent items
// come after them, so glass in front of a transmissive surface blends over it; a transmissive
// surface sees only the opaque scene through it (docs/materials.md).
void Renderer::View::declareTransmission() {
    const auto transmits = [](const RenderItem& it) { return (it.features & FeatureTransmission) != 0; };
    if (queue_.transmissive.empty() &&
        std::none_of(queue_.transparent.begin(), queue_.transparent.end(), transmits) &&
        std::none_of(queue_.claimed.begin(), queue_.claimed.end(), transmits))
        return;
    graph_.addPass(
        "transmission copy",
        [&](FrameGraph::Builder& b) {
            PassBuilder pb(b, graph_.blackboard, &queue_);
            pb.sample(resources::DrawColour);
            const TextureDesc desc{.format = draw_->colorFormat, .filter = Filter::Linear, .mipmaps = true};
            const std::string name(resources::TransmissionColour);
            pb.publish(name, pb.colour(pb.create(name, desc), 0, false));
        },
        [this](PassCommands& c) {
            c.copyColour(graph_.blackboard.get(resources::DrawColour),
                         graph_.blackboard.get(resources::TransmissionColour));
        },
        "after opaque");
    if (queue_.transmissive.empty()) return;
    graph_.addPass(
        "main: transmissive",
        [&](FrameGraph::Builder& b) {
            PassBuilder pb(b, graph_.blackboard, &queue_);
            pb.sampleMaterials(queue_.transmissive);
            pb.sample(resources::TransmissionColour);
            pb.write(resources::DrawColour);
            pb.write(resources::DrawDepth);
        },
        [this](PassCommands&) { drawTransmissive(); }, "main");
}

void Renderer::View::declareResolve() {
    graph_.addPass(
        "aa resolve",
        [&](FrameGraph::Builder& b) {
            PassBuilder pb(b, graph_.blackboard, &queue_);
            pb.sample(resources::DrawColour);
            pb.sample(resources::DrawDepth);
            pb.write(resources::ViewColour, false);
            pb.write(resources::ViewDepth, false);
        },
        [this](PassCommands&) { resolve(); }, "resolve");
}

void Renderer::View::declarePostAa() {
    const aa::ViewState& aa = *aa_;
    static const char* const names[] = {nullptr,  nullptr,   nullptr,      "aa fxaa",
                                        "aa taa", "aa smaa", "aa smaa t2x"};
    const char* name = names[std::size_t(aa.settings.mode)];
    if (!name) return;
    graph_.addPass(
        name,
        [&](FrameGraph::Builder& b) {
            PassBuilder pb(b, graph_.blackboard, &queue_);
            pb.sample(resources::ViewDepth);
            pb.write(resources::ViewColour);
            b.sideEffect(); // TAA and SMAA T2x keep their history
        },
        [this](PassCommands&) {
            legacyState(true, *s_.current);
            aa::finish(r_, *aa_, target_);
        },
        "post");
}

// The visible nodes' GPU objects, made or updated before any pass runs (the compile step).
void Renderer::View::compileNodes() {
    s_.log.stage = "compile";
    for (const EffectNode* e : plan_.effects)
        e->compile(r_);
    for (const Drawable* d : plan_.drawables)
        d->compile(r_);
}

// Runs the live passes, each timed and named for GL error sites.
void Renderer::View::executeGraph() {
    s_.pool.beginFrame(s_.frames);
    const std::size_t firstTimer = s_.timers.count();
    const FrameGraph* outer = std::exchange(s_.graph, &graph_);
    const bool timing = r_.options_.timePasses;
    graph_.execute(s_.pool, [&](std::string_view name, const FrameGraph::Execute& execute) {
        s_.log.stage = name;
        s_.timers.begin(timing, std::string(name));
        if (execute) {
            PassCommands commands(r_, graph_, name);
            execute(commands);
            s_.cache.setScissor(false);
            s_.blendedCutoff.reset();
            if (s_.passViewBound) { // the pass drew from another view (PassCommands::setView)
                glBindBufferBase(GL_UNIFORM_BUFFER, 0, s_.frameUbo.get());
                s_.passViewBound = false;
            }
        }
        s_.timers.end(timing);
    });
    s_.graph = outer;
    const aa::ViewState& aa = *aa_;
    if (aa.settings.mode == AntiAliasing::Mode::None || aa.settings.mode == AntiAliasing::Mode::Msaa ||
        aa.settings.mode == AntiAliasing::Mode::Ssaa)
        aa::finish(r_, *aa_, target_);
    const std::string name = camera_.name.empty() ? "view " + std::to_string(s_.graphs.size()) : camera_.name;
    s_.graphs.push_back({name, std::move(graph_), firstTimer, s_.timers.count() - firstTimer});
    r_.current_ = &r_.queue_;
    s_.current = &s_.scene;
}

// Back to the view's target, whatever an older pass or AA step bound; `invalidate` when GL state
// was changed behind the cache.
void Renderer::View::legacyState(bool invalidate, const gl::RenderTarget& t) {
    if (invalidate) s_.cache.invalidate();
    s_.cache.bindFramebuffer(t.fbo.get(), {t.width, t.height}, true);
    s_.cache.setColourMask(true);
}

void Renderer::View::drawOpaque() {
    s_.log.stage = "main pass"; // GL error sites name the main pass, whichever half
    clearTarget();
    if (r_.options_.countFragments) {
        fragments_ = gl::createQuery(GL_SAMPLES_PASSED);
        glBeginQuery(GL_SAMPLES_PASSED, fragments_.get());
    }
    if (!queue_.opaque.empty()) ++r_.stats_.geometryPasses;
    if (r_.options_.occlusionCulling != RendererOptions::OcclusionCulling::Off && draw_->samples <= 1 &&
        render::depthIsMonotone(queue_.opaque))
        drawOpaqueTwoPhase();
    else
        r_.drawItems(queue_.opaque);
}

// RendererOptions::occlusionCulling: per camera, so views (display channels, render-to-texture
// cameras) each remember their own visible set.
void Renderer::View::drawOpaqueTwoPhase() {
    render::OcclusionState& state = s_.occlusionViews[&camera_];
    if (state.owner.expired()) state = {}, state.owner = camera_.weak_from_this();
    const bool unsafe =
        r_.options_.occlusionCulling == RendererOptions::OcclusionCulling::DebugUnsafeMinDepth;
    const render::OcclusionResult res = render::drawOpaqueTwoPhase(
        r_, *draw_, queue_.opaque, r_.frame_.viewProjection, state, unsafe, &s_.occlusionCulled);
    r_.stats_.occlusionTested += res.tested;
    r_.stats_.occlusionCulled += res.culled;
}

void Renderer::View::drawTransmissive() {
    s_.log.stage = "main pass";
    bindDrawTarget();
    r_.drawItems(queue_.transmissive);
}

void Renderer::View::drawTransparent() {
    s_.log.stage = "main pass";
    bindDrawTarget(); // passes before it (a copy, an OIT composite) may have bound their own
    r_.drawItems(queue_.transparent);
    if (fragments_) {
        glEndQuery(GL_SAMPLES_PASSED);
        GLuint64 n = 0;
        glGetQueryObjectui64v(fragments_.get(), GL_QUERY_RESULT, &n);
        r_.stats_.fragments += n;
    }
}

void Renderer::View::bindDrawTarget() {
    s_.cache.bindFramebuffer(draw_->fbo.get(), {draw_->width, draw_->height}, true);
    s_.cache.setColourMask(true);
}

void Renderer::View::clearTarget() {
    bindDrawTarget();
    s_.cache.setDepth(DepthState{}); // depth writes on: a clear obeys the depth mask
    const glm::vec4 cc = clearColour_;
    glClearColor(cc.r, cc.g, cc.b, cc.a);
    const GLbitfield mask = (camera_.clearColorEnabled ? GL_COLOR_BUFFER_BIT : 0u) |
                            (camera_.clearDepthEnabled ? GL_DEPTH_BUFFER_BIT : 0u);
    if (mask) glClear(mask);
}

// Down to the view's own single-sample target; later passes read its colour and depth.
void Renderer::View::resolve() {
    aa::resolve(r_, *aa_, *draw_, target_);
    s_.current = &target_;
    legacyState(true, target_);
    r_.frame_.width = target_.width;
    r_.frame_.height = target_.height;
    const glm::vec4 viewport(0.0f, 0.0f, float(target_.width), float(target_.height));
    glNamedBufferSubData(s_.frameUbo.get(), offsetof(render::FrameBlock, viewport), sizeof viewport,
                         &viewport);
    s_.frameBlock.viewport = viewport;
}

} // namespace sgfx

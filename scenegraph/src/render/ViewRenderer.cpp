// A frame: Renderer::render, and each view it draws (the camera's, and first the render-to-texture
// cameras it sees) in steps: cull, sub-cameras, projection and anti-aliasing, the frame block, the
// passes and the main pass, the resolve and post passes. The frame plan's passes run here.
#include "render/GpuUpload.h"
#include "render/RendererImpl.h"
#include "sgfx/Camera.h"
#include "sgfx/CullVisitor.h"
#include "sgfx/GraphicsContext.h"

#include <glad/gl.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace sgfx {

void FramePlan::add(std::shared_ptr<RenderPass> pass) {
    if (pass && std::find(passes.begin(), passes.end(), pass) == passes.end())
        passes.push_back(std::move(pass));
}

bool FramePlan::has(std::string_view name) const {
    return std::any_of(passes.begin(), passes.end(), [&](const auto& p) { return p->name() == name; });
}

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
    void mainPass();
    void resolveAndPost();

private:
    void clearTarget();

    using clock = std::chrono::steady_clock;
    Renderer& r_;
    Impl& s_;
    Camera& camera_;
    gl::RenderTarget& target_;
    RenderQueue& queue_;
    FramePlan& plan_;
    const clock::time_point t0_ = clock::now();
    float computedNear_ = 0.0f, computedFar_ = 0.0f; // the cull's depth range of what it kept
    aa::ViewState* aa_ = nullptr;
    gl::RenderTarget* draw_ = nullptr; // where the view is drawn (target_, or a larger/multisample one)
};

void Renderer::render(Camera& camera, double time, std::uint64_t frameNumber) {
    using clock = std::chrono::steady_clock;
    context_.assertOwnerThread();
    const auto t0 = clock::now();
    stats_ = {};
    impl_->submittedTriangles = 0;
    frame_.time = time;
    frame_.frameNumber = frameNumber;
    // Forget the targets of render-to-texture cameras that no longer exist.
    std::erase_if(impl_->cameraTargets, [](const auto& e) { return e.second.owner.expired(); });
    std::erase_if(impl_->aaViews, [](const auto& e) { return e.second.owner.expired(); });
    ++impl_->frames;
    std::erase_if(impl_->sortedMeshes, [&](const auto& e) {
        return e.second.owner.expired() || impl_->frames - e.second.lastUse > 600;
    });
    impl_->timers.clear();
    renderView(camera, impl_->scene, queue_, plan_, 0);
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

void Renderer::renderView(Camera& camera, gl::RenderTarget& target, RenderQueue& queue, FramePlan& plan,
                          int depth) {
    View view(*this, camera, target, queue, plan);
    view.cull();
    view.renderSubCameras(depth);
    view.beginProjection();
    view.uploadFrameBlock();
    view.mainPass();
    view.resolveAndPost();
}

void Renderer::View::cull() {
    const Viewport vp = camera_.viewport;
    static const GLenum formats[] = {GL_SRGB8_ALPHA8, GL_RGBA16F, GL_RGBA32F};
    const RendererOptions& options = r_.options_;
    const auto colorTarget = std::size_t(options.colorTarget);
    if (colorTarget >= std::size(formats))
        throw std::invalid_argument("sgfx: RendererOptions::colorTarget has an invalid value " +
                                    std::to_string(colorTarget));
    if (std::uint8_t(options.lighting) > std::uint8_t(RendererOptions::Lighting::PerVertex))
        throw std::invalid_argument("sgfx: RendererOptions::lighting has an invalid value " +
                                    std::to_string(int(options.lighting)));
    target_.resize(vp.width, vp.height, formats[colorTarget]);

    queue_.clear();
    plan_.clear();
    CullVisitor visitor(camera_, queue_, &plan_);
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
    aa::begin(aa, camera_, projection * camera_.viewMatrix, target_.width, target_.height, s_.warnings);
    aa_ = &aa;
    draw_ = &aa::drawTarget(aa, target_);
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
    const int nLights = std::min<int>(int(queue_.lights.size()), render::kMaxLights);
    fb.lightCount = glm::ivec4(nLights, 0, 0, 0);
    for (int i = 0; i < nLights; ++i) {
        fb.lightVector[i] = queue_.lights[std::size_t(i)].vector;
        fb.lightColor[i] = glm::vec4(queue_.lights[std::size_t(i)].color, 0.0f);
    }
    std::uint32_t& features = r_.viewFeatures_;
    features = (std::uint32_t(nLights) << FeatureLightCountShift) |
               (r_.options_.lighting == RendererOptions::Lighting::PerVertex ? FeatureVertexLighting : 0u);
    for (int i = 0; i < nLights; ++i)
        if (queue_.lights[std::size_t(i)].vector.w != 0.0f) features |= FeaturePointLights;
    glNamedBufferSubData(s_.frameUbo.get(), 0, sizeof fb, &fb);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, s_.frameUbo.get());
    s_.cache.invalidate();
    r_.current_ = &queue_;
    s_.current = draw_;
    s_.camera = &camera_;
}

// The compute and pre-passes, then the main pass: linear shading, sRGB-encoded once by the
// framebuffer on write; the opaque items, the passes between them and the transparent ones.
void Renderer::View::mainPass() {
    gl::RenderTarget& draw = *draw_;
    r_.runPasses(plan_, PassStage::Compute, draw);
    r_.runPasses(plan_, PassStage::PrePass, draw);

    clearTarget();
    gl::QueryObject fragments;
    if (r_.options_.countFragments) {
        fragments = gl::createQuery(GL_SAMPLES_PASSED);
        glBeginQuery(GL_SAMPLES_PASSED, fragments.get());
    }
    s_.log.stage = "main pass";
    const bool timing = r_.options_.timePasses;
    s_.timers.begin(timing, "main: opaque");
    r_.drawItems(queue_.opaque);
    s_.timers.end(timing);
    r_.runPasses(plan_, PassStage::AfterOpaque, draw);
    r_.runPasses(plan_, PassStage::Transparent, draw);
    s_.log.stage = "main pass";
    s_.timers.begin(timing, "main: transparent");
    r_.drawItems(queue_.transparent);
    s_.timers.end(timing);
    if (fragments) {
        glEndQuery(GL_SAMPLES_PASSED);
        GLuint64 n = 0;
        glGetQueryObjectui64v(fragments.get(), GL_QUERY_RESULT, &n);
        r_.stats_.fragments += n;
    }
}

void Renderer::View::clearTarget() {
    glBindFramebuffer(GL_FRAMEBUFFER, draw_->fbo.get());
    glViewport(0, 0, draw_->width, draw_->height);
    glEnable(GL_FRAMEBUFFER_SRGB);
    glDepthMask(GL_TRUE);
    s_.cache.forgetDepth();
    const glm::vec4 cc = camera_.clearColor;
    glClearColor(cc.r, cc.g, cc.b, cc.a);
    const GLbitfield mask = (camera_.clearColorEnabled ? GL_COLOR_BUFFER_BIT : 0u) |
                            (camera_.clearDepthEnabled ? GL_DEPTH_BUFFER_BIT : 0u);
    if (mask) glClear(mask);
}

// Down to the view's own single-sample target; the post passes read its colour and depth; then
// FXAA or TAA.
void Renderer::View::resolveAndPost() {
    const RendererOptions& options = r_.options_; // read at each step: a pass may change it
    aa::ViewState& aa = *aa_;
    if (draw_ != &target_) {
        s_.log.stage = "anti-aliasing resolve";
        s_.timers.begin(options.timePasses, "aa resolve");
        aa::resolve(r_, aa, *draw_, target_);
        s_.timers.end(options.timePasses);
        s_.current = &target_;
        r_.frame_.width = target_.width;
        r_.frame_.height = target_.height;
        const glm::vec4 viewport(0.0f, 0.0f, float(target_.width), float(target_.height));
        glNamedBufferSubData(s_.frameUbo.get(), offsetof(render::FrameBlock, viewport), sizeof viewport,
                             &viewport);
    }
    r_.runPasses(plan_, PassStage::Post, target_);
    s_.log.stage = "anti-aliasing";
    const bool postAa =
        aa.settings.mode == AntiAliasing::Mode::Fxaa || aa.settings.mode == AntiAliasing::Mode::Taa;
    s_.timers.begin(options.timePasses && postAa,
                    aa.settings.mode == AntiAliasing::Mode::Fxaa ? "aa fxaa" : "aa taa");
    aa::finish(r_, aa, target_);
    s_.timers.end(options.timePasses && postAa);
    r_.current_ = &r_.queue_;
    s_.current = &s_.scene;
}

void Renderer::runPasses(FramePlan& plan, PassStage stage, gl::RenderTarget& target) {
    for (auto& p : plan.passes) {
        if (p->stage() != stage) continue;
        impl_->log.stage = p->name();
        impl_->timers.begin(options_.timePasses, std::string(p->name()));
        p->execute(*this);
        impl_->timers.end(options_.timePasses);
        impl_->cache.invalidate(); // the pass may have changed GL state behind the cache
        // Back to the view's target and sRGB encoding, whatever the pass bound.
        glBindFramebuffer(GL_FRAMEBUFFER, target.fbo.get());
        glViewport(0, 0, target.width, target.height);
        glEnable(GL_FRAMEBUFFER_SRGB);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    }
}

} // namespace sgfx

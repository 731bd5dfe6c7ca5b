#include "sgfx/Viewer.h"

#include "ViewerChannels.h"
#include "sgfx/Drawable.h"
#include "sgfx/Effect.h"
#include "sgfx/Geometry.h"
#include "sgfx/StateSet.h"
#include "sgfx/gl/Objects.h"

#include <sgfx_glad/gl.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {
// Releases the GPU copies held by geometry and textures while the context is still current
// (OSG's releaseGLObjects), so a scene may outlive its viewer without leaking GL objects.
class ReleaseVisitor : public NodeVisitor {
public:
    ReleaseVisitor()
        : NodeVisitor(Mode::AllChildren) {}
    void apply(Node& n) override {
        release(n.stateSet().get());
        traverse(n);
    }
    void apply(Geometry& g) override {
        g.gpu().reset();
        apply(static_cast<Node&>(g));
    }
    void apply(Drawable& d) override {
        d.releaseGLObjects();
        apply(static_cast<Node&>(d));
    }
    void apply(EffectNode& e) override {
        e.releaseGLObjects();
        apply(static_cast<Node&>(e));
    }
    void apply(Camera& c) override {
        release(c.renderTarget.get());
        apply(static_cast<Node&>(c));
    }

private:
    static void release(const Texture* t) {
        if (t) t->gpu().reset();
    }
    static void release(const StateSet* s) {
        if (!s) return;
        if (s->material.value && *s->material.value) {
            const Material& m = **s->material.value;
            release(m.baseColorTexture.get());
            release(m.alphaTexture.get());
            release(m.normalTexture.get());
            release(m.metallicRoughnessTexture.get());
            release(m.occlusionTexture.get());
            release(m.emissiveTexture.get());
        }
        for (const auto& [name, t] : s->textures)
            if (t.value) release(t.value->get());
    }
};
} // namespace

Viewer::Viewer(std::unique_ptr<GraphicsContext> context)
    : context_(std::move(context))
    , camera_(Camera::create())
    , renderer_(std::make_unique<Renderer>(*context_))
    , pager_(std::make_shared<DatabasePager>()) {
    renderer_->setDatabasePager(pager_.get());
    if (context_->isWindow())
        camera_->setViewport(0, 0, std::max(1, context_->width()), std::max(1, context_->height()));
    camera_->setPerspective(45.0f, 0.1f, 10000.0f);
}

namespace {
// SGFX_HEADLESS, read once: what Headless::Default means in this process.
Viewer::Headless osmesaOrEgl() {
    static const Viewer::Headless kind = [] {
        const char* v = std::getenv("SGFX_HEADLESS");
        const std::string value = v ? v : "";
        if (value.empty() || value == "osmesa") return Viewer::Headless::Osmesa;
        if (value == "egl") return Viewer::Headless::Egl;
        throw std::invalid_argument("SGFX_HEADLESS: '" + value + "' is not egl or osmesa");
    }();
    return kind;
}
} // namespace

std::unique_ptr<Viewer> Viewer::createHeadless(int width, int height, Headless kind) {
    if (kind == Headless::Default) kind = osmesaOrEgl();
    auto v = kind == Headless::Egl ? std::make_unique<Viewer>(std::make_unique<EglContext>())
                                   : std::make_unique<Viewer>(std::make_unique<OsmesaContext>());
    v->camera()->setViewport(0, 0, width, height);
    return v;
}

Viewer::~Viewer() {
    context_->makeCurrent();
    ReleaseVisitor release;
    camera_->accept(release);
    channels_.reset();
    camera_.reset();
    scene_.reset();
    renderer_.reset();
}

void Viewer::setSceneData(NodePtr scene) {
    if (scene_) camera_->removeChild(scene_.get());
    scene_ = std::move(scene);
    if (scene_) camera_->addChild(scene_);
}

void Viewer::setDatabasePager(std::shared_ptr<DatabasePager> pager) {
    pager_ = std::move(pager);
    renderer_->setDatabasePager(pager_.get());
}

void Viewer::setChannels(std::vector<DisplayChannel> channels) {
    // Made and checked first: on error the previous channels stay.
    std::unique_ptr<ViewerChannels> next =
        channels.empty() ? nullptr : std::make_unique<ViewerChannels>(std::move(channels));
    context_->makeCurrent(); // the old composite's GL objects die here
    channels_ = std::move(next);
}

const std::vector<DisplayChannel>& Viewer::channels() const {
    static const std::vector<DisplayChannel> none;
    return channels_ ? channels_->channels() : none;
}

Camera& Viewer::channelCamera(std::size_t i) {
    if (!channels_) throw std::out_of_range("sgfx: Viewer::channelCamera: no channels are set");
    return channels_->camera(i);
}

const FrameStats& Viewer::channelStats(std::size_t i) const {
    if (!channels_) throw std::out_of_range("sgfx: Viewer::channelStats: no channels are set");
    return channels_->channelStats(i);
}

const FrameStats& Viewer::stats() const {
    return channels_ ? channels_->stats() : renderer_->stats();
}

Image Viewer::capture() {
    context_->makeCurrent();
    return channels_ ? renderer_->readPixels(channels_->composite()) : renderer_->readPixels();
}

Image Viewer::captureChannel(std::size_t i) {
    if (!channels_) throw std::out_of_range("sgfx: Viewer::captureChannel: no channels are set");
    (void)channels_->channels().at(i); // out of range before the read-back
    return channels_->crop(capture(), i);
}

void Viewer::frame(double dt) {
    update(dt);
    renderFrame();
}

void Viewer::update(double dt) {
    update_.deltaTime = dt;
    update_.simulationTime += dt;
    ++update_.frameNumber;
    if (pager_) {
        const std::vector<NodePtr> unloaded =
            pager_->updateSceneGraph(update_.frameNumber, update_.simulationTime);
        if (!unloaded.empty()) {
            // GL objects die with the context current, even when the application keeps the subgraph.
            context_->makeCurrent();
            ReleaseVisitor release;
            for (const NodePtr& n : unloaded)
                n->accept(release);
        }
    }
    update_.updatePoses(); // what an interrupted traversal left (the list holds weak pointers)
    camera_->accept(update_);
    update_.updatePoses();
}

void Viewer::renderFrame() {
    context_->makeCurrent();
    if (context_->isWindow()) {
        const int w = context_->width(), h = context_->height();
        if (w > 0 && h > 0 && (w != camera_->viewport.width || h != camera_->viewport.height))
            camera_->setViewport(0, 0, w, h);
    }
    if (channels_)
        channels_->render(*renderer_, *camera_, update_.simulationTime, update_.frameNumber);
    else
        renderer_->render(*camera_, update_.simulationTime, update_.frameNumber);
    const gl::RenderTarget& shown = channels_ ? channels_->composite() : renderer_->sceneTarget();
    if (!context_->isWindow() || !finalDrawCallback) {
        renderer_->present(shown);
        return;
    }
    renderer_->blitToWindow(shown);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, context_->width(), context_->height());
    glDisable(GL_FRAMEBUFFER_SRGB);
    finalDrawCallback(*this);
    renderer_->resetStateCache(); // the callback's GL state is unknown to the renderer
    context_->swapBuffers();
}

} // namespace sgfx

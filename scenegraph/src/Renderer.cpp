// The renderer's construction and small accessors. The rest lives in render/ (see
// render/RendererImpl.h for which file holds what).
#include "sgfx/Renderer.h"

#include "EmbeddedShaders.h"
#include "render/RendererImpl.h"
#include "sgfx/GraphicsContext.h"

#include <sgfx_glad/gl.h>

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>

namespace sgfx {

namespace {

// The units render/TextureUnits.h lays out: 32 for a material program's samplers (every desktop
// GPU and llvmpipe offer 32 per fragment stage), then a drawable's own 16.
void checkTextureUnits() {
    GLint fragment = 0, combined = 0;
    glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &fragment);
    glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &combined);
    if (fragment < GLint(render::kHandedOutUnits) || combined < GLint(render::kTrackedUnits))
        throw std::runtime_error(
            "sgfx: the OpenGL context offers " + std::to_string(fragment) + " fragment and " +
            std::to_string(combined) + " combined texture units; sgfx needs " +
            std::to_string(render::kHandedOutUnits) + " and " + std::to_string(render::kTrackedUnits));
}

} // namespace

Renderer::Renderer(GraphicsContext& context, Options options)
    : context_(context)
    , options_(options)
    , impl_(std::make_unique<Impl>(stats_.stateChanges)) {
    context_.makeCurrent();
    checkTextureUnits();
    // The error policy is read from the environment once, here, never on the frame path.
    const char* env = std::getenv("SGFX_GL_ERRORS");
    impl_->glErrorsDefault = env && std::string_view(env) == "throw"
                                 ? RendererOptions::GlErrorPolicy::Throw
                                 : RendererOptions::GlErrorPolicy::Collect;
    if (!options_.glErrors) options_.glErrors = impl_->glErrorsDefault;
    impl_->frameUbo = gl::createBuffer();
    impl_->lightBuffer = gl::createBuffer();
    impl_->lightTiles = gl::createBuffer();
    impl_->emptyVao = gl::createVertexArray();
    glNamedBufferData(impl_->frameUbo.get(), sizeof(render::FrameBlock), nullptr, GL_DYNAMIC_DRAW);
    render::enableDebugOutput(impl_->log);
    // Cube maps (environment light) filter across face edges, as every GL 4 implementation can.
    glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    // Defaults for attributes a geometry leaves out (context state, not VAO state).
    glVertexAttrib3f(1, 0.0f, 0.0f, 1.0f);
    glVertexAttrib4f(2, 1.0f, 0.0f, 0.0f, 1.0f);
    glVertexAttrib2f(3, 0.0f, 0.0f);
    glVertexAttrib4f(4, 1.0f, 1.0f, 1.0f, 1.0f);
    // A skin without JOINTS_1/WEIGHTS_1 reads joint 0 at weight 0 there (GL's own default is
    // (0, 0, 0, 1), and an integer input read from a float default is undefined).
    glVertexAttribI4ui(10, 0, 0, 0, 0);
    glVertexAttrib4f(11, 0.0f, 0.0f, 0.0f, 0.0f);
    glVertexAttribI4ui(12, 0, 0, 0, 0);
    glVertexAttrib4f(13, 0.0f, 0.0f, 0.0f, 0.0f);
}

Renderer::~Renderer() {
    context_.makeCurrent();
    render::disableDebugOutput();
    // No buffer stays bound to an indexed storage binding: Mesa leaks one still bound when the
    // context is destroyed (LeakSanitizer).
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kLightsBinding, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kLightTilesBinding, 0);
    composer_.clear();
}

gl::RenderTarget& Renderer::sceneTarget() {
    return impl_->scene;
}

gl::RenderTarget& Renderer::currentTarget() {
    return *impl_->current;
}

void Renderer::bindTexture(unsigned unit, unsigned texture) {
    if (unit >= gl::StateCache::kTrackedUnits)
        throw std::invalid_argument("sgfx: texture unit " + std::to_string(unit) + " is out of range");
    impl_->cache.bindTexture(unit, texture);
}

void Renderer::setBlend(BlendMode mode) {
    impl_->cache.setBlend(mode);
}

void Renderer::setCull(CullFace face) {
    // The item's winding stays: the renderer set it for a mirrored item before its draw.
    impl_->cache.setCull(face, impl_->cache.mirroredWinding());
}

void Renderer::useProgram(gl::Program& program) {
    if (impl_->cache.useProgram(program.get())) ++stats_.programChanges;
}

void Renderer::beginOffscreen(unsigned fbo, glm::ivec2 size) {
    impl_->cache.beginOffscreen(fbo, size);
}

void Renderer::clearColour(int attachment, const glm::vec4& value) {
    // Like glClearBufferfv on the bound framebuffer: the colour mask applies.
    const unsigned fbo = impl_->cache.framebuffer();
    if (fbo == ~0u) throw std::logic_error("sgfx: Renderer::clearColour: the bound framebuffer is unknown");
    glClearNamedFramebufferfv(fbo, GL_COLOR, attachment, &value[0]);
}

void Renderer::endOffscreen() {
    impl_->cache.endOffscreen();
}

void Renderer::resetStateCache() {
    impl_->cache.invalidate();
}

gl::Program& Renderer::gbufferProgram() {
    static const BaseShader base{"gbuffer_flat", "gbuffer_flat.vert",
                                 std::string(shaders::embedded("gbuffer_flat.vert")), "gbuffer_flat.frag",
                                 std::string(shaders::embedded("gbuffer_flat.frag"))};
    return composer_.program(base, {}, 0);
}

gl::Program& Renderer::depthOnlyProgram() {
    static const BaseShader base{"depth_only", "depth_only.vert",
                                 std::string(shaders::embedded("depth_only.vert")), "depth_only.frag",
                                 std::string(shaders::embedded("depth_only.frag"))};
    return composer_.program(base, {}, 0);
}

std::size_t Renderer::renderTargetBytes() const {
    return impl_->pool.bytesHeld();
}

} // namespace sgfx

#include "sgfx/PassCommands.h"

#include "render/RendererImpl.h"
#include "sgfx/GraphicsContext.h"
#include "sgfx/gl/Objects.h"

#include <sgfx_glad/gl.h>

#include <stdexcept>
#include <string>

namespace sgfx {

namespace {

unsigned aliveTexture(const FrameGraph& graph, ResourceId id, std::string_view pass) {
    const unsigned t = graph.texture(id);
    if (!t)
        throw std::logic_error("sgfx: frame graph pass '" + std::string(pass) + "' uses '" +
                               graph.resourceName(id) + "', which it did not declare or which is not alive");
    return t;
}

} // namespace

const FrameData& PassCommands::frame() const {
    return renderer_.frame();
}

const RenderQueue& PassCommands::queue() const {
    return renderer_.queue();
}

glm::ivec2 PassCommands::size(ResourceId id) const {
    const ResolvedDesc& d = graph_.resolved(id);
    return {d.width, d.height};
}

int PassCommands::samples(ResourceId id) const {
    return graph_.resolved(id).samples;
}

gl::Program& PassCommands::program(const BaseShader& base, std::span<const ShaderSnippet* const> snippets,
                                   FeatureMask features) {
    return renderer_.composer().program(base, snippets, features);
}

void PassCommands::target(std::initializer_list<ResourceId> colour, ResourceId depth) {
    std::vector<std::pair<unsigned, unsigned>> attachments;
    glm::ivec2 extent{0};
    bool srgb = false;
    unsigned point = GL_COLOR_ATTACHMENT0;
    for (const ResourceId id : colour) {
        if (id.valid()) {
            attachments.emplace_back(point, aliveTexture(graph_, id, pass_));
            extent = size(id);
            srgb = srgb || graph_.resolved(id).format == format::Srgb8Alpha8;
        }
        ++point;
    }
    if (depth.valid()) {
        attachments.emplace_back(GL_DEPTH_ATTACHMENT, aliveTexture(graph_, depth, pass_));
        if (extent == glm::ivec2(0)) extent = size(depth);
    }
    if (attachments.empty())
        throw std::logic_error("sgfx: frame graph pass '" + std::string(pass_) +
                               "' sets a target without attachments");
    Renderer::Impl& s = *renderer_.impl_;
    // The view's own target already has a framebuffer for exactly these attachments.
    const gl::RenderTarget& view = *s.current;
    const bool own = attachments.size() == 2 && attachments[0].second == view.color.get() &&
                     attachments[1].second == view.depth.get() &&
                     attachments[0].first == GL_COLOR_ATTACHMENT0;
    const unsigned fbo = own ? view.fbo.get() : s.pool.framebuffer(attachments, pass_);
    s.cache.bindFramebuffer(fbo, extent, srgb);
    s.cache.setColourMask(true);
}

void PassCommands::clearColour(const glm::vec4& value, int attachment) {
    Renderer::Impl& s = *renderer_.impl_;
    s.cache.setColourMask(true);
    glClearNamedFramebufferfv(s.cache.framebuffer(), GL_COLOR, attachment, &value[0]);
}

void PassCommands::clearDepth(float value) {
    Renderer::Impl& s = *renderer_.impl_;
    s.cache.setDepth(DepthState{}); // depth writes on: a clear obeys the depth mask
    glClearNamedFramebufferfv(s.cache.framebuffer(), GL_DEPTH, 0, &value);
}

unsigned PassCommands::nextUnit() {
    if (units_ >= gl::StateCache::kUnits)
        throw std::runtime_error("sgfx: frame graph pass '" + std::string(pass_) + "' binds more than " +
                                 std::to_string(gl::StateCache::kUnits) + " textures");
    return units_++;
}

void PassCommands::bind(gl::Program& program, std::string_view sampler, ResourceId id) {
    bindTexture(program, sampler, aliveTexture(graph_, id, pass_));
}

void PassCommands::bindTexture(gl::Program& program, std::string_view sampler, unsigned texture) {
    const unsigned unit = nextUnit();
    renderer_.impl_->cache.bindTexture(unit, texture); // and no sampler object: the texture's state
    program.set(sampler, int(unit));
}

void PassCommands::bindComparison(gl::Program& program, std::string_view sampler, ResourceId id) {
    const unsigned texture = aliveTexture(graph_, id, pass_);
    if (samples(id) != 1)
        throw std::logic_error("sgfx: frame graph pass '" + std::string(pass_) +
                               "' binds the multisampled '" + graph_.resourceName(id) +
                               "' for depth comparison");
    Renderer::Impl& s = *renderer_.impl_;
    const unsigned unit = nextUnit();
    s.cache.bindTexture(unit, texture, s.comparisonSampler());
    program.set(sampler, int(unit));
}

void PassCommands::fullscreen(gl::Program& program, const FullscreenState& state) {
    renderer_.impl_->cache.setBlend(state.blend);
    renderer_.drawFullscreen(program, state.depth);
}

void PassCommands::drawQueue(std::span<const RenderItem> items, DrawMode mode) {
    if (items.empty()) return;
    if (items.data() == renderer_.queue().opaque.data()) ++renderer_.stats_.geometryPasses;
    switch (mode) {
    case DrawMode::DepthOnly:
        renderer_.drawItems(items, &renderer_.depthOnlyProgram(), mode);
        break;
    case DrawMode::GBuffer:
        renderer_.drawItems(items, &renderer_.gbufferProgram(), mode);
        break;
    case DrawMode::Main:
    case DrawMode::PassBlend:
        renderer_.drawItems(items, nullptr, mode);
        break;
    }
}

void PassCommands::blendAttachments(std::initializer_list<AttachmentBlend> blends) {
    static const GLenum factors[] = {
        GL_ZERO, GL_ONE, GL_SRC_COLOR, GL_ONE_MINUS_SRC_COLOR, GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA};
    std::vector<std::pair<unsigned, unsigned>> f;
    for (const AttachmentBlend& b : blends)
        f.emplace_back(factors[std::size_t(b.source)], factors[std::size_t(b.destination)]);
    renderer_.impl_->cache.setBlendPerAttachment(f);
}

void PassCommands::depthState(const DepthState& depth) {
    renderer_.impl_->cache.setDepth(depth);
}

void PassCommands::scissor(const glm::ivec4& rect) {
    renderer_.impl_->cache.setScissor(true, rect);
}

void PassCommands::viewport(const glm::ivec4& rect) {
    renderer_.impl_->cache.setViewport(rect);
}

void PassCommands::setView(const glm::mat4& view, const glm::mat4& projection) {
    Renderer::Impl& s = *renderer_.impl_;
    render::FrameBlock fb = s.frameBlock;
    fb.view = view;
    fb.projection = projection;
    fb.viewProjection = projection * view;
    fb.invViewProjection = glm::inverse(fb.viewProjection);
    // A buffer per call in the frame: a GPU may still read the previous one.
    if (s.passViewBlocksUsed == s.passViewBlocks.size()) {
        s.passViewBlocks.push_back(gl::createBuffer());
        glNamedBufferData(s.passViewBlocks.back().get(), sizeof fb, nullptr, GL_DYNAMIC_DRAW);
    }
    const unsigned buffer = s.passViewBlocks[s.passViewBlocksUsed++].get();
    glNamedBufferSubData(buffer, 0, sizeof fb, &fb);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, buffer);
    s.passViewBound = true;
}

void PassCommands::blendedCasters(float cutoff) {
    renderer_.impl_->blendedCutoff = cutoff;
}

void PassCommands::transformFeedback(gl::Program& program, unsigned vertexArray,
                                     std::span<const FeedbackBuffer> outputs, std::uint32_t first,
                                     std::uint32_t count) {
    Renderer::Impl& s = *renderer_.impl_;
    // Draws check the framebuffer even with rasterization off: the view's (complete) target.
    const gl::RenderTarget& view = *s.current;
    s.cache.bindFramebuffer(view.fbo.get(), {view.width, view.height}, true);
    if (s.cache.useProgram(program.get())) ++renderer_.stats_.programChanges;
    glEnable(GL_RASTERIZER_DISCARD);
    glBindVertexArray(vertexArray);
    for (std::size_t i = 0; i < outputs.size(); ++i)
        glBindBufferRange(GL_TRANSFORM_FEEDBACK_BUFFER, GLuint(i), outputs[i].buffer,
                          GLintptr(outputs[i].offset), GLsizeiptr(outputs[i].size));
    glBeginTransformFeedback(GL_POINTS);
    glDrawArrays(GL_POINTS, GLint(first), GLsizei(count));
    glEndTransformFeedback();
    // Nothing left bound: Mesa would keep a buffer bound to an indexed binding alive past its owner.
    for (std::size_t i = 0; i < outputs.size(); ++i)
        glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, GLuint(i), 0);
    glBindVertexArray(0);
    glDisable(GL_RASTERIZER_DISCARD);
}

void PassCommands::dispatch(gl::Program& program, const glm::uvec3& groups) {
    Renderer::Impl& s = *renderer_.impl_;
    if (s.cache.useProgram(program.get())) ++renderer_.stats_.programChanges;
    glDispatchCompute(groups.x, groups.y, groups.z);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
}

void PassCommands::bindImage(gl::Program& program, std::string_view image, ResourceId id) {
    const ResolvedDesc& d = graph_.resolved(id);
    if (d.samples != 1)
        throw std::logic_error("sgfx: frame graph pass '" + std::string(pass_) +
                               "' binds the multisampled '" + graph_.resourceName(id) + "' as an image");
    const unsigned unit = nextImageUnit();
    glBindImageTexture(unit, aliveTexture(graph_, id, pass_), 0, GL_FALSE, 0, GL_READ_WRITE, d.format);
    program.set(image, int(unit));
}

unsigned PassCommands::nextImageUnit() {
    if (images_ >= 8)
        throw std::runtime_error("sgfx: frame graph pass '" + std::string(pass_) +
                                 "' binds more than 8 images");
    return images_++;
}

void PassCommands::warn(std::string message) {
    renderer_.warn(std::move(message));
}

void Renderer::runCommands(std::string_view name, const std::function<void(PassCommands&)>& commands) {
    context_.assertOwnerThread();
    static const FrameGraph none;
    PassCommands c(*this, none, name);
    commands(c);
}

void PassCommands::copyDepth(ResourceId from, ResourceId to) {
    Renderer::Impl& s = *renderer_.impl_;
    const unsigned src =
        s.pool.framebuffer({{GL_DEPTH_ATTACHMENT, aliveTexture(graph_, from, pass_)}}, pass_);
    const unsigned dst = s.pool.framebuffer({{GL_DEPTH_ATTACHMENT, aliveTexture(graph_, to, pass_)}}, pass_);
    const glm::ivec2 a = size(from), b = size(to);
    glBlitNamedFramebuffer(src, dst, 0, 0, a.x, a.y, 0, 0, b.x, b.y, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
}

void PassCommands::copyColour(ResourceId from, ResourceId to) {
    Renderer::Impl& s = *renderer_.impl_;
    const unsigned target = aliveTexture(graph_, to, pass_);
    const unsigned src =
        s.pool.framebuffer({{GL_COLOR_ATTACHMENT0, aliveTexture(graph_, from, pass_)}}, pass_);
    const unsigned dst = s.pool.framebuffer({{GL_COLOR_ATTACHMENT0, target}}, pass_);
    const glm::ivec2 a = size(from), b = size(to);
    if (a != b && samples(from) > 1)
        throw std::logic_error("sgfx: frame graph pass '" + std::string(pass_) + "' copies multisample '" +
                               graph_.resourceName(from) + "' into '" + graph_.resourceName(to) +
                               "' of another size; GL resolves without scaling only");
    // Same sizes blit nearest (exact), others linear.
    glBlitNamedFramebuffer(src, dst, 0, 0, a.x, a.y, 0, 0, b.x, b.y, GL_COLOR_BUFFER_BIT,
                           a == b ? GL_NEAREST : GL_LINEAR);
    if (graph_.resolved(to).mipmaps) glGenerateTextureMipmap(target);
}

} // namespace sgfx

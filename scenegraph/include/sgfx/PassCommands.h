#pragma once
// Everything a frame-graph pass may do to the GPU. Each command goes through the renderer's state
// cache, so a pass never calls GL itself and never has to reset the cache; texture units are
// chosen here, so no effect knows a unit number.
#include "sgfx/Export.h"
#include "sgfx/FrameGraph.h"
#include "sgfx/RenderQueue.h"
#include "sgfx/ShaderComposer.h"
#include "sgfx/StateSet.h"

#include <glm/glm.hpp>

#include <initializer_list>
#include <span>
#include <string>
#include <string_view>

namespace sgfx {

class Renderer;
struct FrameData;
enum class DrawMode : std::uint8_t;
namespace gl {
class Program;
}

/// Blend and depth state of a full-screen draw (no culling, depth off by default).
struct SGFX_API FullscreenState {
    BlendMode blend = BlendMode::Off;
    DepthState depth{.test = false, .write = false, .func = CompareFunc::Always};
};

/// One colour attachment's blend function (source and destination factors, added).
struct SGFX_API AttachmentBlend {
    enum class Factor : std::uint8_t { Zero, One, SrcColour, OneMinusSrcColour, SrcAlpha, OneMinusSrcAlpha };
    Factor source = Factor::One, destination = Factor::Zero;
};

/// A buffer range a transform feedback writes (its binding index is its place in the list).
struct SGFX_API FeedbackBuffer {
    unsigned buffer = 0;
    std::size_t offset = 0, size = 0; ///< bytes
};

class SGFX_API PassCommands {
public:
    PassCommands(Renderer& renderer, const FrameGraph& graph, std::string_view pass)
        : renderer_(renderer)
        , graph_(graph)
        , pass_(pass) {}

    const FrameData& frame() const;
    const RenderQueue& queue() const;
    std::string_view pass() const { return pass_; }
    /// The pixel size of a resource of this frame.
    glm::ivec2 size(ResourceId id) const;
    int samples(ResourceId id) const;

    /// A composed program (cached by the composer).
    gl::Program& program(const BaseShader& base, std::span<const ShaderSnippet* const> snippets = {},
                         FeatureMask features = 0);
    /// Draws into these attachments (colour 0.. in order, then depth; an invalid id is skipped);
    /// the viewport covers them. sRGB targets are encoded on write.
    void target(std::initializer_list<ResourceId> colour, ResourceId depth = {});
    void clearColour(const glm::vec4& value, int attachment = 0);
    void clearDepth(float value = 1.0f);
    /// Binds the resource to `program`'s sampler uniform `sampler` on a unit chosen per pass.
    void bind(gl::Program& program, std::string_view sampler, ResourceId id);
    /// The same for a texture the pass's node owns (a lookup table, a noise texture).
    void bindTexture(gl::Program& program, std::string_view sampler, unsigned texture);
    /// Binds a depth resource to a `sampler2DShadow` uniform through the renderer's depth-comparison
    /// sampler object (see SnippetSampler::comparison); bind() of the same resource to another
    /// uniform reads it plainly in the same draw.
    void bindComparison(gl::Program& program, std::string_view sampler, ResourceId id);
    /// One full-screen triangle (vertex stage: ShaderComposer::fullscreenVertex()).
    void fullscreen(gl::Program& program, const FullscreenState& state = {});
    /// Draws queue items as the main pass would (Main), or their depth (DepthOnly) or G-buffer
    /// outputs (GBuffer); counted in FrameStats::geometryPasses.
    void drawQueue(std::span<const RenderItem> items, DrawMode mode);
    /// Blend per colour attachment for the following drawQueue(..., DrawMode::PassBlend) (weighted
    /// blended OIT adds to one target and multiplies the other).
    void blendAttachments(std::initializer_list<AttachmentBlend> blends);
    /// Depth state for the following drawQueue(..., DrawMode::PassBlend).
    void depthState(const DepthState& depth);
    /// Limits the pass's draws to (x, y, width, height) in pixels; reset when the pass ends.
    void scissor(const glm::ivec4& rect);
    /// Draws into (x, y, width, height) of the current target (call after target(), which
    /// covers the whole target again); with scissor(rect) too, clearDepth clears only that part.
    void viewport(const glm::ivec4& rect);
    /// Later draws of the pass see the world from `view` through `projection` (a light's, for a
    /// shadow map): the frame block (binding 0) is the view's with these matrices and their
    /// product and inverse; the eye, viewport, time and lights stay the view's. Ends with the pass.
    void setView(const glm::mat4& view, const glm::mat4& projection);
    /// Later drawQueue(..., DepthOnly) calls of the pass draw blended built-in items that carry
    /// FeatureAlphaMask as cut-outs at opacity `cutoff` (a shadow's "blended items cast above an
    /// opacity"). Ends with the pass.
    void blendedCasters(float cutoff);
    /// Runs `program` over `count` points from `first` of `vertexArray` with rasterization off,
    /// capturing its vertex outputs into `outputs` (transform feedback; GPU particle simulation).
    void transformFeedback(gl::Program& program, unsigned vertexArray,
                           std::span<const FeedbackBuffer> outputs, std::uint32_t first, std::uint32_t count);
    /// Runs a compute program over `groups` work groups; its writes are visible to every later
    /// command (a full memory barrier).
    void dispatch(gl::Program& program, const glm::uvec3& groups);
    /// Binds a single-sample resource as image `unit`'s write target of a compute program
    /// (`layout(binding = N)` images are numbered by the program; the pass writes the resource).
    void bindImage(gl::Program& program, std::string_view image, ResourceId id);
    /// A warning for Renderer::takeWarnings (a setting the pass could not honour).
    void warn(std::string message);
    /// Copies depth `from` into `to` (a multisample source is resolved, one sample per pixel).
    void copyDepth(ResourceId from, ResourceId to);
    /// Copies colour `from` into level 0 of `to` (a multisample source is resolved, and must then
    /// have `to`'s size; single-sample sizes may differ: linear filtering), then fills the rest of
    /// `to`'s mip chain when it has one. Throws std::logic_error for a multisample source of
    /// another size.
    void copyColour(ResourceId from, ResourceId to);

private:
    unsigned nextUnit();
    unsigned nextImageUnit();
    Renderer& renderer_;
    const FrameGraph& graph_;
    std::string_view pass_;
    unsigned units_ = 0, images_ = 0;
};

} // namespace sgfx

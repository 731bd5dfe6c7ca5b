#pragma once
#include "sgfx/Export.h"
#include "sgfx/Node.h"
#include "sgfx/ProgramKey.h"

#include <cstdint>

namespace sgfx {

struct BaseShader;
class FramePlan;
class FrameSetup;
class Renderer;
class UpdateVisitor;
struct RenderItem;
struct ResolvedState;
namespace gl {
class Program;
}

/// A leaf that draws itself (particle systems, volumes) with a base shader of its own that has
/// the built-in material's hook points, so the effects above it compose into its program exactly
/// as they do for Geometry: it is queued, sorted, blended, claimed by a transparency pass and
/// drawn in depth and G-buffer passes like any other item. The core knows nothing else about it.
class SGFX_API Drawable : public Node {
public:
    void accept(NodeVisitor& v) override;

    /// The base shader this frame's draws use (the same object for the whole frame).
    virtual const BaseShader& baseShader() const = 0;
    /// MaterialFeature bits of its variant beyond blending, which the core adds (FeatureBlend and
    /// the blend kind); FeatureGBuffer is added for G-buffer passes. `state` is its resolved state.
    virtual FeatureMask features(const ResolvedState& state) const = 0;
    /// Its bound in world space when its world matrix is `model`. Drawables whose content lives in
    /// world space (particles) override it; the cull visitor frustum-tests this bound, uses it for
    /// the near/far planes and the transparent sort.
    virtual BoundingSphere worldBound(const glm::mat4& model) const { return bound().transformed(model); }
    /// Once per frame and view while visible: passes it needs (simulation, depth copies).
    /// See EffectNode::setupFrame.
    virtual void setupFrame(FrameSetup&) const {}
    /// See EffectNode::compile: uploads and buffers before the frame's passes and draws.
    virtual void compile(Renderer&) const {}
    /// The update traversal (Viewer::frame): clocks, emitters.
    virtual void update(UpdateVisitor&) {}
    /// Issues its draw calls. `program` is bound with the effects' uniforms, the material's and
    /// the state's set; `item.model` is its world matrix.
    virtual void draw(Renderer& renderer, gl::Program& program, const RenderItem& item) const = 0;
    /// A background (sky, star field): never frustum-culled, left out of the near/far computation,
    /// queued after every other opaque item (it draws only where nothing else did).
    virtual bool background() const { return false; }
    /// For FrameStats::triangles.
    virtual std::size_t triangleCount() const { return 0; }
    /// Drops its GPU objects (the context is current): ReleaseVisitor, Viewer teardown.
    virtual void releaseGLObjects() {}
};

} // namespace sgfx

#pragma once
#include "sgfx/Export.h"
#include <sgfx/Effect.h>
#include <sgfx/Renderer.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>

namespace sgfx {

/// How fog reaches the pixels (switchable at run time; no user shader changes in any mode).
enum class FogMode : std::uint8_t {
    /// Every fragment, opaque or transparent, is fogged over its whole segment from the eye.
    /// Exact through alpha-blended glass with the Exponential response. No pre-pass. Default.
    /// When the node covers every opaque and masked item of a single-sample view, those are
    /// fogged by one full-screen pass after them, from the depth buffer (the same result; see
    /// FogNode::lastFrameDeferred); blended and transmissive items keep the per-fragment fog.
    Forward,
    /// Seed §2: a depth pre-pass of the whole view; in every material, fragments in front
    /// (‖P−O‖ − ‖Pn−O‖ < ε) get F_n on [O, Pn], those behind get F_f on [Pn, P].
    ForwardSplit,
    /// Seed §1: one full-screen pass after the scene, from the depth buffer (eq. 2, eq. 7).
    /// Fogs the whole view, not just the subtree, and nothing behind transparent surfaces.
    PostProcess,
};

/// Optical depth F → fog amount k.
enum class FogResponse : std::uint8_t {
    Linear,      ///< k = clamp(F, 0, 1): seed eq. 7
    Exponential, ///< k = 1 − e^(−F): Beer–Lambert; transmittances of segments multiply
};

/// What pixels without geometry (depth 1) get.
enum class FogSky : std::uint8_t {
    Off,      ///< the clear colour stays
    FarPlane, ///< fog along the ray to the camera's far plane (moves with computed near/far)
    Distance, ///< fog along the ray to FogParameters::skyDistance (default)
};

/// ρ(h) = density·e^(−falloff·h), h = height above the reference plane along `up` (seed eq. 3).
struct SGFX_API FogParameters {
    float density = 1e-4f;                ///< ρ0 per metre at the reference height, [0, 1e6]
    float falloff = 1e-4f;                ///< b per metre, [0, 1e3]
    glm::vec3 color{0.70f, 0.74f, 0.80f}; ///< linear RGB
    float referenceHeight = 0.0f;         ///< metres along `up`
    glm::vec3 up{0.0f, 0.0f, 1.0f};       ///< world up (normalised when set)
    float maxOpacity = 1.0f;              ///< k never exceeds it, [0, 1]
    FogResponse response = FogResponse::Exponential;
    FogSky sky = FogSky::Distance;
    float skyDistance = 1e5f; ///< metres, (0, 1e10]

    /// The seed's figure 1: "solid" fog (ρ0 = 1e-4, b = 1e-4) and ground fog (ρ0 = 1e-3, b = 4.5e-3).
    static FogParameters solid();
    static FogParameters ground();

    /// Throws std::invalid_argument naming the field and the value.
    void validate() const;
};

/// Height fog over its subtree (fog seed, eq. 3): the optical depth of ρ(h) = ρ0·e^(−b·h) along
/// each view ray turns into the fog amount k, applied in every material below (Forward,
/// ForwardSplit) or in a full-screen pass (PostProcess). See docs/effects/fog.md.
class SGFX_API FogNode : public EffectNode {
public:
    static std::shared_ptr<FogNode> create(const FogParameters& parameters = FogParameters::solid(),
                                           FogMode mode = FogMode::Forward);
    FogNode();
    ~FogNode() override;

    std::string_view kind() const override { return "fog"; }
    int order() const override { return 500; } // after lighting effects, before diagnostics
    const ShaderSnippet& snippet() const override;
    void setupFrame(FrameSetup& frame) const override;
    void compile(Renderer& renderer) const override;
    void applyUniforms(gl::Program& program, const DrawContext&) const override;

    /// Both throw std::invalid_argument with the reason and keep the previous value.
    void setParameters(const FogParameters& parameters);
    void setMode(FogMode mode);
    const FogParameters& parameters() const { return parameters_; }
    FogMode mode() const { return mode_; }

    /// Forward mode: whether the view drawn last fogged its opaque and masked items in one
    /// full-screen pass ("fog opaque") instead of in their materials. It does when every opaque
    /// item of the view is below this node, no effect with colour code comes after it in those
    /// items' effect sets (an OIT bin on the glass does not count), and the view draws
    /// single-sample; otherwise the materials fog every fragment as before.
    bool lastFrameDeferred() const { return deferred_; }
    /// Forward mode: true lets the node defer its opaque items' fog to one full-screen pass where
    /// that is exact. Default false: on llvmpipe the pass costs more than it saves
    /// (docs/effects/fog.md, "Cost"), and on an sRGB8 target an overbright surface is clipped
    /// before the pass fogs it.
    void setDeferOpaque(bool allow) { deferOpaque_ = allow; }
    bool deferOpaque() const { return deferOpaque_; }

    /// Forward modes: true (default) paints the sky rule's colour with the main pass's clear
    /// instead of the "fog sky" pass where that is exact: FogSky::Distance; the view clears its
    /// colour and depth; every opaque item is a plain geometry (no drawable) drawn unblended with
    /// the default depth state (test Less, write on: nothing it draws can leave a pixel at the
    /// far plane); no pass runs before the fog's after the opaque items; the clear and fog colours
    /// lie in [0, 1]; and k varies by under 1e-4 of the colour step over the sky directions in
    /// view (a view that shows no sky above the fog's reach, say). On llvmpipe the pass costs a
    /// full-screen pass over the uncovered pixels (docs/effects/fog.md, "Cost").
    void setClearSky(bool allow) { clearSky_ = allow; }
    bool clearSky() const { return clearSky_; }

    /// Sets the fog uniforms (fog_optical_depth.glsl) on any program that declares them, for a view
    /// whose eye is at `eye`.
    static void setUniforms(gl::Program& program, const FogParameters& parameters, const glm::vec3& eye);

private:
    void addPostPass(FrameSetup& frame) const;
    void addSkyPass(FrameSetup& frame) const;
    void addNearestDepth(FrameSetup& frame) const;
    void addOpaquePass(FrameSetup& frame, bool sky) const;
    bool paintSkyWithClear(FrameSetup& frame) const;
    bool canDefer(const RenderQueue& queue, int samples) const;
    FogParameters parameters_;
    FogMode mode_ = FogMode::Forward;
    /// The view about to be drawn defers its opaque fog: set by compile() (the step that updates
    /// a node for that view; setupFrame, which declared the passes of the same choice, changes
    /// nothing), read by snippet() and applyUniforms() while the view's materials are drawn.
    mutable bool deferred_ = false;
    bool deferOpaque_ = false;
    bool clearSky_ = true;
};

} // namespace sgfx

#pragma once
#include "sgfx/Export.h"
#include <sgfx/Effect.h>
#include <sgfx/Renderer.h>

#include <cstdint>
#include <memory>

namespace sgfx {

/// How a bin's blended items reach the pixels (switchable at run time).
enum class TransparencyMode : std::uint8_t {
    /// Back to front per item (and per triangle where asked), the over operator in the GPU's
    /// blender: exact wherever items do not interpenetrate. Default.
    Sorted,
    /// Weighted blended order-independent transparency (McGuire & Bavoil 2013): no sorting at
    /// all, intersecting items need no splitting. An approximation: colours are averaged by
    /// weight, so a front layer with alpha near 1 does not fully hide what is behind it.
    WeightedBlended,
};

/// w(z, α) of the weighted blended mode; z is the view depth in units of `depthScale` metres,
/// d the window depth (gl_FragCoord.z). McGuire & Bavoil 2013, equations 7–10.
enum class OitWeight : std::uint8_t {
    Constant,      ///< w = α: no depth cue (a plain coverage-weighted average)
    Depth7,        ///< α·clamp(10 / (1e-5 + (z/5)² + (z/200)⁶), 1e-2, 3e3): default
    Depth8,        ///< α·clamp(10 / (1e-5 + (z/10)³ + (z/200)⁶), 1e-2, 3e3)
    Depth9,        ///< α·clamp(0.03 / (1e-5 + (z/200)⁴), 1e-2, 3e3)
    WindowDepth10, ///< α·max(1e-2, 3e3·(1 − d)³)
};

/// Weighted blended OIT: the weight function's depth scale and the revealage precision.
struct SGFX_API OitParameters {
    OitWeight weight = OitWeight::Depth7;
    /// Metres per unit of the paper's z: its constants suit 0.1–500 units, so a scene whose
    /// transparent content spans kilometres raises this.
    float depthScale = 1.0f;
    /// Revealage target: R16F (default) or R8, which quantises the product of many (1 − α).
    bool revealage8Bit = false;

    /// Throws std::invalid_argument naming the field.
    void validate() const;
};

/// Everything below it is drawn in the transparent stage (its StateSet sets RenderBin::Transparent
/// and straight alpha blending, which a child's StateSet may override, e.g. with Additive), in the
/// bin's mode. Application geometry elsewhere opts in with a StateSet (blend or renderBin) and
/// tunes its order with StateSet::transparency.
class SGFX_API TransparencyBin : public EffectNode {
public:
    static std::shared_ptr<TransparencyBin> create(TransparencyMode mode = TransparencyMode::Sorted);
    TransparencyBin();
    ~TransparencyBin() override;

    std::string_view kind() const override { return "transparency"; }
    /// Last at the colour hook: the weighted blended mode turns the final colour into its sums.
    int order() const override { return 10000; }
    const ShaderSnippet& snippet() const override;
    void setupFrame(FrameSetup& frame) const override;
    void applyUniforms(gl::Program& program, const DrawContext&) const override;
    /// The weighted blended mode draws straight and premultiplied alpha items itself; additive
    /// and multiplicative blending commute, so those stay in the sorted stage.
    bool drawsBlended(BlendMode mode) const override;

    /// Each throws std::invalid_argument with the reason and keeps the previous value.
    void setMode(TransparencyMode mode);
    void setOitParameters(const OitParameters& parameters);
    /// Order, depth bias, two-pass, per-triangle sorting and depth writes for the whole bin
    /// (written to this node's StateSet; a child's StateSet may set its own).
    void setDetails(const TransparencyDetails& details);

    TransparencyMode mode() const { return mode_; }
    const OitParameters& oitParameters() const { return oit_; }

private:
    void addAccumulatePass(FrameSetup& frame) const;
    void addCompositePass(FrameSetup& frame) const;
    TransparencyMode mode_ = TransparencyMode::Sorted;
    OitParameters oit_;
};

} // namespace sgfx

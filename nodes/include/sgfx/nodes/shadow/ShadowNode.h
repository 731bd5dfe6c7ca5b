#pragma once
/// @file
/// Sun shadows for everything below a node: cascaded shadow maps with slope-scaled bias, normal
/// offset and a choice of filters, applied to the built-in materials (and to foreign shaders that
/// opt in) through the light-visibility hook, with no shader rewritten. docs/effects/shadows.md.
#include <sgfx/Effect.h>
#include <sgfx/Export.h>
#include <sgfx/nodes/shadow/ShadowMath.h>

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sgfx {

class Light;

namespace shadow {
/// Node-mask bits: the default nodeMask (~0) has both. Clear kCasts on a node whose subtree
/// should cast no shadow, kReceives on one whose subtree should stay lit.
inline constexpr NodeMask kCasts = 1u << 30;
inline constexpr NodeMask kReceives = 1u << 31;
} // namespace shadow

/// How a shadow map is read per pixel.
enum class ShadowFilter : std::uint8_t {
    Hard2x2, ///< one hardware comparison, bilinear over 2×2 texels: the cheap option
    Pcf,     ///< 16 taps of a Poisson disc, rotated per world cell: the default
    Pcss,    ///< percentage-closer soft shadows: penumbrae widen with the blocker's distance
};

/// What ShadowNode draws over the view besides shadows, for tuning.
enum class ShadowDebugView : std::uint8_t {
    Off,
    Cascades, ///< tints each pixel by the cascade that shades it (red, green, blue, yellow)
};

/// Everything about a ShadowNode's maps. validate() names a field that is out of range.
struct SGFX_API ShadowOptions {
    int cascades = 3;           ///< 1..4 maps along the view
    int mapSize = 2048;         ///< texels per side of one cascade's map, 256..4096, multiple of 64
    float maxDistance = 200.0f; ///< metres of view depth shadowed, (0, 1e6]; the camera's far plane clips it
    float splitLambda = 0.75f;  ///< [0, 1]: 0 uniform, 1 logarithmic splits (Zhang et al. 2006)
    float blendBand = 0.1f;     ///< [0, 0.5]: fraction of a cascade's depth blended into the next
    float fadeBand = 0.1f;      ///< [0, 0.5]: fraction of the last cascade faded out to lit
    ShadowFilter filter = ShadowFilter::Pcf;
    float pcfRadius = 1.5f;  ///< [0.5, 8] texels: radius of the PCF disc
    bool pcfEarlyOut = true; ///< centre and 4 outer taps agree: the other 12 are skipped
    /// PCSS: the sun's angular radius, [0, 0.2] rad (a SkyNode sets it), and the widest penumbra,
    /// [1, 32] texels (the blocker search and the filter stop at half of it).
    float lightAngularRadius = 0.00465f;
    float maxPenumbraTexels = 16.0f;
    /// Bias (docs/plans/shadows.md §5): depth b = t·(constant + slope·R·min(tan θ, maxSlope)),
    /// normal offset δ = normalOffset·t·(R + ½)·sin θ; t the cascade's texel, R the disc radius.
    float constantBias = 0.5f; ///< [0, 16] texels
    float slopeBias = 0.4f;    ///< [0, 16]
    float maxSlope = 2.0f;     ///< [0, 100]
    float normalOffset = 1.0f; ///< [0, 16]
    float density = 1.0f;      ///< [0, 1]: v' = 1 − density·(1 − v) (the particle seed's shadow density)
    /// When set, (0, 1]: blended items cast where their opacity is at least this (built-in
    /// materials; foreign blended shaders cast whole). Unset: blended items cast nothing.
    std::optional<float> blendedCasterAlpha;
    bool transmissiveCast = false;      ///< transmissive (glass) items cast
    bool drawablesCast = false;         ///< drawables (particles, volumes) cast; the background never does
    int spotMapSize = 1024;             ///< texels per side of a spot's map, 128..4096, multiple of 64
    float spotNear = 0.05f;             ///< metres, (0, 100]: a spot map's near plane
    NodeMask castMask = shadow::kCasts; ///< non-zero: nodes that may cast
    NodeMask receiveMask = shadow::kReceives; ///< non-zero: nodes that may receive
    ShadowDebugView debugView = ShadowDebugView::Off;
    bool snapToTexels = true; ///< off only to show the shimmer snapping prevents

    /// Throws std::invalid_argument ("sgfx: ShadowOptions: cascades = 5 is outside [1, 4]").
    void validate() const;
};

/// Per view and frame, what the node planned (ShadowNode::lastFrame): for tests and tuning.
struct SGFX_API ShadowFrameInfo {
    bool active = false;              ///< a sun was found in the view and casts
    int sunLight = -1;                ///< its index among the view's lights
    std::vector<double> splits;       ///< C_0..C_N, metres of view depth
    std::vector<double> radii;        ///< r' per cascade (metres)
    std::vector<double> texels;       ///< t per cascade (metres)
    std::vector<std::size_t> casters; ///< items drawn into each cascade
};

/// A Group whose subtree is shadowed from one directional light (the sun), which may live anywhere
/// in the view's graph. Its snippet multiplies that light by its visibility in every built-in
/// material below (Blinn-Phong and metallic-roughness, both light loops); what casts is culled from
/// the light per frame from this node down, so casters outside the view throw shadows into it.
class SGFX_API ShadowNode : public EffectNode {
public:
    static std::shared_ptr<ShadowNode> create(std::shared_ptr<Light> sun = nullptr,
                                              const ShadowOptions& options = {});
    ShadowNode();
    ~ShadowNode() override;

    /// The light whose shadows this node draws; nullptr: none (everything lit). Throws
    /// std::invalid_argument unless it is Directional.
    void setSun(std::shared_ptr<Light> sun);
    const std::shared_ptr<Light>& sun() const { return sun_; }
    /// Spot lights shadowed besides the sun, at most 3, each with a perspective map (cones wider
    /// than 80° are cut there). Throws std::invalid_argument for a light that is not a Spot, or a
    /// fourth one.
    void addSpot(std::shared_ptr<Light> spot);
    bool removeSpot(const Light* spot);
    const std::vector<std::shared_ptr<Light>>& spots() const { return spots_; }
    /// Validates; the old options stay on a throw.
    void setOptions(const ShadowOptions& options);
    const ShadowOptions& options() const { return options_; }
    /// What the last view that drew this node planned.
    ShadowFrameInfo lastFrame() const;

    std::string_view kind() const override { return "shadow"; }
    int order() const override { return 1000; }
    const ShaderSnippet& snippet() const override { return snippet_; }
    void setupFrame(FrameSetup& f) const override;
    void applyUniforms(gl::Program& program, const DrawContext& ctx) const override;
    NodeMask subtreeMask() const override { return options_.receiveMask; }

    struct Plan;     ///< one view's cascades and casters (internal)
    struct SpotPlan; ///< one spot's map (internal)
    struct Shared; ///< the plan the passes last ran, read by applyUniforms (internal)

private:
    void rebuildSnippet();
    void addPasses(FrameSetup& f, const std::shared_ptr<const Plan>& plan) const;
    void applySpotUniforms(gl::Program& program, const Plan& plan, glm::ivec4& slots) const;
    void applyCommonUniforms(gl::Program& program, const Plan& plan) const;
    std::shared_ptr<Light> sun_;
    std::vector<std::shared_ptr<Light>> spots_;
    ShadowOptions options_;
    ShaderSnippet snippet_;
    std::string atlasName_;
    std::shared_ptr<Shared> shared_;
};

} // namespace sgfx

#pragma once
#include "sgfx/Export.h"
#include "sgfx/Group.h"
#include "sgfx/Texture.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <string_view>

namespace sgfx {

/// A rectangle of the target in pixels, origin bottom left.
struct SGFX_API Viewport {
    int x = 0, y = 0, width = 640, height = 480;
    float aspect() const { return height > 0 ? float(width) / float(height) : 1.0f; }
    bool operator==(const Viewport&) const = default;
};

/// Anti-aliasing of one camera's image (Camera::setAntiAliasing). Headless and windowed renders
/// take the same path; the targets follow the viewport.
struct SGFX_API AntiAliasing {
    enum class Mode : std::uint8_t {
        None,
        Msaa,    ///< multisample colour and depth, resolved before the post passes
        Ssaa,    ///< rendered `factor`× larger per axis, box-filtered down
        Fxaa,    ///< fast approximate AA on the final image (Lottes' FXAA 3.11, written from its description)
        Taa,     ///< temporal: Halton(2,3) sub-pixel jitter, history reprojected and clamped
        Smaa,    ///< morphological AA (Jimenez et al. 2012, SMAA 1x), written from the paper
        SmaaT2x, ///< SMAA 1x per frame, two sub-pixel jitters, the last two frames averaged
    };
    enum class FxaaQuality : std::uint8_t { Low, Medium, High };
    /// SMAA presets: edge threshold and search steps of the reference's presets (low 0.15 / 4,
    /// medium 0.1 / 8, high 0.1 / 16, ultra 0.05 / 32); diagonal patterns on high (8 steps) and ultra (16).
    enum class SmaaPreset : std::uint8_t { Low, Medium, High, Ultra };
    /// What SMAA looks for edges in: perceptual luma, the largest colour channel difference, or depth.
    enum class SmaaEdge : std::uint8_t { Luma, Colour, Depth };
    Mode mode = Mode::None;
    int samples = 4; ///< MSAA samples; clamped to GL_MAX_SAMPLES with a warning
    int factor = 2;  ///< SSAA per axis, 2..4
    FxaaQuality fxaaQuality = FxaaQuality::Medium;
    float taaFeedback = 0.9375f; ///< TAA: history weight once 1/(1 − feedback) = 16 frames are in, [0, 0.98]
    SmaaPreset smaaPreset = SmaaPreset::High;
    SmaaEdge smaaEdge = SmaaEdge::Luma;
    /// SMAA diagonal search steps, one pixel a step: −1 the preset's (high 8, ultra 16, else off),
    /// 0 off, up to smaa::kMaxDiagonal − 1.
    int smaaDiagonalSteps = -1;

    static AntiAliasing none() { return {}; }
    static AntiAliasing msaa(int samples = 4) {
        AntiAliasing a;
        a.mode = Mode::Msaa;
        a.samples = samples;
        return a;
    }
    static AntiAliasing ssaa(int factor = 2) {
        AntiAliasing a;
        a.mode = Mode::Ssaa;
        a.factor = factor;
        return a;
    }
    static AntiAliasing fxaa(FxaaQuality q = FxaaQuality::Medium) {
        AntiAliasing a;
        a.mode = Mode::Fxaa;
        a.fxaaQuality = q;
        return a;
    }
    static AntiAliasing taa(float feedback = 0.9375f) {
        AntiAliasing a;
        a.mode = Mode::Taa;
        a.taaFeedback = feedback;
        return a;
    }
    static AntiAliasing smaa(SmaaPreset preset = SmaaPreset::High, SmaaEdge edge = SmaaEdge::Luma) {
        AntiAliasing a;
        a.mode = Mode::Smaa;
        a.smaaPreset = preset;
        a.smaaEdge = edge;
        return a;
    }
    static AntiAliasing smaaT2x(SmaaPreset preset = SmaaPreset::High, SmaaEdge edge = SmaaEdge::Luma) {
        AntiAliasing a = smaa(preset, edge);
        a.mode = Mode::SmaaT2x;
        return a;
    }
    /// Throws std::invalid_argument naming the field (samples < 1, factor outside 1..4, ...).
    void validate() const;
    bool operator==(const AntiAliasing&) const = default;

    /// The names command lines and settings files use: none, msaa (4 samples), msaaN (N = 1..8),
    /// ssaaN (N = 2..4), fxaa, fxaa-low, fxaa-high, taa, and
    /// smaa[-t2x][-low|-medium|-high|-ultra][-luma|-colour|-depth] (default high, luma). parse() throws
    /// std::invalid_argument listing them for anything else; name() gives parse()'s name back (msaaN, ssaaN
    /// spelt out).
    static AntiAliasing parse(std::string_view name);
    std::string name() const;
    static constexpr std::string_view kNames =
        "none, msaa, msaa1..msaa8, ssaa2..ssaa4, fxaa, fxaa-low, fxaa-high, taa, "
        "smaa[-t2x][-low|-medium|-high|-ultra][-luma|-colour|-depth]";
};

/// A view into the graph: its children are the scene. View space looks down -Z.
class SGFX_API Camera : public Group {
public:
    static std::shared_ptr<Camera> create() { return std::make_shared<Camera>(); }
    void accept(NodeVisitor& v) override;

    glm::mat4 viewMatrix{1.0f};
    glm::mat4 projectionMatrix{1.0f};
    Viewport viewport;
    glm::vec4 clearColor{0.2f, 0.25f, 0.3f, 1.0f}; ///< linear RGBA
    bool clearColorEnabled = true;
    bool clearDepthEnabled = true;
    bool cullingEnabled = true;
    /// When set, the projection's near/far come from the visible bounds each frame (OSG's
    /// COMPUTE_NEAR_FAR), clamped so near >= far * nearFarRatio.
    bool computeNearFar = false;
    float nearFarRatio = 1e-4f;
    /// Render to texture: a camera nested in a scene with a target draws its own children into
    /// the texture (sized to its viewport, sRGB colour) before the enclosing camera draws, so any
    /// material may sample it in the same frame (a mirror, a monitor in a cockpit). On the
    /// viewer's own camera it receives a copy of the final image.
    std::shared_ptr<Texture> renderTarget;

    /// Validated (std::invalid_argument, the previous setting kept).
    void setAntiAliasing(const AntiAliasing& aa);
    const AntiAliasing& antiAliasing() const { return antiAliasing_; }
    /// TAA: drop the history at the next frame (a camera cut). Large jumps of the view are
    /// detected on their own.
    void resetHistory() { ++historyEpoch_; }
    std::uint64_t historyEpoch() const { return historyEpoch_; }

    /// Perspective projection kept symbolic so a resize can refresh the aspect ratio.
    /// Throws std::invalid_argument for fovy outside (0,180), near <= 0 or far <= near.
    void setPerspective(float fovyDegrees, float zNear, float zFar);
    void setLookAt(const glm::vec3& eye, const glm::vec3& center, const glm::vec3& up = {0, 0, 1});
    void setViewport(int x, int y, int w, int h);

    /// True while projectionMatrix is still the one setPerspective made (assigning another
    /// matrix, e.g. an orthographic one, switches the automatic aspect refresh off).
    bool perspective() const { return perspective_ && projectionMatrix == perspectiveMatrix_; }
    float fovy() const { return fovy_; }
    float zNear() const { return zNear_; }
    float zFar() const { return zFar_; }
    glm::vec3 eyePosition() const;

private:
    AntiAliasing antiAliasing_;
    std::uint64_t historyEpoch_ = 0;
    bool perspective_ = false;
    glm::mat4 perspectiveMatrix_{1.0f};
    float fovy_ = 45.0f, zNear_ = 0.1f, zFar_ = 1000.0f;
};

/// Directional: parallel light along `direction`; Point: from `position` in every direction;
/// Ambient: no direction (adds to the ambient term); Spot: from `position` in a cone around
/// `direction` (KHR_lights_punctual's spot).
enum class LightType : std::uint8_t { Directional, Point, Ambient, Spot };

/// How a point or spot light's contribution changes with distance d.
enum class LightFalloff : std::uint8_t {
    /// Constant (sgfx 0.1's point lights): colour × intensity at any distance, times the range
    /// window when `range` > 0.
    None,
    /// Physical (KHR_lights_punctual): intensity / d², times the range window when `range` > 0.
    InverseSquare,
};

/// A light placed in the graph; it illuminates the whole scene (positional state, as in OSG).
///
/// Units: sgfx light colours are irradiance over π, so a white Lambert surface facing a
/// directional light of colour × intensity = c shows c. A glTF directional light of E lux is
/// intensity E / π here; a glTF point or spot light of I candela is intensity I / π with
/// LightFalloff::InverseSquare (the loader converts both). With InverseSquare a point light's
/// value at distance d is colour × intensity / d² × window, window = clamp(1 − (d/range)⁴, 0, 1)
/// (glTF's recommended range cut-off; 1 without a range). A spot multiplies that by
/// a², a = clamp((cos θ − cos outer) / (cos inner − cos outer), 0, 1), θ the angle from its axis.
///
/// Lights are never frustum-culled with their group: a Light switches culling off for itself
/// and its ancestors (setCullingActive), so a lamp's light is collected when its lamp post is
/// out of view; a point or spot light with a range is left out when its range sphere is.
class SGFX_API Light : public Node {
public:
    Light() { setCullingActive(false); }
    static std::shared_ptr<Light> create(LightType t = LightType::Directional) {
        auto l = std::make_shared<Light>();
        l->type = t;
        return l;
    }
    void accept(NodeVisitor& v) override;
    /// Throws std::invalid_argument naming the light and the field: a type or falloff outside
    /// its enum, a non-finite or negative colour, intensity or range, a zero or non-finite
    /// direction for directional and spot lights, cone angles outside 0 <= inner < outer <= π/2.
    void validate() const;

    LightType type = LightType::Directional;
    glm::vec3 color{1.0f}; ///< linear RGB, multiplied by intensity
    float intensity = 1.0f;
    /// Direction the light travels (directional) or the spot's axis, local frame.
    glm::vec3 direction{0, 0, -1};
    glm::vec3 position{0.0f}; ///< point and spot lights, local frame
    /// Point and spot lights: no light beyond this distance (metres, world units; the node's
    /// scale does not change it); 0 = unlimited. Ranged lights are what the light list sorts
    /// into screen tiles, so give lamps a range.
    float range = 0.0f;
    float innerConeAngle = 0.0f;                 ///< spot: radians from the axis, full light inside
    float outerConeAngle = 0.78539816339744831f; ///< spot: radians, no light outside (π/4 as glTF)
    LightFalloff falloff = LightFalloff::None;   ///< point and spot lights
};

} // namespace sgfx

#pragma once
#include "sgfx/Export.h"
#include <sgfx/Effect.h>
#include <sgfx/Renderer.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace sgfx {

/// Where the m sample offsets lie around a point (SSAO seed §2).
enum class AoKernel : std::uint8_t {
    /// Inside the unit hemisphere along the normal, denser towards the centre (near occluders
    /// count most): default.
    Hemisphere,
    /// The seed's S = (2r − 1, 2r − 1, r): a half cube, corners up to √3 from the centre.
    PaperHalfCube,
};

/// How a sample point is tested against the surface seen at its pixel.
enum class AoCompare : std::uint8_t {
    /// Against the tangent plane of that pixel, followed to the sample's exact screen position:
    /// flat surfaces never occlude themselves, at any angle. Default.
    TangentPlane,
    /// The seed's F: the stored depth of the pixel (z_t ≥ z_A + δ). Pixels seen at grazing angles
    /// span more depth than δ and occlude themselves.
    StoredDepth,
};

enum class AoBlur : std::uint8_t {
    Bilateral, ///< N×N weighted by depth similarity: no bleeding across depth edges. Default.
    Box,       ///< the seed's §3 N×N mean
};

/// What the G-buffer pre-pass stores (seed §1).
enum class AoGBuffer : std::uint8_t {
    /// View-space normal (RGBA16F) and linear view depth (R32F): positions are rebuilt from depth,
    /// exact to a fraction of a millimetre kilometres away. Default.
    LinearDepth,
    /// The seed's two RGB16F targets, positions and normals (stored as RGBA16F: three-channel
    /// float targets need not be renderable). Half floats lose centimetres beyond ~60 m.
    PaperPositions,
};

/// Where the occlusion pass takes the surface normals from.
enum class AoNormals : std::uint8_t {
    /// The G-buffer pre-pass (the whole scene drawn again writing normal and linear depth): the
    /// materials' normals, normal maps included. Default.
    GBuffer,
    /// Rebuilt from the shared scene depth pre-pass (depth only, no G-buffer): of the two
    /// neighbours along x (and along y) the one nearer in depth gives the tangent, so planes get
    /// their exact normal and no normal crosses a depth edge. Geometric normals only.
    FromDepth,
};

/// Draws the occlusion map over the view (white = open, black = occluded), as the seed's
/// figures 5 and 7.
enum class AoDebugView : std::uint8_t { Off, Raw, Blurred };

/// The occlusion kernel, its G-buffer, blur and strength (seed symbols in the field comments).
struct SGFX_API AmbientOcclusionParameters {
    int samples = 32;    ///< m, 8..64
    float radius = 0.5f; ///< R in metres, (0, 1e4]
    float bias = 0.025f; ///< δ in metres, [0, 1e3]
    AoKernel kernel = AoKernel::Hemisphere;
    AoCompare compare = AoCompare::TangentPlane;
    /// Occluders farther than R from the point (in depth) count less (smoothstep(0, 1, R / Δz)),
    /// so a distant foreground object casts no halo.
    bool rangeCheck = true;
    AoBlur blur = AoBlur::Bilateral;
    int blurSize = 5;            ///< N (odd), 1..15; 1 = no blur
    bool halfResolution = false; ///< occlusion and blur at half size, depth-aware upsampling
    float intensity = 1.0f;      ///< k' = min(1, intensity·k)^power, [0, 100]
    float power = 1.0f;          ///< [0.01, 100]
    AoGBuffer gbuffer = AoGBuffer::LinearDepth;
    AoDebugView debugView = AoDebugView::Off;
    std::uint32_t seed = 1; ///< kernel and rotation noise (fixed: the same frame gives the same map)
    AoNormals normals = AoNormals::GBuffer;
    /// Half resolution, 8 taps a frame, accumulated over frames: frame n takes set n mod 8 of a
    /// 64-tap kernel (8 still frames use all of it; `samples` is not used). The history is
    /// reprojected through last frame's view, dropped where its linear depth differs by more
    /// than 2 %, blended by max(1/8, 1/(age + 1)), and reset on resize, camera jumps (> 2 m or
    /// > 15°) and parameter changes. Replaces the blur (blurSize is not used); the materials
    /// upsample by depth. One history per node: views of different sizes under one node reset
    /// it every frame.
    bool temporal = false;

    /// The seed's method as published: half-cube kernel, stored-depth test, no range check,
    /// box blur, position G-buffer.
    static AmbientOcclusionParameters paper();

    /// Throws std::invalid_argument naming the field and the value.
    void validate() const;
};

namespace ao {
/// The m offsets in tangent space (normal = +Z), as the occlusion pass receives them.
SGFX_API std::vector<glm::vec3> kernel(AoKernel kind, int samples, std::uint32_t seed);
/// The 4×4 tiled rotation vectors V_r = (2r − 1, 2r − 1, 0) (seed §2).
SGFX_API std::vector<glm::vec2> rotationNoise(std::uint32_t seed);
} // namespace ao

/// Screen-space ambient occlusion (SSAO seed, Maltsev 2019): a G-buffer pre-pass of the whole
/// view, an occlusion pass, a blur, and in every built-in material below the node the ambient
/// term multiplied by (1 − k). Blended surfaces are not occluded. Foreign shaders may opt in:
/// @code
///   #ifdef SGFX_AMBIENT_OCCLUSION
///   float sgfx_ambientOcclusion(); // defined by sgfx: k at this pixel, 0..1
///   #endif
/// @endcode
class SGFX_API AmbientOcclusionNode : public EffectNode {
public:
    static std::shared_ptr<AmbientOcclusionNode> create(const AmbientOcclusionParameters& parameters = {});
    AmbientOcclusionNode();
    ~AmbientOcclusionNode() override;

    std::string_view kind() const override { return "ambient_occlusion"; }
    int order() const override { return 100; } // the ambient term, before fog at the colour hook
    const ShaderSnippet& snippet() const override;
    void setupFrame(FrameSetup& frame) const override;
    void compile(Renderer& renderer) const override;
    void applyUniforms(gl::Program& program, const DrawContext&) const override;
    void releaseGLObjects() override;

    /// Throws std::invalid_argument with the reason and keeps the previous value.
    void setParameters(const AmbientOcclusionParameters& parameters);
    const AmbientOcclusionParameters& parameters() const { return parameters_; }

private:
    struct Shared;
    void addOcclusionPass(FrameSetup& frame) const;
    void addBlurPasses(FrameSetup& frame) const;
    void addDebugPass(FrameSetup& frame) const;
    void addNormalsPass(FrameSetup& frame) const;
    void addAccumulatePass(FrameSetup& frame) const;
    AmbientOcclusionParameters parameters_;
    std::shared_ptr<Shared> shared_; ///< noise texture and kernel, kept by the passes' execute
};

} // namespace sgfx

#pragma once
/// @file
/// Participating media in a box, raymarched per pixel (lecture 12, volume rendering): absorption
/// (Beer–Lambert), emission, single scattering towards a directional light with a
/// Henyey–Greenstein or Rayleigh phase function; the march stops at the opaque scene's depth, so
/// walls inside smoke cut it. Composited premultiplied; fog applies up to where the medium starts.
/// The lecture's slicing and splatting are options (VolumeMethod).
#include "sgfx/Export.h"
#include <sgfx/nodes/volume/VolumeMath.h>

#include <sgfx/Drawable.h>
#include <sgfx/ShaderComposer.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace sgfx {

struct Image;

/// A density grid over the box, x fastest, then y, then z.
struct SGFX_API VolumeGrid {
    enum class Format : std::uint8_t { R8, R16F, R32F }; ///< GPU storage; R8 holds [0, 1]
    glm::ivec3 size{0};
    Format format = Format::R32F;
    std::vector<float> values;

    static VolumeGrid constant(float density);
    /// A ball of density 1 with radius `radius` (box units, 0.5 touches the faces), its edge
    /// softened over `edge`.
    static VolumeGrid sphere(int resolution = 64, float radius = 0.45f, float edge = 0.05f);
    /// Fractal value noise for smoke and clouds: `coverage` of the box is non-empty, the rest is
    /// exactly 0 (what empty-space skipping jumps over).
    static VolumeGrid noise(int resolution = 64, std::uint32_t seed = 1, int octaves = 4,
                            float coverage = 0.5f);
    /// A raw file of size.x·size.y·size.z values (R8: bytes; R16F: IEEE half; R32F: float),
    /// little-endian; throws std::runtime_error naming the file and the expected and actual sizes.
    static VolumeGrid loadRaw(const std::filesystem::path& file, glm::ivec3 size, Format format);
    /// Throws std::invalid_argument: sizes, value count, non-finite or negative values.
    void validate() const;
};

/// The phase function of single scattering.
enum class VolumePhase : std::uint8_t { Isotropic, HenyeyGreenstein, Rayleigh };
/// Raymarch per pixel (default), the lecture's slicing (view-aligned slices blended back to
/// front) or its splatting (Gaussian kernels at grid points drawn as camera-facing billboards,
/// sorted back to front).
enum class VolumeMethod : std::uint8_t { Raymarch, Slicing, Splatting };

/// The medium's optical properties, its light, the box size and the rendering method.
struct SGFX_API VolumeParameters {
    glm::vec3 size{1.0f};                        ///< box edges (m), centred on the node's origin
    float absorption = 1.0f;                     ///< k_a per metre at density 1
    float scattering = 0.0f;                     ///< k_s per metre at density 1
    glm::vec3 emission{0.0f};                    ///< k_e per metre at density 1 (linear radiance)
    float densityScale = 1.0f;                   ///< multiplies the grid or function
    glm::vec3 lightColor{1.0f};                  ///< the directional light that scatters (linear)
    float ambient = 1.0f;                        ///< share of the scene's ambient light the medium scatters
    glm::vec3 lightDirection{0.0f, 0.0f, -1.0f}; ///< the way it travels, world (normalised when set)
    VolumePhase phase = VolumePhase::HenyeyGreenstein;
    float g = 0.3f;                 ///< Henyey–Greenstein asymmetry, (−1, 1)
    int steps = 64;                 ///< N per ray (the most, with stepLength)
    float stepLength = 0.0f;        ///< > 0: N = ceil(segment / stepLength), at most `steps`
    int lightSteps = 8;             ///< M per light ray
    float earlyTermination = 0.99f; ///< stop once the opacity exceeds it; 1 = never
    volume::Integration integration = volume::Integration::Exact;
    bool jitter = false; ///< random start per pixel: banding becomes noise
    /// Jump over coarse cells whose maximum density is 0. Off by default: on llvmpipe the extra
    /// fetch and branch per step cost more than they save (bench/volume_table.sh).
    bool emptySpaceSkipping = false;
    bool halfResolution = false; ///< march at half size, then a depth-aware upsample
    /// Diagnostics: each pixel's red channel is the number of density samples its ray took
    /// (raymarching at full resolution only), for tests and for tuning skipping and early stops.
    bool debugSampleCount = false;
    VolumeMethod method = VolumeMethod::Raymarch;
    int slices = 128; ///< Slicing: planes across the box
    /// Splatting: metres between kernel centres (a lattice over the box, per axis the box edge
    /// over round(edge / spacing) ≥ 1); each kernel's standard deviation is
    /// volume::kSplatSigmaPerSpacing times the largest axis spacing. At most volume::kMaxSplats.
    float splatSpacing = 0.1f;

    /// Throws std::invalid_argument naming the field and its range.
    void validate() const;
};

/// A participating medium in a box (lecture 12): a density grid raymarched per pixel or drawn
/// as slices or splats, with absorption, emission and single scattering, stopped by the opaque scene.
/// See docs/effects/volume-sky.md.
class SGFX_API VolumeNode : public Drawable {
public:
    static std::shared_ptr<VolumeNode> create(const VolumeParameters& parameters = {},
                                              VolumeGrid grid = VolumeGrid::constant(1.0f));
    /// The density as GLSL: the body of `float volumeDensity(vec3 uvw)`, uvw ∈ [0, 1]³.
    static std::shared_ptr<VolumeNode> createFunction(const VolumeParameters& parameters,
                                                      std::string glslBody);
    VolumeNode(const VolumeParameters& parameters, VolumeGrid grid, std::string function);
    ~VolumeNode() override;

    /// Both throw std::invalid_argument and keep the old values.
    void setParameters(const VolumeParameters& parameters);
    void setGrid(VolumeGrid grid);
    const VolumeParameters& parameters() const { return parameters_; }
    /// Emission colour by density (a row image; x = ρ in [0, 1]), multiplying k_e; null: none.
    void setTransferFunction(std::shared_ptr<Image> ramp);

    /// Default state: premultiplied blending, front faces culled, no depth test (the march
    /// stops at the scene's depth itself).
    static std::shared_ptr<StateSet> defaultState();

    const BaseShader& baseShader() const override;
    FeatureMask features(const ResolvedState&) const override { return FeatureWorldPosition; }
    void setupFrame(FrameSetup& frame) const override;
    void compile(Renderer& renderer) const override;
    void draw(Renderer& renderer, gl::Program& program, const RenderItem& item) const override;
    void releaseGLObjects() override;

protected:
    BoundingSphere computeBound() const override;

private:
    struct Gpu;
    std::string halfName(const char* what) const;
    VolumeParameters parameters_;
    VolumeGrid grid_;
    std::string function_;
    std::shared_ptr<Image> transfer_;
    BaseShader shader_, halfShader_, sliceShader_, splatShader_;
    mutable std::unique_ptr<Gpu> gpu_; ///< made and refreshed by compile(), read by draw()
    mutable bool gridDirty_ = true;
};

} // namespace sgfx

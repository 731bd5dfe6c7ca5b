#pragma once
/// @file
/// GPU particle systems (seed: gpu-particles-transform-feedback-2014): the particle array is
/// advanced by a vertex shader with transform feedback (two buffers, ping-pong, rasterizer off)
/// and drawn by synthesising each particle's polygons on the GPU, either in a geometry shader
/// (the seed) or by instancing. The particles are lit by the scene's lights with the built-in
/// material and go through the shader composer, so fog, ambient occlusion and the transparency
/// passes apply to them like to any other surface.
#include "sgfx/Export.h"
#include <sgfx/nodes/particles/ParticleMath.h>

#include <sgfx/Drawable.h>
#include <sgfx/ShaderComposer.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sgfx {

class StateSet;
class PassCommands;

/// The polygons each particle becomes.
enum class ParticleShape : std::uint8_t {
    Sprite,      ///< a square of side k facing the camera (smoke, sparks, water)
    Hexagon,     ///< a turning hexagon of width k (snowflakes)
    Tetrahedron, ///< a tetrahedron of edge k, stretched along v with `stretch` (raindrops)
    Quad,        ///< a square of side k turned by the particle's angles (leaves)
};

/// How the polygons are made, all from the same particle buffers:
///  GeometryShader: points expanded by a geometry shader (the seed);
///  Instanced:      one instance per particle, its record as per-instance attributes;
///  Pulled:         one plain draw of all the triangles; each vertex reads its particle's record
///                  from the buffer (vertex pulling, gl_VertexID / vertices per particle).
///  PointSprite:    sprites only: one point per particle, the rasterizer makes a screen-aligned
///                  square (side clamped to the driver's largest point size); other shapes use
///                  Pulled instead.
/// Auto: the fastest on the driver (measured: bench/particles_table.sh).
enum class ParticlePath : std::uint8_t { Auto, GeometryShader, Instanced, Pulled, PointSprite };

/// The particle buffers: one interleaved 52-byte record per particle, or four streams
/// (age + position, velocity, r0, r), one buffer each.
enum class ParticleLayout : std::uint8_t { Interleaved, Split };

/// How a simulation step runs, both over the same buffers and the same GLSL equations
/// (particle_motion.glsl, mirrored by ParticleMath.h):
///  TransformFeedback: one vertex per particle, rasterizer off, outputs captured (the seed);
///  Compute:           a compute shader (64 particles per work group) reading copy M and writing
///                     M' as shader storage, then a memory barrier before the draws;
///  Auto:              from 65536 particles, the faster of the two, timed once per buffer
///                     allocation (so per context, capacity and layout): 3 steps of each at the
///                     node's capacity, after one warm-up step each; lastFrame() reports the
///                     choice and the timings. Below 65536, TransformFeedback untimed (a step
///                     costs well under a millisecond either way).
/// The start mode's records (reset, growth) are written by transform feedback on either path.
enum class ParticleUpdate : std::uint8_t { Auto, TransformFeedback, Compute };

/// A particle system: emitter, forces, look, count, and how it is simulated and drawn.
struct SGFX_API ParticleSettings {
    particles::Emitter emitter;
    std::uint32_t capacity = 10000; ///< n
    std::uint32_t seed = 1;
    particles::Respawn respawn = particles::Respawn::CarryAge;
    particles::RotationBounce bounce = particles::RotationBounce::Reflect;
    particles::StartMode start = particles::StartMode::Steady;
    ParticleShape shape = ParticleShape::Sprite;
    float sizeStart = 0.1f, sizeEnd = 0.1f;     ///< k (m), interpolated over the life
    glm::vec4 colorStart{1.0f}, colorEnd{1.0f}; ///< multiplies the material (linear RGB, opacity)
    float stretch = 0.0f;  ///< tetrahedra: length × (1 + stretch·|v|), for rain streaks (s)
    float softness = 0.0f; ///< soft particles: fade within this distance of opaque surfaces (m)
    ParticlePath path = ParticlePath::Auto;
    ParticleLayout layout = ParticleLayout::Interleaved;
    ParticleUpdate update = ParticleUpdate::Auto;

    /// Throws std::invalid_argument naming the field and the allowed range.
    void validate() const;
};

/// What the node's simulation did at its last frame (GL thread; tests, benches, tuning).
struct SGFX_API ParticleFrameInfo {
    /// The update path the steps ran on (Auto resolved); Auto until the first step has run.
    ParticleUpdate update = ParticleUpdate::Auto;
    /// Whether `update` was picked by Auto's timing, and the ms per step it measured (median of
    /// 3, CPU-timed up to a glFinish); 0 when not measured.
    bool measured = false;
    float transformFeedbackMs = 0.0f, computeMs = 0.0f;
    std::uint32_t steps = 0; ///< steps run by the last simulate()
};

/// A GPU particle system (particle seed): simulated by transform feedback or a compute shader, drawn lit and
/// composed like any surface. Presets: rain(), snow(), leaves(), smoke(), waterJet(), sparks().
/// See docs/effects/particles.md.
class SGFX_API ParticleSystemNode : public Drawable {
public:
    /// Most particles a system may hold: 2^24 (2 × 872 MB of records).
    static constexpr std::uint32_t kMaxCapacity = 1u << 24;

    static std::shared_ptr<ParticleSystemNode> create(const ParticleSettings& settings = {});
    explicit ParticleSystemNode(const ParticleSettings& settings);
    ~ParticleSystemNode() override;

    /// Ready-made systems, each with its state set (material, blending, texture). Place the
    /// emitter with a Transform above the node: it lies in the node's z = 0 plane.
    static std::shared_ptr<ParticleSystemNode> rain(glm::vec2 area = {60.0f, 60.0f},
                                                    std::uint32_t count = 100000);
    static std::shared_ptr<ParticleSystemNode> snow(glm::vec2 area = {60.0f, 60.0f},
                                                    std::uint32_t count = 50000);
    static std::shared_ptr<ParticleSystemNode> leaves(glm::vec2 area = {20.0f, 20.0f},
                                                      std::uint32_t count = 2000);
    static std::shared_ptr<ParticleSystemNode> smoke(float sourceWidth = 1.0f, std::uint32_t count = 2000);
    static std::shared_ptr<ParticleSystemNode> waterJet(glm::vec3 direction = {0.0f, 0.5f, 1.0f},
                                                        float speed = 12.0f, std::uint32_t count = 20000);
    static std::shared_ptr<ParticleSystemNode> sparks(std::uint32_t count = 5000);

    /// Replaces the settings; throws std::invalid_argument and keeps the old ones when invalid.
    /// A new capacity keeps the live particles (the first min(old, new)); new ones are born at
    /// the steady rate. A new seed, start mode or respawn rule applies from the next respawn.
    void setSettings(const ParticleSettings& settings);
    const ParticleSettings& settings() const { return settings_; }
    void setEmitter(const particles::Emitter& emitter);
    void setCapacity(std::uint32_t capacity);

    /// The clock: the update traversal calls advance(Δt × timeScale) unless paused; the
    /// simulation runs one step per frame on the GPU with all the time advanced since the last.
    bool paused = false;
    float timeScale = 1.0f;
    void advance(double dt);
    /// A step of exactly `dt` of its own (tests, fixed-step replays); runs before the next frame.
    void queueStep(float dt);
    /// Starts over at the next frame (step 0, the start mode's records).
    void reset();

    /// Steps run since the last reset.
    std::uint32_t steps() const { return step_; }
    /// The world matrix of the emitter at the last simulation step.
    const glm::mat4& emitterMatrix() const { return emitterMatrix_; }
    /// The particle records as the GPU holds them now (GL thread; empty before the first frame).
    std::vector<particles::ParticleRecord> readRecords() const;
    /// The path the draws use on the current driver (Auto resolved).
    ParticlePath resolvedPath() const;
    /// The update path and, under ParticleUpdate::Auto, what its timing measured.
    const ParticleFrameInfo& lastFrame() const { return lastFrame_; }

    /// Drawable
    const BaseShader& baseShader() const override;
    FeatureMask features(const ResolvedState& state) const override;
    BoundingSphere worldBound(const glm::mat4& model) const override;
    void setupFrame(FrameSetup& frame) const override;
    void update(UpdateVisitor& uv) override;
    void draw(Renderer& renderer, gl::Program& program, const RenderItem& item) const override;
    std::size_t triangleCount() const override;
    void releaseGLObjects() override;

    /// What simulate() does: make or resize the buffers (the renderer's compile step), run the
    /// queued steps (the simulation pass), or both (a tool timing one step alone).
    enum class SimulationPart : std::uint8_t { Buffers, Steps, All };
    /// GL thread, inside a frame's compile step or pass, or Renderer::runCommands.
    void simulate(PassCommands& commands, SimulationPart part = SimulationPart::All);
    void compile(Renderer& renderer) const override;

    /// Default state for a shape: lit material, blending as the presets use it, double-sided.
    static std::shared_ptr<StateSet> defaultState();

protected:
    BoundingSphere computeBound() const override;

private:
    struct Gpu;
    struct Pass;
    ParticleSettings settings_;
    std::vector<float> pendingSteps_;
    bool resetPending_ = true;
    std::uint32_t step_ = 0;
    glm::mat4 emitterMatrix_{1.0f};
    mutable glm::mat4 lastModel_{1.0f}; ///< world matrix seen by the last cull
    std::unique_ptr<Gpu> gpu_;
    ParticleFrameInfo lastFrame_;
    std::shared_ptr<Pass> pass_;
    mutable std::unique_ptr<BaseShader> shader_; ///< draw program base for (path, shape, soft)
    mutable int shaderKey_ = -1;
};

} // namespace sgfx

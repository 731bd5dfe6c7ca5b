#include <sgfx/nodes/particles/ParticleSystemNode.h>

#include "ParameterChecks.h"

#include <sgfx/FrameSetup.h>
#include <sgfx/GraphicsContext.h>
#include <sgfx/Material.h>
#include <sgfx/PassCommands.h>
#include <sgfx/Renderer.h>
#include <sgfx/StateSet.h>
#include <sgfx/Visitors.h>
#include <sgfx/gl/Objects.h>

#include <sgfx_glad/gl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>

namespace sgfx {

namespace {

using particles::ParticleRecord;

// The vertex-pulling path's buffer textures: a drawable's own units (never handed out by the
// renderer), bound through the renderer at every draw.
constexpr unsigned kBufferUnit = Renderer::kFirstDrawableUnit;

// Bytes per particle of each stream: one interleaved record, or (age + P, v, r0, r).
constexpr std::array<int, 4> kSplitStrides{16, 12, 12, 12};
constexpr int kRecordBytes = 52;

// The compute step's shader storage bindings: copy M from kSourceBinding, M' from kTargetBinding
// (one per stream; the splats use 13..20, the renderer's lights 8 and 9).
constexpr unsigned kSourceBinding = 21, kTargetBinding = 25;
// Work groups per row of a dispatch (GL guarantees 65535 in x and y; 2^24 particles need 262144
// groups): short rows, so the tests' 10^4 particles already span two.
constexpr std::uint32_t kGroupsPerRow = 128;
// ParticleUpdate::Auto times the paths from this many particles on; below, a step costs well under
// a millisecond either way, less than compiling the compute program and timing it would.
constexpr std::uint32_t kAutoMeasureFrom = 1u << 16;

void check(const char* name, float v, double lo, double hi, bool openLow = false) {
    nodes::checkRange("ParticleSettings", name, v, lo, hi, openLow);
}
void checkVector(const char* name, glm::vec3 v, double limit) {
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(v[i]) || std::abs(v[i]) > limit)
            nodes::refuse("ParticleSettings", std::string(name) + " = (" + nodes::number(v.x) + ", " +
                                                  nodes::number(v.y) + ", " + nodes::number(v.z) +
                                                  ") must be finite and within ±" + nodes::number(limit));
}

const BaseShader& updateShader(ParticleLayout layout) {
    static const auto make = [](bool interleaved) {
        BaseShader b{interleaved ? "particle_update_interleaved" : "particle_update_split",
                     "particle_update.vert", nodes::shaderWithIncludes("particle_update.vert"), "", ""};
        b.feedbackVaryings = {"o_state", "o_velocity", "o_angles0", "o_angles"};
        b.feedbackInterleaved = interleaved;
        return b;
    };
    static const BaseShader interleaved = make(true), split = make(false);
    return layout == ParticleLayout::Split ? split : interleaved;
}

std::unique_ptr<gl::Program> computeProgram(ParticleLayout layout) {
    const bool split = layout == ParticleLayout::Split;
    std::string defines = "#define SGFX_PARTICLE_SOURCE " + std::to_string(kSourceBinding) +
                          "\n#define SGFX_PARTICLE_TARGET " + std::to_string(kTargetBinding) + "\n";
    if (split) defines += "#define SGFX_PARTICLE_SPLIT\n";
    ComposedProgram c;
    c.compute = nodes::shaderWithIncludes("particle_update.comp");
    c.compute.insert(c.compute.find('\n') + 1, defines); // after #version
    c.vertexSources = {"particle_update.comp"};
    c.description = split ? "particle_update_split (compute)" : "particle_update_interleaved (compute)";
    return std::make_unique<gl::Program>(c);
}

// The uniforms of one step (particle_motion.glsl), the same for both update paths.
void setStepUniforms(gl::Program& program, const ParticleSettings& s, const glm::mat4& emitterMatrix,
                     float dt, std::uint32_t step) {
    const particles::Emitter& e = s.emitter;
    program.set("u_emitter", emitterMatrix);
    program.set("u_emitterSize", e.size);
    program.set("u_velocity", e.velocity);
    program.set("u_spread", e.velocitySpread);
    program.set("u_acceleration", e.acceleration);
    program.set("u_krot", e.rotationRange);
    program.set("u_kvel", e.rotationSpeed);
    program.set("u_tmax", e.lifetime);
    program.set("u_dt", dt);
    program.setUnsigned("u_step", step);
    program.setUnsigned("u_seed", s.seed);
    program.set("u_carryAge", s.respawn == particles::Respawn::CarryAge ? 1 : 0);
    program.set("u_reflect", s.bounce == particles::RotationBounce::Reflect ? 1 : 0);
}

double medianOf3(std::array<double, 3> v) {
    std::sort(v.begin(), v.end());
    return v[1];
}

// A draw program's base: the path's vertex (and geometry) stage and the built-in material's
// fragment stage, with the shape and the soft-particle modifier compiled in.
BaseShader drawShader(ParticlePath path, ParticleShape shape, bool soft, ParticleLayout layout) {
    static const char* const shapes[] = {"sprite", "hexagon", "tetrahedron", "quad"};
    const std::string defines = "#define SGFX_PARTICLE_SHAPE " + std::to_string(int(shape)) + "\n";
    auto withDefines = [&](const std::string& src) { return nodes::afterVersion(src, defines); };
    std::string fragment = ShaderComposer::blinnPhong().fragmentSource;
    if (soft) fragment = nodes::afterVersion(std::move(fragment), nodes::shaderText("particle_soft.glsl"));
    static const char* const paths[] = {"", "particles_gs_", "particles_instanced_", "particles_pulled_",
                                        "particles_points_"};
    const std::string name = std::string(paths[int(path)]) + shapes[int(shape)] + (soft ? "_soft" : "");
    if (path == ParticlePath::GeometryShader) {
        BaseShader b{name, "particle_points.vert", nodes::shaderText("particle_points.vert"),
                     soft ? "particle_soft.glsl + blinn_phong.frag" : "blinn_phong.frag",
                     std::move(fragment)};
        b.geometryName = "particle_corners.geom";
        b.geometrySource = withDefines(nodes::shaderWithIncludes("particle_corners.geom"));
        return b;
    }
    if (path == ParticlePath::PointSprite) {
        fragment = nodes::afterVersion(std::move(fragment), "#define SGFX_POINT_SPRITE\n");
        return BaseShader{
            name, "particle_point.vert", withDefines(nodes::shaderWithIncludes("particle_point.vert")),
            soft ? "particle_soft.glsl + blinn_phong.frag" : "blinn_phong.frag", std::move(fragment)};
    }
    if (path == ParticlePath::Pulled) {
        std::string vertex =
            nodes::afterVersion(withDefines(nodes::shaderWithIncludes("particle_pulled.vert")),
                                "#define SGFX_PARTICLE_BUFFER_UNIT " + std::to_string(kBufferUnit) + "\n" +
                                    (layout == ParticleLayout::Split ? "#define SGFX_PARTICLE_SPLIT\n" : ""));
        return BaseShader{name + (layout == ParticleLayout::Split ? "_split" : ""), "particle_pulled.vert",
                          std::move(vertex),
                          soft ? "particle_soft.glsl + blinn_phong.frag" : "blinn_phong.frag",
                          std::move(fragment)};
    }
    return BaseShader{
        name, "particle_instanced.vert", withDefines(nodes::shaderWithIncludes("particle_instanced.vert")),
        soft ? "particle_soft.glsl + blinn_phong.frag" : "blinn_phong.frag", std::move(fragment)};
}

int trianglesPerParticle(ParticleShape s) {
    return s == ParticleShape::Hexagon || s == ParticleShape::Tetrahedron ? 4 : 2;
}

std::shared_ptr<Texture> makeTexture(std::shared_ptr<Image> image) {
    auto t = Texture::create(std::move(image), true);
    t->wrapS = t->wrapT = Wrap::ClampToEdge;
    return t;
}

// A soft round puff: white, opacity falling smoothly to 0 at the edge.
std::shared_ptr<Texture> puffTexture() {
    constexpr int n = 64;
    auto img = Image::create(n, n, 4);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float dx = (float(x) + 0.5f) / n - 0.5f, dy = (float(y) + 0.5f) / n - 0.5f;
            const float r = std::sqrt(dx * dx + dy * dy) * 2.0f;
            const float a = r >= 1.0f ? 0.0f : (1.0f - r * r) * (1.0f - r * r);
            std::uint8_t* p = img->pixel(x, y);
            p[0] = p[1] = p[2] = 255;
            p[3] = std::uint8_t(std::lround(a * 255.0f));
        }
    return makeTexture(img);
}

// A leaf: a pointed ellipse with a midrib, green to autumn orange across the image.
std::shared_ptr<Texture> leafTexture() {
    constexpr int n = 64;
    auto img = Image::create(n, n, 4);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float u = (float(x) + 0.5f) / n * 2.0f - 1.0f, v = (float(y) + 0.5f) / n * 2.0f - 1.0f;
            const float halfWidth = 0.55f * (1.0f - v * v) * (1.0f - 0.3f * v);
            const bool inside = std::abs(u) < halfWidth && std::abs(v) < 0.95f;
            const bool rib = std::abs(u) < 0.04f;
            const float t = 0.5f + 0.5f * u;
            std::uint8_t* p = img->pixel(x, y);
            p[0] = std::uint8_t(rib ? 120 : 90 + 140 * t);
            p[1] = std::uint8_t(rib ? 110 : 130 - 40 * t);
            p[2] = std::uint8_t(rib ? 40 : 30);
            p[3] = inside ? 255 : 0;
        }
    return makeTexture(img);
}

std::shared_ptr<ParticleSystemNode> withState(std::string name, const ParticleSettings& s,
                                              const std::function<void(StateSet&, Material&)>& style) {
    auto node = ParticleSystemNode::create(s);
    node->name = std::move(name);
    auto state = ParticleSystemNode::defaultState();
    style(*state, **state->material.value);
    node->setStateSet(state);
    return node;
}

} // namespace

// ---------------------------------------------------------------- settings
void ParticleSettings::validate() const {
    if (capacity == 0 || capacity > ParticleSystemNode::kMaxCapacity)
        nodes::refuse("ParticleSettings", "capacity = " + std::to_string(capacity) + " is outside [1, " +
                                              std::to_string(ParticleSystemNode::kMaxCapacity) +
                                              "] (2 × 52 bytes of GPU buffer per particle)");
    const particles::Emitter& e = emitter;
    check("emitter.lifetime (tmax)", e.lifetime, 0.0, 1e6, true);
    check("emitter.size.x (W)", e.size.x, 0.0, 1e7);
    check("emitter.size.y (H)", e.size.y, 0.0, 1e7);
    checkVector("emitter.velocity (v0)", e.velocity, 1e6);
    checkVector("emitter.acceleration (a)", e.acceleration, 1e6);
    check("emitter.velocitySpread (kv)", e.velocitySpread, 0.0, 1e6);
    check("emitter.rotationRange (krot)", e.rotationRange, 0.0, 3.14159265358979);
    check("emitter.rotationSpeed (kvel)", e.rotationSpeed, 0.0, 1e6);
    check("sizeStart", sizeStart, 0.0, 1e6);
    check("sizeEnd", sizeEnd, 0.0, 1e6);
    check("stretch", stretch, 0.0, 1e3);
    check("softness", softness, 0.0, 1e6);
    for (int i = 0; i < 4; ++i) {
        check("colorStart", colorStart[i], 0.0, i == 3 ? 1.0 : 1e6);
        check("colorEnd", colorEnd[i], 0.0, i == 3 ? 1.0 : 1e6);
    }
    if (std::uint8_t(respawn) > std::uint8_t(particles::Respawn::Paper))
        nodes::refuse("ParticleSettings", "respawn has an invalid value " + std::to_string(int(respawn)));
    if (std::uint8_t(bounce) > std::uint8_t(particles::RotationBounce::Clamp))
        nodes::refuse("ParticleSettings", "bounce has an invalid value " + std::to_string(int(bounce)));
    if (std::uint8_t(start) > std::uint8_t(particles::StartMode::Burst))
        nodes::refuse("ParticleSettings", "start has an invalid value " + std::to_string(int(start)));
    if (std::uint8_t(shape) > std::uint8_t(ParticleShape::Quad))
        nodes::refuse("ParticleSettings", "shape has an invalid value " + std::to_string(int(shape)));
    if (std::uint8_t(path) > std::uint8_t(ParticlePath::PointSprite))
        nodes::refuse("ParticleSettings", "path has an invalid value " + std::to_string(int(path)));
    if (std::uint8_t(layout) > std::uint8_t(ParticleLayout::Split))
        nodes::refuse("ParticleSettings", "layout has an invalid value " + std::to_string(int(layout)));
    if (std::uint8_t(update) > std::uint8_t(ParticleUpdate::Compute))
        nodes::refuse("ParticleSettings", "update has an invalid value " + std::to_string(int(update)) +
                                              " (Auto, TransformFeedback or Compute)");
}

// ---------------------------------------------------------------- GPU state
// Two copies of the array (M and M'), each one buffer (interleaved) or four (split), with a
// vertex array per copy for points (update, geometry-shader draws) and for instances.
struct ParticleSystemNode::Gpu {
    ParticleLayout layout = ParticleLayout::Interleaved;
    std::uint32_t capacity = 0;
    int current = 0; // which copy holds M
    std::array<std::array<gl::BufferObject, 4>, 2> buffers;
    std::array<gl::VertexArrayObject, 2> pointVao, instanceVao;
    gl::VertexArrayObject emptyVao;
    std::array<std::array<gl::TextureObject, 4>, 2> bufferTextures; // vertex pulling's views
    std::unique_ptr<gl::Program> compute;                           // the compute step, made at its first use
    ParticleFrameInfo choice; // the update path steps take (Auto: once measured)

    int streams() const { return layout == ParticleLayout::Split ? 4 : 1; }
    int stride(int s) const {
        return layout == ParticleLayout::Split ? kSplitStrides[std::size_t(s)] : kRecordBytes;
    }

    // Allocates both copies; false (and nothing kept) when the driver runs out of memory.
    bool allocate(ParticleLayout l, std::uint32_t n) {
        layout = l;
        capacity = n;
        // GL: the particle buffers (transform feedback ping-pong), made and sized here, with the
        // driver's out-of-memory answer read directly (errors before it drained); no command for
        // buffers yet.
        while (glGetError() != GL_NO_ERROR) {
        }
        for (auto& copy : buffers)
            for (int s = 0; s < streams(); ++s) {
                copy[std::size_t(s)] = gl::createBuffer();
                // GL: storage for one stream of one copy (see above).
                glNamedBufferData(copy[std::size_t(s)].get(), GLsizeiptr(n) * stride(s), nullptr,
                                  GL_DYNAMIC_COPY);
            }
        if (glGetError() == GL_OUT_OF_MEMORY) return false; // GL: the allocation's outcome (above)
        emptyVao = gl::createVertexArray();
        static const GLenum splitFormats[4] = {GL_RGBA32F, GL_RGB32F, GL_RGB32F, GL_RGB32F};
        for (int c = 0; c < 2; ++c)
            for (int s = 0; s < streams(); ++s) {
                gl::TextureObject& t = bufferTextures[std::size_t(c)][std::size_t(s)];
                t = gl::createTexture(GL_TEXTURE_BUFFER);
                // GL: a buffer-texture view of the copy for vertex pulling; no command for it.
                glTextureBuffer(t.get(), layout == ParticleLayout::Split ? splitFormats[s] : GL_R32F,
                                buffers[std::size_t(c)][std::size_t(s)].get());
            }
        for (int c = 0; c < 2; ++c) {
            pointVao[std::size_t(c)] = gl::createVertexArray();
            instanceVao[std::size_t(c)] = gl::createVertexArray();
            for (GLuint vao : {pointVao[std::size_t(c)].get(), instanceVao[std::size_t(c)].get()}) {
                static const int sizes[4] = {4, 3, 3, 3};
                static const int offsets[4] = {0, 16, 28, 40};
                for (int a = 0; a < 4; ++a) {
                    const int binding = layout == ParticleLayout::Split ? a : 0;
                    // GL: the node's own vertex arrays (per point and per instance) over its
                    // buffers, set up once per allocation; the renderer has no command for them.
                    glVertexArrayAttribFormat(vao, GLuint(a), sizes[a], GL_FLOAT, GL_FALSE,
                                              layout == ParticleLayout::Split ? 0 : GLuint(offsets[a]));
                    glVertexArrayAttribBinding(vao, GLuint(a), GLuint(binding));
                    glEnableVertexArrayAttrib(vao, GLuint(a));
                }
                for (int s = 0; s < streams(); ++s) {
                    // GL: the vertex arrays' buffers and instance divisors (as above).
                    glVertexArrayVertexBuffer(vao, GLuint(s), buffers[std::size_t(c)][std::size_t(s)].get(),
                                              0, stride(s));
                    if (vao == instanceVao[std::size_t(c)].get())
                        glVertexArrayBindingDivisor(vao, GLuint(s), 1);
                }
            }
        }
        return true;
    }

    void step(PassCommands& c, gl::Program& feedbackProgram, ParticleUpdate how,
              const std::function<void(gl::Program&)>& uniforms);
    void measure(PassCommands& c, gl::Program& feedbackProgram,
                 const std::function<void(gl::Program&)>& uniforms);

    // What a transform feedback into particles [first, first + count) of copy `c` writes.
    std::vector<FeedbackBuffer> feedback(int c, std::uint32_t first, std::uint32_t count) const {
        std::vector<FeedbackBuffer> out;
        for (int s = 0; s < streams(); ++s)
            out.push_back({buffers[std::size_t(c)][std::size_t(s)].get(),
                           std::size_t(first) * std::size_t(stride(s)),
                           std::size_t(count) * std::size_t(stride(s))});
        return out;
    }
};

// One step M → M' into the other copy by `how` (the caller swaps the copies); `uniforms` sets
// the step's uniforms on the program that runs it.
void ParticleSystemNode::Gpu::step(PassCommands& c, gl::Program& feedbackProgram, ParticleUpdate how,
                                   const std::function<void(gl::Program&)>& uniforms) {
    const int src = current, dst = 1 - src;
    if (how != ParticleUpdate::Compute) {
        uniforms(feedbackProgram);
        c.transformFeedback(feedbackProgram, pointVao[std::size_t(src)].get(), feedback(dst, 0, capacity), 0,
                            capacity);
        return;
    }
    if (!compute) compute = computeProgram(layout);
    uniforms(*compute);
    compute->setUnsigned("u_count", capacity);
    for (int s = 0; s < streams(); ++s) {
        gl::bindStorageBuffer(kSourceBinding + unsigned(s), buffers[std::size_t(src)][std::size_t(s)]);
        gl::bindStorageBuffer(kTargetBinding + unsigned(s), buffers[std::size_t(dst)][std::size_t(s)]);
    }
    const std::uint32_t groups = (capacity + 63) / 64;
    const std::uint32_t row = std::min(groups, kGroupsPerRow);
    c.dispatch(*compute, {row, (groups + row - 1) / row, 1}); // ends with a full memory barrier
    // Nothing left bound: Mesa would keep a buffer bound to an indexed binding alive past its owner.
    static const gl::BufferObject none;
    for (int s = 0; s < streams(); ++s) {
        gl::bindStorageBuffer(kSourceBinding + unsigned(s), none);
        gl::bindStorageBuffer(kTargetBinding + unsigned(s), none);
    }
}

// ParticleUpdate::Auto: one warm-up step of each path (shader compilation), then 3 timed steps of
// each, interleaved, all into the spare copy (M is untouched); keeps the faster median.
void ParticleSystemNode::Gpu::measure(PassCommands& c, gl::Program& feedbackProgram,
                                      const std::function<void(gl::Program&)>& uniforms) {
    auto timed = [&](ParticleUpdate how) {
        gl::finish();
        const auto t0 = std::chrono::steady_clock::now();
        step(c, feedbackProgram, how, uniforms);
        gl::finish();
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    };
    timed(ParticleUpdate::TransformFeedback);
    timed(ParticleUpdate::Compute);
    std::array<double, 3> tf{}, cs{};
    for (std::size_t i = 0; i < 3; ++i) {
        tf[i] = timed(ParticleUpdate::TransformFeedback);
        cs[i] = timed(ParticleUpdate::Compute);
    }
    choice.measured = true;
    choice.transformFeedbackMs = float(medianOf3(tf));
    choice.computeMs = float(medianOf3(cs));
    choice.update = choice.computeMs <= choice.transformFeedbackMs ? ParticleUpdate::Compute
                                                                   : ParticleUpdate::TransformFeedback;
}

// ---------------------------------------------------------------- passes
// The simulation's handle on its node: the frame graph's execute advances the particles (GPU state
// of the node, changed while the frame executes, never during cull or setup).
struct ParticleSystemNode::Pass {
    ParticleSystemNode& node;
};

// ---------------------------------------------------------------- node
std::shared_ptr<ParticleSystemNode> ParticleSystemNode::create(const ParticleSettings& settings) {
    return std::make_shared<ParticleSystemNode>(settings);
}

ParticleSystemNode::ParticleSystemNode(const ParticleSettings& settings)
    : pass_(std::make_shared<Pass>(Pass{*this})) {
    settings.validate();
    settings_ = settings;
    // Particles live in world space and move every frame: the node tests its own world bound,
    // so its ancestors' (parent-frame) bounds never drop it.
    setCullingActive(false);
}

ParticleSystemNode::~ParticleSystemNode() = default;

std::shared_ptr<StateSet> ParticleSystemNode::defaultState() {
    auto state = std::make_shared<StateSet>();
    auto m = Material::create();
    m->ambient = glm::vec3(1.0f);
    m->diffuse = glm::vec4(1.0f);
    state->material.set(m);
    state->cullFace.set(CullFace::None);
    return state;
}

void ParticleSystemNode::setSettings(const ParticleSettings& s) {
    s.validate();
    settings_ = s;
    dirtyBound();
}

void ParticleSystemNode::setEmitter(const particles::Emitter& e) {
    ParticleSettings s = settings_;
    s.emitter = e;
    setSettings(s);
}

void ParticleSystemNode::setCapacity(std::uint32_t n) {
    ParticleSettings s = settings_;
    s.capacity = n;
    setSettings(s);
}

void ParticleSystemNode::advance(double dt) {
    if (!std::isfinite(dt) || dt < 0.0)
        nodes::refuse("ParticleSystemNode::advance", "dt = " + nodes::number(dt) + " must be finite and ≥ 0");
    // Longer than a few lifetimes changes nothing but float precision (every particle respawns).
    const float cap = 4.0f * settings_.emitter.lifetime;
    if (dt == 0.0) return;
    if (pendingSteps_.empty()) pendingSteps_.push_back(0.0f);
    pendingSteps_.back() = std::min(cap, pendingSteps_.back() + float(dt));
}

void ParticleSystemNode::queueStep(float dt) {
    if (!std::isfinite(dt) || dt < 0.0f)
        nodes::refuse("ParticleSystemNode::queueStep",
                      "dt = " + nodes::number(dt) + " must be finite and ≥ 0");
    pendingSteps_.push_back(dt);
}

void ParticleSystemNode::reset() {
    resetPending_ = true;
    pendingSteps_.clear();
}

void ParticleSystemNode::update(UpdateVisitor& uv) {
    if (!paused && timeScale > 0.0f && std::isfinite(timeScale)) advance(uv.deltaTime * double(timeScale));
}

ParticlePath ParticleSystemNode::resolvedPath() const {
    ParticlePath p = settings_.path;
    if (p == ParticlePath::Auto) {
        // Measured with bench/particles_table.sh on llvmpipe: point sprites, then vertex
        // pulling, are several times faster than instancing and the geometry shader (its draw
        // module runs a tiny vertex batch per instance and per emitted primitive). No GPU was
        // measured; the same order is used there.
        p = settings_.shape == ParticleShape::Sprite ? ParticlePath::PointSprite : ParticlePath::Pulled;
    }
    if (p == ParticlePath::PointSprite && settings_.shape != ParticleShape::Sprite) p = ParticlePath::Pulled;
    if (p == ParticlePath::Pulled) {
        // Buffer textures hold GL_MAX_TEXTURE_BUFFER_SIZE texels (13 per particle interleaved);
        // the limit was queried when the context was made (this runs during cull: no GL here).
        const std::uint64_t texels =
            std::uint64_t(settings_.capacity) * (settings_.layout == ParticleLayout::Split ? 1 : 13);
        if (texels > std::uint64_t(std::max(currentDeviceLimits().maxTextureBufferSize, 65536)))
            p = ParticlePath::Instanced;
    }
    return p;
}

const BaseShader& ParticleSystemNode::baseShader() const {
    const bool soft = settings_.softness > 0.0f;
    const int key =
        int(resolvedPath()) | int(settings_.shape) << 2 | (soft ? 1 << 4 : 0) | int(settings_.layout) << 5;
    if (!shader_ || shaderKey_ != key) {
        shader_ =
            std::make_unique<BaseShader>(drawShader(resolvedPath(), settings_.shape, soft, settings_.layout));
        shaderKey_ = key;
    }
    return *shader_;
}

FeatureMask ParticleSystemNode::features(const ResolvedState& state) const {
    FeatureMask f = FeatureNormals | FeatureTexCoords | FeatureVertexColor | FeatureWorldPosition;
    if (const Material* m = state.material.value ? state.material.value->get() : nullptr) {
        if (m->baseColorTexture) f |= FeatureBaseMap;
        if (m->alphaTexture) f |= FeatureAlphaMap;
        if (m->alphaCutoff) f |= FeatureAlphaMask;
        if (m->specular != glm::vec3(0.0f)) f |= FeatureSpecular;
    }
    return f;
}

BoundingSphere ParticleSystemNode::worldBound(const glm::mat4& model) const {
    lastModel_ = model;
    const particles::Emitter& e = settings_.emitter;
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (int i = 0; i < 4; ++i) {
        const glm::vec3 c(model * glm::vec4((i & 1 ? 0.5f : -0.5f) * e.size.x,
                                            (i & 2 ? 0.5f : -0.5f) * e.size.y, 0.0f, 1.0f));
        lo = glm::min(lo, c);
        hi = glm::max(hi, c);
    }
    // Reach of P0 + v·t + ½·a·t² over t ∈ [0, tmax] with v within v0 ± kv per axis.
    const float tmax = e.lifetime;
    float vmax = 0.0f;
    for (int c = 0; c < 3; ++c) {
        float dlo = 0.0f, dhi = 0.0f;
        for (const float v : {e.velocity[c] - e.velocitySpread, e.velocity[c] + e.velocitySpread}) {
            const float a = e.acceleration[c];
            float ts[3] = {0.0f, tmax, 0.0f};
            if (a != 0.0f) ts[2] = std::clamp(-v / a, 0.0f, tmax);
            for (const float t : ts) {
                const float d = v * t + 0.5f * a * t * t;
                dlo = std::min(dlo, d);
                dhi = std::max(dhi, d);
            }
            vmax = std::max(vmax, std::abs(v) + std::abs(a) * tmax);
        }
        lo[c] += dlo;
        hi[c] += dhi;
    }
    float margin = std::max(settings_.sizeStart, settings_.sizeEnd);
    if (settings_.shape == ParticleShape::Tetrahedron) margin *= 1.0f + settings_.stretch * vmax * 1.7321f;
    BoundingSphere s;
    s.center = 0.5f * (lo + hi);
    s.radius = 0.5f * glm::length(hi - lo) + margin;
    return s;
}

BoundingSphere ParticleSystemNode::computeBound() const {
    const glm::mat4 model = lastModel_;
    return worldBound(model).transformed(glm::inverse(model));
}

// The simulation step (seed: transform feedback from M to M') before the view's passes; soft
// particles read the view's one scene depth (the opaque items' depth) while they draw.
void ParticleSystemNode::setupFrame(FrameSetup& f) const {
    f.addPass(
        "particles: simulate", PassPhase::Compute, [](PassBuilder& b) { b.sideEffect(); },
        [pass = pass_](PassCommands& c) { pass->node.simulate(c, SimulationPart::Steps); });
    if (settings_.softness <= 0.0f) return;
    f.requestSceneDepth({.when = PassPhase::AfterOpaque});
    f.sampleInMainPass(std::string(resources::SceneDepth));
}

std::size_t ParticleSystemNode::triangleCount() const {
    if (resolvedPath() == ParticlePath::PointSprite) return 0; // points
    return std::size_t(gpu_ ? gpu_->capacity : 0) * std::size_t(trianglesPerParticle(settings_.shape));
}

void ParticleSystemNode::releaseGLObjects() {
    gpu_.reset();
    resetPending_ = true;
}

// The particle buffers: made, resized (keeping the live particles) or reset before the frame's
// passes; the simulation pass then only steps them.
void ParticleSystemNode::compile(Renderer& r) const {
    r.runCommands("particles: buffers",
                  [pass = pass_](PassCommands& c) { pass->node.simulate(c, SimulationPart::Buffers); });
}

void ParticleSystemNode::simulate(PassCommands& c, SimulationPart part) {
    const ParticleSettings& s = settings_;
    gl::Program& program = c.program(updateShader(s.layout));
    emitterMatrix_ = lastModel_;
    auto setCommon = [&](float dt) { setStepUniforms(program, s, emitterMatrix_, dt, step_); };
    // Sets up particles [first, first + count) of copy `c` by the start mode `init` (1..3).
    auto initialise = [&](int copy, int init, std::uint32_t first, std::uint32_t count) {
        setCommon(0.0f);
        program.set("u_init", init);
        program.setUnsigned("u_initFirst", first);
        program.setUnsigned("u_initCount", count);
        c.transformFeedback(program, gpu_->emptyVao.get(), gpu_->feedback(copy, first, count), first, count);
    };

    if (part != SimulationPart::Steps &&
        (!gpu_ || gpu_->capacity != s.capacity || gpu_->layout != s.layout)) {
        auto next = std::make_unique<Gpu>();
        if (!next->allocate(s.layout, s.capacity)) {
            c.warn("sgfx: ParticleSystemNode '" + name + "': the driver could not allocate " +
                   std::to_string(std::uint64_t(s.capacity) * 2 * kRecordBytes) + " bytes for " +
                   std::to_string(s.capacity) + " particles; keeping " +
                   std::to_string(gpu_ ? gpu_->capacity : 0));
            if (gpu_) {
                settings_.capacity = gpu_->capacity;
                settings_.layout = gpu_->layout;
            }
        } else {
            std::uint32_t kept = 0;
            if (gpu_ && !resetPending_) {
                // Keep the live particles: copy what fits, record by record across layouts.
                kept = std::min(gpu_->capacity, s.capacity);
                if (gpu_->layout == next->layout) {
                    for (int st = 0; st < next->streams(); ++st)
                        // GL: copies the live particles into the new buffers; no buffer command.
                        glCopyNamedBufferSubData(
                            gpu_->buffers[std::size_t(gpu_->current)][std::size_t(st)].get(),
                            next->buffers[0][std::size_t(st)].get(), 0, 0,
                            GLsizeiptr(kept) * next->stride(st));
                } else {
                    std::vector<ParticleRecord> records = readRecords();
                    records.resize(kept);
                    std::vector<std::uint8_t> bytes;
                    for (int st = 0; st < next->streams(); ++st) {
                        bytes.assign(std::size_t(kept) * std::size_t(next->stride(st)), 0);
                        for (std::uint32_t i = 0; i < kept; ++i) {
                            const auto* src = reinterpret_cast<const std::uint8_t*>(&records[i]);
                            const int from =
                                next->layout == ParticleLayout::Split ? (st == 0 ? 0 : 4 + 12 * st) : 0;
                            std::memcpy(bytes.data() + std::size_t(i) * std::size_t(next->stride(st)),
                                        src + from, std::size_t(next->stride(st)));
                        }
                        // GL: uploads the converted records; no buffer command.
                        glNamedBufferSubData(next->buffers[0][std::size_t(st)].get(), 0,
                                             GLsizeiptr(bytes.size()), bytes.data());
                    }
                }
            }
            gpu_ = std::move(next);
            // Particles added by growing are born at the steady rate (a reset sets all up below).
            if (!resetPending_ && kept < s.capacity)
                initialise(0, int(particles::StartMode::Ramp) + 1, kept, s.capacity - kept);
        }
    }
    if (part != SimulationPart::Steps && gpu_ && resetPending_) {
        step_ = 0;
        initialise(gpu_->current, int(s.start) + 1, 0, gpu_->capacity);
        resetPending_ = false;
    }
    if (part == SimulationPart::Buffers) return;
    lastFrame_.steps = std::uint32_t(gpu_ ? pendingSteps_.size() : 0);
    if (gpu_ && !pendingSteps_.empty()) {
        program.set("u_init", 0);
        Gpu& g = *gpu_;
        if (s.update != ParticleUpdate::Auto || g.capacity < kAutoMeasureFrom) {
            g.choice = ParticleFrameInfo{};
            g.choice.update = s.update != ParticleUpdate::Auto ? s.update : ParticleUpdate::TransformFeedback;
        } else if (!g.choice.measured) {
            g.measure(c, program, [&](gl::Program& p) {
                setStepUniforms(p, s, emitterMatrix_, pendingSteps_.front(), step_ + 1);
            });
        }
        for (const float dt : pendingSteps_) {
            ++step_;
            // One simulation step: M to M' (the seed's transform feedback, or the compute shader).
            g.step(c, program, g.choice.update,
                   [&](gl::Program& p) { setStepUniforms(p, s, emitterMatrix_, dt, step_); });
            g.current = 1 - g.current; // M' becomes M (seed: the pointers swap)
        }
        const std::uint32_t steps = lastFrame_.steps;
        lastFrame_ = g.choice;
        lastFrame_.steps = steps;
    }
    pendingSteps_.clear();
}

std::vector<ParticleRecord> ParticleSystemNode::readRecords() const {
    std::vector<ParticleRecord> out;
    if (!gpu_) return out;
    const Gpu& g = *gpu_;
    out.resize(g.capacity);
    if (g.layout == ParticleLayout::Interleaved) {
        // GL: reads the particles back (tests, layout changes); no buffer command.
        glGetNamedBufferSubData(g.buffers[std::size_t(g.current)][0].get(), 0,
                                GLsizeiptr(g.capacity) * kRecordBytes, out.data());
        return out;
    }
    std::vector<std::uint8_t> bytes;
    for (int st = 0; st < 4; ++st) {
        const int stride = g.stride(st);
        bytes.resize(std::size_t(g.capacity) * std::size_t(stride));
        // GL: reads one stream back (as above).
        glGetNamedBufferSubData(g.buffers[std::size_t(g.current)][std::size_t(st)].get(), 0,
                                GLsizeiptr(bytes.size()), bytes.data());
        const int to = st == 0 ? 0 : 4 + 12 * st;
        for (std::uint32_t i = 0; i < g.capacity; ++i)
            std::memcpy(reinterpret_cast<std::uint8_t*>(&out[i]) + to,
                        bytes.data() + std::size_t(i) * std::size_t(stride), std::size_t(stride));
    }
    return out;
}

void ParticleSystemNode::draw(Renderer& r, gl::Program& program, const RenderItem& item) const {
    if (!gpu_) return;
    const ParticleSettings& s = settings_;
    program.set("sgfx_model", glm::mat4(1.0f)); // particles are in world space
    program.set("u_size", glm::vec2(s.sizeStart, s.sizeEnd));
    program.set("u_colorStart", s.colorStart);
    program.set("u_colorEnd", s.colorEnd);
    program.set("u_tmax", s.emitter.lifetime);
    program.set("u_krot", s.emitter.rotationRange);
    program.set("u_stretch", s.shape == ParticleShape::Tetrahedron ? s.stretch : 0.0f);
    if (s.softness > 0.0f) {
        // Opaque particles (drawn before the scene depth exists), or a view without it, are hard.
        const bool soft = (item.features & FeatureBlend) &&
                          r.bindFrameResource(program, "sgfx_particleSceneDepth", resources::SceneDepth);
        program.set("sgfx_particleSoftness", soft ? s.softness : 0.0f);
    }
    const Gpu& g = *gpu_;
    const ParticlePath path = resolvedPath();
    if (path == ParticlePath::PointSprite) {
        // GL: point sprites: the size from the shader and the sprite's v upwards, states the
        // renderer's cache does not hold (set back right after), and the node's own draw.
        glEnable(GL_PROGRAM_POINT_SIZE);
        glPointParameteri(GL_POINT_SPRITE_COORD_ORIGIN, GL_LOWER_LEFT); // v up, as the quads' B
        glBindVertexArray(g.pointVao[std::size_t(g.current)].get());
        glDrawArrays(GL_POINTS, 0, GLsizei(g.capacity));
        glPointParameteri(GL_POINT_SPRITE_COORD_ORIGIN, GL_UPPER_LEFT);
        glDisable(GL_PROGRAM_POINT_SIZE);
    } else if (path == ParticlePath::GeometryShader) {
        // GL: the node's own points (vertex array and draw); no command draws a drawable's arrays.
        glBindVertexArray(g.pointVao[std::size_t(g.current)].get());
        glDrawArrays(GL_POINTS, 0, GLsizei(g.capacity));
    } else if (path == ParticlePath::Pulled) {
        for (int st = 0; st < g.streams(); ++st)
            r.bindTexture(kBufferUnit + unsigned(st),
                          g.bufferTextures[std::size_t(g.current)][std::size_t(st)].get());
        // GL: the node's own draw (vertex pulling, no attributes); no command draws a drawable's arrays.
        glBindVertexArray(g.emptyVao.get());
        glDrawArrays(GL_TRIANGLES, 0,
                     GLsizei(std::size_t(g.capacity) * 3 * std::size_t(trianglesPerParticle(s.shape))));
    } else {
        // GL: the node's own instanced draw; no command draws a drawable's arrays. One strip per
        // particle (4 or 6 vertices); the tetrahedron's four faces as triangles.
        glBindVertexArray(g.instanceVao[std::size_t(g.current)].get());
        if (s.shape == ParticleShape::Tetrahedron)
            glDrawArraysInstanced(GL_TRIANGLES, 0, 12, GLsizei(g.capacity));
        else
            glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, s.shape == ParticleShape::Hexagon ? 6 : 4,
                                  GLsizei(g.capacity));
    }
}

// ---------------------------------------------------------------- presets
std::shared_ptr<ParticleSystemNode> ParticleSystemNode::rain(glm::vec2 area, std::uint32_t count) {
    ParticleSettings s;
    s.capacity = count;
    s.emitter.size = area;
    s.emitter.velocity = {0.8f, 0.4f, -9.0f}; // terminal speed: drag balances gravity
    s.emitter.velocitySpread = 0.4f;
    s.emitter.acceleration = {0.0f, 0.0f, 0.0f};
    s.emitter.lifetime = 4.0f; // falls 36 m: put the emitter about that high
    s.shape = ParticleShape::Tetrahedron;
    s.sizeStart = s.sizeEnd = 0.02f;
    s.stretch = 2.5f;
    s.colorStart = s.colorEnd = {0.75f, 0.8f, 0.85f, 0.35f};
    return withState("rain", s, [](StateSet& st, Material& m) {
        st.blend.set(BlendMode::Alpha);
        m.ambient = glm::vec3(0.6f);
        m.diffuse = glm::vec4(0.6f, 0.65f, 0.7f, 1.0f);
        m.specular = glm::vec3(0.6f);
        m.shininess = 64.0f;
    });
}

std::shared_ptr<ParticleSystemNode> ParticleSystemNode::snow(glm::vec2 area, std::uint32_t count) {
    ParticleSettings s;
    s.capacity = count;
    s.emitter.size = area;
    s.emitter.velocity = {0.3f, 0.2f, -1.2f};
    s.emitter.velocitySpread = 0.35f;
    s.emitter.acceleration = {0.0f, 0.0f, 0.0f};
    s.emitter.rotationRange = 1.0f;
    s.emitter.rotationSpeed = 1.5f;
    s.emitter.lifetime = 25.0f; // falls 30 m
    s.shape = ParticleShape::Hexagon;
    s.sizeStart = s.sizeEnd = 0.03f;
    return withState("snow", s, [](StateSet&, Material& m) {
        m.ambient = glm::vec3(0.9f);
        m.diffuse = glm::vec4(0.9f, 0.92f, 0.95f, 1.0f);
    });
}

std::shared_ptr<ParticleSystemNode> ParticleSystemNode::leaves(glm::vec2 area, std::uint32_t count) {
    ParticleSettings s;
    s.capacity = count;
    s.emitter.size = area;
    s.emitter.velocity = {0.5f, 0.0f, -1.0f};
    s.emitter.velocitySpread = 0.6f;
    s.emitter.acceleration = {0.2f, 0.0f, 0.0f};
    s.emitter.rotationRange = 1.2f;
    s.emitter.rotationSpeed = 2.5f;
    s.emitter.lifetime = 10.0f;
    s.shape = ParticleShape::Quad;
    s.sizeStart = s.sizeEnd = 0.15f;
    return withState("leaves", s, [](StateSet&, Material& m) {
        m.baseColorTexture = leafTexture();
        m.alphaCutoff = 0.5f;
        m.ambient = glm::vec3(0.8f);
    });
}

std::shared_ptr<ParticleSystemNode> ParticleSystemNode::smoke(float sourceWidth, std::uint32_t count) {
    ParticleSettings s;
    s.capacity = count;
    s.emitter.size = {sourceWidth, sourceWidth};
    s.emitter.velocity = {0.0f, 0.0f, 1.5f};
    s.emitter.velocitySpread = 0.3f;
    s.emitter.acceleration = {0.3f, 0.0f, 0.2f}; // a light wind and buoyancy
    s.emitter.lifetime = 6.0f;
    s.sizeStart = 0.5f * sourceWidth + 0.2f;
    s.sizeEnd = 3.0f * sourceWidth + 1.0f;
    s.colorStart = {0.25f, 0.25f, 0.25f, 0.5f};
    s.colorEnd = {0.4f, 0.4f, 0.4f, 0.0f};
    s.softness = 1.0f;
    return withState("smoke", s, [](StateSet& st, Material& m) {
        st.blend.set(BlendMode::Premultiplied);
        m.baseColorTexture = puffTexture();
    });
}

std::shared_ptr<ParticleSystemNode> ParticleSystemNode::waterJet(glm::vec3 direction, float speed,
                                                                 std::uint32_t count) {
    if (!(glm::length(direction) > 0.0f) || !std::isfinite(glm::length(direction)))
        nodes::refuse("ParticleSystemNode::waterJet", "direction must be a finite non-zero vector");
    ParticleSettings s;
    s.capacity = count;
    s.emitter.size = {0.1f, 0.1f};
    s.emitter.velocity = glm::normalize(direction) * speed;
    s.emitter.velocitySpread = 0.08f * speed;
    s.emitter.acceleration = {0.0f, 0.0f, -9.81f};
    s.emitter.lifetime = 2.0f * speed / 9.81f;
    s.sizeStart = 0.06f;
    s.sizeEnd = 0.3f;
    s.colorStart = {0.6f, 0.7f, 0.8f, 0.35f};
    s.colorEnd = {0.6f, 0.7f, 0.8f, 0.05f};
    s.softness = 0.3f;
    return withState("water jet", s, [](StateSet& st, Material& m) {
        st.blend.set(BlendMode::Premultiplied);
        m.baseColorTexture = puffTexture();
        m.specular = glm::vec3(0.4f);
        m.shininess = 48.0f;
    });
}

std::shared_ptr<ParticleSystemNode> ParticleSystemNode::sparks(std::uint32_t count) {
    ParticleSettings s;
    s.capacity = count;
    s.emitter.size = {0.2f, 0.2f};
    s.emitter.velocity = {0.0f, 0.0f, 4.0f};
    s.emitter.velocitySpread = 3.0f;
    s.emitter.acceleration = {0.0f, 0.0f, -9.81f};
    s.emitter.lifetime = 1.2f;
    s.sizeStart = 0.05f;
    s.sizeEnd = 0.01f;
    s.colorStart = {1.0f, 1.0f, 1.0f, 1.0f};
    s.colorEnd = {1.0f, 1.0f, 1.0f, 0.0f};
    return withState("sparks", s, [](StateSet& st, Material& m) {
        st.blend.set(BlendMode::Additive); // commutes: no sorting needed
        m.ambient = glm::vec3(0.0f);
        m.diffuse = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
        m.emissive = glm::vec3(4.0f, 1.8f, 0.5f);
        m.baseColorTexture = puffTexture();
    });
}

} // namespace sgfx

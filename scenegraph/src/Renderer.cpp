#include "sgfx/Renderer.h"

#include "AntiAliasing.h"
#include "EmbeddedShaders.h"
#include "sgfx/Camera.h"
#include "sgfx/CullVisitor.h"
#include "sgfx/Drawable.h"
#include "sgfx/Geometry.h"
#include "sgfx/GraphicsContext.h"
#include "sgfx/TriangleSort.h"
#include "sgfx/gl/Objects.h"

#include <glad/gl.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <map>
#include <unordered_map>

namespace sgfx {

void FramePlan::add(std::shared_ptr<RenderPass> pass) {
    if (pass && std::find(passes.begin(), passes.end(), pass) == passes.end())
        passes.push_back(std::move(pass));
}

bool FramePlan::has(std::string_view name) const {
    return std::any_of(passes.begin(), passes.end(), [&](const auto& p) { return p->name() == name; });
}

namespace {

// std140 mirror of shaders/frame_block.glsl.
struct FrameBlock {
    glm::mat4 view, projection, viewProjection, invViewProjection;
    glm::vec4 eye, viewport, ambientLight, time;
    glm::ivec4 lightCount;
    glm::vec4 lightVector[8];
    glm::vec4 lightColor[8];
};
constexpr int kMaxLights = 8;

enum Unit : unsigned {
    BaseUnit = 0,
    AlphaUnit = 1,
    NormalUnit = 2,
    MetalRoughUnit = 3,
    OcclusionUnit = 4,
    EmissiveUnit = 5,
    FirstUserUnit = 6
};

GLenum glMode(PrimitiveMode m) {
    switch (m) {
    case PrimitiveMode::Points:
        return GL_POINTS;
    case PrimitiveMode::Lines:
        return GL_LINES;
    case PrimitiveMode::LineStrip:
        return GL_LINE_STRIP;
    case PrimitiveMode::Triangles:
        return GL_TRIANGLES;
    case PrimitiveMode::TriangleStrip:
        return GL_TRIANGLE_STRIP;
    case PrimitiveMode::TriangleFan:
        return GL_TRIANGLE_FAN;
    }
    return GL_TRIANGLES;
}

GLenum glCompare(CompareFunc f) {
    static const GLenum map[] = {GL_NEVER,   GL_LESS,     GL_EQUAL,  GL_LEQUAL,
                                 GL_GREATER, GL_NOTEQUAL, GL_GEQUAL, GL_ALWAYS};
    return map[std::size_t(f)];
}

GLint glFilter(Filter f) {
    switch (f) {
    case Filter::Nearest:
        return GL_NEAREST;
    case Filter::Linear:
        return GL_LINEAR;
    case Filter::LinearMipmapLinear:
        return GL_LINEAR_MIPMAP_LINEAR;
    }
    return GL_LINEAR;
}

GLint glWrap(Wrap w) {
    switch (w) {
    case Wrap::Repeat:
        return GL_REPEAT;
    case Wrap::ClampToEdge:
        return GL_CLAMP_TO_EDGE;
    case Wrap::MirroredRepeat:
        return GL_MIRRORED_REPEAT;
    }
    return GL_REPEAT;
}

template <class T>
void uploadAttribute(gl::GeometryBuffers& b, GLuint index, const std::vector<T>& data, GLint components) {
    if (data.empty()) {
        glDisableVertexArrayAttrib(b.vao.get(), index);
        return;
    }
    auto& buf = b.attributes[index];
    if (!buf) buf = gl::createBuffer();
    glNamedBufferData(buf.get(), GLsizeiptr(data.size() * sizeof(T)), data.data(), GL_STATIC_DRAW);
    glVertexArrayVertexBuffer(b.vao.get(), index, buf.get(), 0, sizeof(T));
    glVertexArrayAttribFormat(b.vao.get(), index, components, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(b.vao.get(), index, index);
    glEnableVertexArrayAttrib(b.vao.get(), index);
}

gl::GeometryBuffers& buffersFor(const Geometry& g) {
    auto& gpu = g.gpu();
    if (gpu && gpu->revision == g.revision()) return *gpu;
    g.validate();
    if (!gpu) {
        gpu = std::make_unique<gl::GeometryBuffers>();
        gpu->vao = gl::createVertexArray();
    }
    gl::GeometryBuffers& b = *gpu;
    uploadAttribute(b, 0, g.positions, 3);
    uploadAttribute(b, 1, g.normals, 3);
    uploadAttribute(b, 2, g.tangents, 4);
    uploadAttribute(b, 3, g.texcoords, 2);
    uploadAttribute(b, 4, g.colors, 4);
    uploadAttribute(b, 5, g.texcoords1, 2);
    // Instance matrices: one mat4 per instance as four vec4 attributes that advance per instance.
    b.instances = std::uint32_t(g.instances.size());
    for (GLuint column = 0; column < 4; ++column) {
        const GLuint location = 6 + column;
        if (g.instances.empty()) {
            glDisableVertexArrayAttrib(b.vao.get(), location);
            continue;
        }
        glVertexArrayAttribFormat(b.vao.get(), location, 4, GL_FLOAT, GL_FALSE, column * sizeof(glm::vec4));
        glVertexArrayAttribBinding(b.vao.get(), location, 6);
        glEnableVertexArrayAttrib(b.vao.get(), location);
    }
    if (!g.instances.empty()) {
        auto& buf = b.attributes[6];
        if (!buf) buf = gl::createBuffer();
        glNamedBufferData(buf.get(), GLsizeiptr(g.instances.size() * sizeof(glm::mat4)), g.instances.data(),
                          GL_STATIC_DRAW);
        glVertexArrayVertexBuffer(b.vao.get(), 6, buf.get(), 0, sizeof(glm::mat4));
        glVertexArrayBindingDivisor(b.vao.get(), 6, 1);
    }
    b.indexed = !g.indices.empty();
    if (b.indexed) {
        if (!b.indices) b.indices = gl::createBuffer();
        glNamedBufferData(b.indices.get(), GLsizeiptr(g.indices.size() * sizeof(std::uint32_t)),
                          g.indices.data(), GL_STATIC_DRAW);
        glVertexArrayElementBuffer(b.vao.get(), b.indices.get());
    }
    b.count = std::uint32_t(g.elementCount());
    b.mode = glMode(g.mode);
    b.revision = g.revision();
    return b;
}

GLuint textureFor(const Texture& t) {
    auto& gpu = t.gpu();
    if (gpu && gpu->revision == t.revision()) return gpu->object.get();
    const Image* img = t.image.get();
    if (!img && gpu) return gpu->object.get(); // a camera's render target
    if (std::uint8_t(t.minFilter) > std::uint8_t(Filter::LinearMipmapLinear) ||
        std::uint8_t(t.magFilter) > std::uint8_t(Filter::LinearMipmapLinear) ||
        std::uint8_t(t.wrapS) > std::uint8_t(Wrap::MirroredRepeat) ||
        std::uint8_t(t.wrapT) > std::uint8_t(Wrap::MirroredRepeat))
        throw std::invalid_argument("sgfx: texture has an invalid Filter or Wrap value");
    if (!img) throw std::invalid_argument("sgfx: texture has no image (and no camera renders into it)");
    if (img->width <= 0 || img->height <= 0 || img->channels < 1 || img->channels > 4)
        throw std::invalid_argument("sgfx: texture image is " + std::to_string(img->width) + "x" +
                                    std::to_string(img->height) + " with " + std::to_string(img->channels) +
                                    " channels; need positive sides and 1..4 channels");
    if (img->pixels.size() < std::size_t(img->width) * img->height * img->channels)
        throw std::invalid_argument("sgfx: texture image data (" + std::to_string(img->pixels.size()) +
                                    " bytes) is smaller than width*height*channels");
    if (!gpu) gpu = std::make_unique<gl::Texture>();
    gpu->object = gl::createTexture(GL_TEXTURE_2D);
    gpu->target = GL_TEXTURE_2D;
    const GLuint name = gpu->object.get();
    static const GLenum linearFormats[] = {GL_R8, GL_RG8, GL_RGB8, GL_RGBA8};
    static const GLenum srgbFormats[] = {GL_R8, GL_RG8, GL_SRGB8, GL_SRGB8_ALPHA8};
    static const GLenum dataFormats[] = {GL_RED, GL_RG, GL_RGB, GL_RGBA};
    const int c = img->channels - 1;
    const bool mip = t.minFilter == Filter::LinearMipmapLinear;
    const int levels = mip ? 1 + int(std::floor(std::log2(std::max(img->width, img->height)))) : 1;
    glTextureStorage2D(name, levels, (t.srgb ? srgbFormats : linearFormats)[c], img->width, img->height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(name, 0, 0, 0, img->width, img->height, dataFormats[c], GL_UNSIGNED_BYTE,
                        img->pixels.data());
    if (mip) glGenerateTextureMipmap(name);
    glTextureParameteri(name, GL_TEXTURE_MIN_FILTER, glFilter(t.minFilter));
    glTextureParameteri(name, GL_TEXTURE_MAG_FILTER, t.magFilter == Filter::Nearest ? GL_NEAREST : GL_LINEAR);
    glTextureParameteri(name, GL_TEXTURE_WRAP_S, glWrap(t.wrapS));
    glTextureParameteri(name, GL_TEXTURE_WRAP_T, glWrap(t.wrapT));
    gpu->revision = t.revision();
    return name;
}

// Where the renderer is, so a GL error names its call site: the pass, and the item being drawn.
struct DebugLog {
    std::string_view stage = "outside a frame";
    const RenderItem* item = nullptr;
    const gl::Program* program = nullptr;
    std::vector<std::string> messages;

    void add(std::string_view message) {
        if (messages.size() >= 64) return; // an error storm: the first ones say enough
        std::string site = "[" + std::string(stage) + "]";
        if (item)
            site += " drawing '" +
                    (item->node().name.empty() ? std::string("<unnamed>") : item->node().name) + "'";
        if (program) site += " with " + program->description();
        messages.push_back(site + ": " + std::string(message));
    }
};

void GLAPIENTRY onDebugMessage(GLenum source, GLenum type, GLuint, GLenum severity, GLsizei,
                               const GLchar* message, const void* user) {
    // Compiler messages already become a ShaderError with translated lines.
    if (source == GL_DEBUG_SOURCE_SHADER_COMPILER) return;
    // Synchronous output: this runs inside the offending call, so the recorded site is exact.
    if (type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH)
        static_cast<DebugLog*>(const_cast<void*>(user))->add(message);
}

// Enum values outside their range (a cast from bad data) would index GL tables out of bounds.
void validateEnums(const ResolvedState& st, const RenderItem& item) {
    const Node& n = item.node();
    auto bad = [&](const char* what, int v) {
        throw std::invalid_argument("sgfx: state of '" +
                                    (n.name.empty() ? std::string("<unnamed>") : n.name) +
                                    "' has an invalid " + what + " value " + std::to_string(v));
    };
    if (st.blend.value && std::uint8_t(*st.blend.value) > std::uint8_t(BlendMode::Multiply))
        bad("BlendMode", int(*st.blend.value));
    if (st.cullFace.value && std::uint8_t(*st.cullFace.value) > std::uint8_t(CullFace::Front))
        bad("CullFace", int(*st.cullFace.value));
    if (st.depth.value && std::uint8_t(st.depth.value->func) > std::uint8_t(CompareFunc::Always))
        bad("CompareFunc", int(st.depth.value->func));
    if (item.geometry && std::uint8_t(item.geometry->mode) > std::uint8_t(PrimitiveMode::TriangleFan))
        bad("PrimitiveMode", int(item.geometry->mode));
}

} // namespace

// Redundant-state filter; every real change is counted as a state change.
struct Renderer::Impl {
    gl::RenderTarget scene;
    struct CameraTarget {
        std::weak_ptr<Node> owner;
        gl::RenderTarget target;
    };
    std::unordered_map<const Camera*, CameraTarget> cameraTargets;
    // Per-triangle back-to-front orders, one per (mesh, view); dropped when the mesh dies, is
    // edited, or was not drawn for a while.
    struct SortedMesh {
        std::weak_ptr<const Node> owner;
        std::uint64_t revision = 0;
        std::uint64_t lastUse = 0;
        std::unique_ptr<TriangleDepthSort> sort;
        gl::BufferObject indices;
    };
    std::map<std::pair<const Geometry*, const Camera*>, SortedMesh> sortedMeshes;
    const Camera* camera = nullptr;                           // the view being drawn
    std::unordered_map<const Camera*, aa::ViewState> aaViews; // per camera, dropped with it
    std::vector<std::string> warnings;
    std::uint64_t frames = 0;
    // RendererOptions::timePasses: queries of this frame, read at its end.
    std::vector<std::pair<std::string, gl::QueryObject>> timers;
    void beginTimer(bool on, std::string name) {
        if (!on) return;
        timers.emplace_back(std::move(name), gl::createQuery(GL_TIME_ELAPSED));
        glBeginQuery(GL_TIME_ELAPSED, timers.back().second.get());
    }
    void endTimer(bool on) {
        if (on) glEndQuery(GL_TIME_ELAPSED);
    }
    gl::RenderTarget* current = &scene; // target of the view being drawn
    gl::BufferObject frameUbo;
    // Model matrices of automatic instance batches (Renderer::drawBatch), a shader storage
    // buffer at kBatchBinding.
    gl::BufferObject batchModels;
    std::vector<glm::mat4> batchScratch;
    std::uint64_t submittedTriangles = 0; // FrameStats::triangles at the last glFlush
    gl::VertexArrayObject emptyVao;       // full-screen passes take their vertices from gl_VertexID
    DebugLog log;

    GLuint program = 0;
    int blend = -1;
    int cull = -1;
    DepthState depth{};
    bool depthKnown = false;
    std::array<GLuint, 16> units{};
    std::size_t* stateChanges = nullptr;

    void bindTexture(unsigned unit, GLuint name) {
        if (units[unit] == name) return;
        glBindTextureUnit(unit, name);
        units[unit] = name;
        ++*stateChanges;
    }
    void setBlend(BlendMode m) {
        if (blend == int(m)) return;
        blend = int(m);
        ++*stateChanges;
        if (m == BlendMode::Off) {
            glDisable(GL_BLEND);
            return;
        }
        glEnable(GL_BLEND);
        glBlendEquation(GL_FUNC_ADD);
        switch (m) {
        case BlendMode::Alpha:
            glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
            break;
        case BlendMode::Premultiplied:
            glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
            break;
        case BlendMode::Additive:
            glBlendFunc(GL_SRC_ALPHA, GL_ONE);
            break;
        case BlendMode::Multiply:
            glBlendFunc(GL_DST_COLOR, GL_ZERO);
            break;
        case BlendMode::Off:
            break;
        }
    }
    void setCull(CullFace c) {
        if (cull == int(c)) return;
        cull = int(c);
        ++*stateChanges;
        if (c == CullFace::None) {
            glDisable(GL_CULL_FACE);
            return;
        }
        glEnable(GL_CULL_FACE);
        glCullFace(c == CullFace::Back ? GL_BACK : GL_FRONT);
    }
    void setDepth(const DepthState& d) {
        if (depthKnown && depth == d) return;
        depth = d;
        depthKnown = true;
        ++*stateChanges;
        if (d.test)
            glEnable(GL_DEPTH_TEST);
        else
            glDisable(GL_DEPTH_TEST);
        glDepthMask(d.write ? GL_TRUE : GL_FALSE);
        glDepthFunc(glCompare(d.func));
    }
    void invalidate() {
        program = 0;
        blend = cull = -1;
        depthKnown = false;
        units.fill(0);
    }
};

Renderer::Renderer(GraphicsContext& context, Options options)
    : context_(context)
    , options_(options)
    , impl_(std::make_unique<Impl>()) {
    context_.makeCurrent();
    impl_->stateChanges = &stats_.stateChanges;
    impl_->frameUbo = gl::createBuffer();
    impl_->emptyVao = gl::createVertexArray();
    glNamedBufferData(impl_->frameUbo.get(), sizeof(FrameBlock), nullptr, GL_DYNAMIC_DRAW);
#ifdef SGFX_GL_DEBUG
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(onDebugMessage, &impl_->log);
#endif
    // Defaults for attributes a geometry leaves out (context state, not VAO state).
    glVertexAttrib3f(1, 0.0f, 0.0f, 1.0f);
    glVertexAttrib4f(2, 1.0f, 0.0f, 0.0f, 1.0f);
    glVertexAttrib2f(3, 0.0f, 0.0f);
    glVertexAttrib4f(4, 1.0f, 1.0f, 1.0f, 1.0f);
}

Renderer::~Renderer() {
    context_.makeCurrent();
#ifdef SGFX_GL_DEBUG
    glDebugMessageCallback(nullptr, nullptr);
#endif
    composer_.clear();
}

gl::RenderTarget& Renderer::sceneTarget() {
    return impl_->scene;
}

gl::RenderTarget& Renderer::currentTarget() {
    return *impl_->current;
}

void Renderer::bindTexture(unsigned unit, unsigned texture) {
    if (unit >= impl_->units.size())
        throw std::invalid_argument("sgfx: texture unit " + std::to_string(unit) + " is out of range");
    impl_->bindTexture(unit, texture);
}

void Renderer::setBlend(BlendMode mode) {
    impl_->setBlend(mode);
}

void Renderer::resetStateCache() {
    impl_->invalidate();
}

gl::Program& Renderer::gbufferProgram() {
    static const BaseShader base{"gbuffer_flat", "gbuffer_flat.vert",
                                 std::string(shaders::embedded("gbuffer_flat.vert")), "gbuffer_flat.frag",
                                 std::string(shaders::embedded("gbuffer_flat.frag"))};
    return composer_.program(base, {}, 0);
}

gl::Program& Renderer::depthOnlyProgram() {
    static const BaseShader base{"depth_only", "depth_only.vert",
                                 std::string(shaders::embedded("depth_only.vert")), "depth_only.frag",
                                 std::string(shaders::embedded("depth_only.frag"))};
    return composer_.program(base, {}, 0);
}

void Renderer::drawFullscreen(gl::Program& program, const DepthState& depth) {
    Impl& s = *impl_;
    s.setDepth(depth);
    s.setCull(CullFace::None);
    if (program.get() != s.program) {
        glUseProgram(program.get());
        s.program = program.get();
        ++stats_.programChanges;
        ++stats_.stateChanges;
    }
    glBindVertexArray(s.emptyVao.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    ++stats_.drawCalls;
}

void Renderer::warn(std::string message) {
    if (std::find(impl_->warnings.begin(), impl_->warnings.end(), message) == impl_->warnings.end())
        impl_->warnings.push_back(std::move(message));
}

std::vector<std::string> Renderer::takeWarnings() {
    return std::exchange(impl_->warnings, {});
}

std::vector<std::string> Renderer::takeGlErrors() {
    // Errors the debug output did not report (no KHR_debug, or SGFX_GL_DEBUG off).
    for (GLenum e; (e = glGetError()) != GL_NO_ERROR;) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "glGetError: 0x%04x", unsigned(e));
        impl_->log.add(buf);
    }
    return std::exchange(impl_->log.messages, {});
}

void Renderer::render(Camera& camera, double time, std::uint64_t frameNumber) {
    using clock = std::chrono::steady_clock;
    context_.assertOwnerThread();
    const auto t0 = clock::now();
    stats_ = {};
    impl_->submittedTriangles = 0;
    frame_.time = time;
    frame_.frameNumber = frameNumber;
    // Forget the targets of render-to-texture cameras that no longer exist.
    std::erase_if(impl_->cameraTargets, [](const auto& e) { return e.second.owner.expired(); });
    std::erase_if(impl_->aaViews, [](const auto& e) { return e.second.owner.expired(); });
    ++impl_->frames;
    std::erase_if(impl_->sortedMeshes, [&](const auto& e) {
        return e.second.owner.expired() || impl_->frames - e.second.lastUse > 600;
    });
    impl_->timers.clear();
    renderView(camera, impl_->scene, queue_, plan_, 0);
    impl_->log.stage = "outside a frame";
    for (auto& [name, query] : impl_->timers) {
        GLuint64 ns = 0;
        glGetQueryObjectui64v(query.get(), GL_QUERY_RESULT, &ns);
        stats_.passTimes.push_back({name, double(ns) * 1e-6});
    }
    impl_->timers.clear();
    if (!options_.glErrors) {
        const char* env = std::getenv("SGFX_GL_ERRORS");
        options_.glErrors = env && std::string_view(env) == "throw" ? RendererOptions::GlErrorPolicy::Throw
                                                                    : RendererOptions::GlErrorPolicy::Collect;
    }
    if (*options_.glErrors == RendererOptions::GlErrorPolicy::Throw) {
        const std::vector<std::string> errors = takeGlErrors();
        if (!errors.empty()) {
            std::string what = "sgfx: GL errors in frame " + std::to_string(frameNumber) + ":";
            for (const std::string& e : errors)
                what += "\n  " + e;
            throw std::runtime_error(what);
        }
    }
    if (camera.renderTarget) copyToTexture(impl_->scene, *camera.renderTarget);
    stats_.drawMs = std::chrono::duration<double, std::milli>(clock::now() - t0).count() - stats_.cullMs;
}

void Renderer::renderView(Camera& camera, gl::RenderTarget& target, RenderQueue& queue, FramePlan& plan,
                          int depth) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    const Viewport vp = camera.viewport;
    static const GLenum formats[] = {GL_SRGB8_ALPHA8, GL_RGBA16F, GL_RGBA32F};
    const auto colorTarget = std::size_t(options_.colorTarget);
    if (colorTarget >= std::size(formats))
        throw std::invalid_argument("sgfx: RendererOptions::colorTarget has an invalid value " +
                                    std::to_string(colorTarget));
    if (std::uint8_t(options_.lighting) > std::uint8_t(RendererOptions::Lighting::PerVertex))
        throw std::invalid_argument("sgfx: RendererOptions::lighting has an invalid value " +
                                    std::to_string(int(options_.lighting)));
    target.resize(vp.width, vp.height, formats[colorTarget]);

    // ---- cull
    queue.clear();
    plan.clear();
    CullVisitor cull(camera, queue, &plan);
    cull.run(camera);
    queue.sort();
    stats_.culledNodes += cull.culledNodes;
    stats_.items += queue.size();
    stats_.cullMs += std::chrono::duration<double, std::milli>(clock::now() - t0).count();

    // ---- nested render-to-texture cameras first (each with its own queue and target)
    constexpr int kMaxCameraDepth = 4; // a camera seen inside its own subgraph stops here
    if (depth < kMaxCameraDepth) {
        for (Camera* sub : queue.subCameras) {
            auto& entry = impl_->cameraTargets[sub];
            entry.owner = sub->weak_from_this();
            RenderQueue subQueue;
            FramePlan subPlan;
            renderView(*sub, entry.target, subQueue, subPlan, depth + 1);
            copyToTexture(entry.target, *sub->renderTarget);
        }
    }

    glm::mat4 projection = camera.projectionMatrix;
    if (camera.computeNearFar && camera.perspective() && cull.computedFar > 0.0f) {
        const float zFar = cull.computedFar * 1.01f;
        const float zNear = std::max(cull.computedNear * 0.99f, zFar * camera.nearFarRatio);
        projection = glm::perspective(glm::radians(camera.fovy()), vp.aspect(), zNear, zFar);
    }
    // ---- anti-aliasing: where the view is drawn (a multisample or larger target, else the
    // view's own), and TAA's sub-pixel jitter
    aa::ViewState& aa = impl_->aaViews[&camera];
    if (aa.owner.expired()) aa = {}, aa.owner = camera.weak_from_this();
    aa::begin(aa, camera, projection * camera.viewMatrix, target.width, target.height, impl_->warnings);
    gl::RenderTarget& draw = aa::drawTarget(aa, target);
    projection = aa.jitter * projection;
    frame_.view = camera.viewMatrix;
    frame_.projection = projection;
    frame_.viewProjection = projection * camera.viewMatrix;
    frame_.inverseViewProjection = glm::inverse(frame_.viewProjection);
    frame_.eye = glm::vec3(glm::inverse(camera.viewMatrix)[3]);
    frame_.width = draw.width;
    frame_.height = draw.height;

    // ---- per-view uniforms, shared by every program through binding 0
    FrameBlock fb{};
    fb.view = frame_.view;
    fb.projection = frame_.projection;
    fb.viewProjection = frame_.viewProjection;
    fb.invViewProjection = frame_.inverseViewProjection;
    fb.eye = glm::vec4(frame_.eye, 1.0f);
    fb.viewport = glm::vec4(0.0f, 0.0f, float(draw.width), float(draw.height));
    fb.ambientLight = glm::vec4(queue.ambientLight, 0.0f);
    fb.time = glm::vec4(float(frame_.time), 0, 0, 0);
    const int nLights = std::min<int>(int(queue.lights.size()), kMaxLights);
    fb.lightCount = glm::ivec4(nLights, 0, 0, 0);
    for (int i = 0; i < nLights; ++i) {
        fb.lightVector[i] = queue.lights[std::size_t(i)].vector;
        fb.lightColor[i] = glm::vec4(queue.lights[std::size_t(i)].color, 0.0f);
    }
    viewFeatures_ = (std::uint32_t(nLights) << FeatureLightCountShift) |
                    (options_.lighting == RendererOptions::Lighting::PerVertex ? FeatureVertexLighting : 0u);
    for (int i = 0; i < nLights; ++i)
        if (queue.lights[std::size_t(i)].vector.w != 0.0f) viewFeatures_ |= FeaturePointLights;
    glNamedBufferSubData(impl_->frameUbo.get(), 0, sizeof fb, &fb);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, impl_->frameUbo.get());
    impl_->invalidate();
    current_ = &queue;
    impl_->current = &draw;
    impl_->camera = &camera;

    runPasses(plan, PassStage::Compute, draw);
    runPasses(plan, PassStage::PrePass, draw);

    // ---- main pass: linear shading, sRGB-encoded once by the framebuffer on write
    glBindFramebuffer(GL_FRAMEBUFFER, draw.fbo.get());
    glViewport(0, 0, draw.width, draw.height);
    glEnable(GL_FRAMEBUFFER_SRGB);
    glDepthMask(GL_TRUE);
    impl_->depthKnown = false;
    const glm::vec4 cc = camera.clearColor;
    glClearColor(cc.r, cc.g, cc.b, cc.a);
    const GLbitfield mask = (camera.clearColorEnabled ? GL_COLOR_BUFFER_BIT : 0u) |
                            (camera.clearDepthEnabled ? GL_DEPTH_BUFFER_BIT : 0u);
    if (mask) glClear(mask);
    gl::QueryObject fragments;
    if (options_.countFragments) {
        fragments = gl::createQuery(GL_SAMPLES_PASSED);
        glBeginQuery(GL_SAMPLES_PASSED, fragments.get());
    }
    impl_->log.stage = "main pass";
    const bool timing = options_.timePasses;
    impl_->beginTimer(timing, "main: opaque");
    drawItems(queue.opaque);
    impl_->endTimer(timing);
    runPasses(plan, PassStage::AfterOpaque, draw);
    runPasses(plan, PassStage::Transparent, draw);
    impl_->log.stage = "main pass";
    impl_->beginTimer(timing, "main: transparent");
    drawItems(queue.transparent);
    impl_->endTimer(timing);
    if (fragments) {
        glEndQuery(GL_SAMPLES_PASSED);
        GLuint64 n = 0;
        glGetQueryObjectui64v(fragments.get(), GL_QUERY_RESULT, &n);
        stats_.fragments += n;
    }

    // ---- down to the view's own single-sample target; post passes read its colour and depth
    if (&draw != &target) {
        impl_->log.stage = "anti-aliasing resolve";
        impl_->beginTimer(options_.timePasses, "aa resolve");
        aa::resolve(*this, aa, draw, target);
        impl_->endTimer(options_.timePasses);
        impl_->current = &target;
        frame_.width = target.width;
        frame_.height = target.height;
        const glm::vec4 viewport(0.0f, 0.0f, float(target.width), float(target.height));
        glNamedBufferSubData(impl_->frameUbo.get(), offsetof(FrameBlock, viewport), sizeof viewport,
                             &viewport);
    }
    runPasses(plan, PassStage::Post, target);
    impl_->log.stage = "anti-aliasing";
    const bool postAa =
        aa.settings.mode == AntiAliasing::Mode::Fxaa || aa.settings.mode == AntiAliasing::Mode::Taa;
    impl_->beginTimer(options_.timePasses && postAa,
                      aa.settings.mode == AntiAliasing::Mode::Fxaa ? "aa fxaa" : "aa taa");
    aa::finish(*this, aa, target);
    impl_->endTimer(options_.timePasses && postAa);
    current_ = &queue_;
    impl_->current = &impl_->scene;
}

void Renderer::runPasses(FramePlan& plan, PassStage stage, gl::RenderTarget& target) {
    for (auto& p : plan.passes) {
        if (p->stage() != stage) continue;
        impl_->log.stage = p->name();
        impl_->beginTimer(options_.timePasses, std::string(p->name()));
        p->execute(*this);
        impl_->endTimer(options_.timePasses);
        impl_->invalidate(); // the pass may have changed GL state behind the cache
        // Back to the view's target and sRGB encoding, whatever the pass bound.
        glBindFramebuffer(GL_FRAMEBUFFER, target.fbo.get());
        glViewport(0, 0, target.width, target.height);
        glEnable(GL_FRAMEBUFFER_SRGB);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    }
}

void Renderer::copyToTexture(const gl::RenderTarget& from, const Texture& to) {
    auto& gpu = to.gpu();
    GLint w = 0, h = 0;
    if (gpu && gpu->object) {
        glGetTextureLevelParameteriv(gpu->object.get(), 0, GL_TEXTURE_WIDTH, &w);
        glGetTextureLevelParameteriv(gpu->object.get(), 0, GL_TEXTURE_HEIGHT, &h);
    }
    GLint format = 0;
    if (gpu && gpu->object)
        glGetTextureLevelParameteriv(gpu->object.get(), 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
    if (!gpu || w != from.width || h != from.height || GLenum(format) != from.colorFormat || to.image) {
        if (!gpu) gpu = std::make_unique<gl::Texture>();
        gpu->object = gl::createTexture(GL_TEXTURE_2D);
        gpu->target = GL_TEXTURE_2D;
        glTextureStorage2D(gpu->object.get(), 1, from.colorFormat, from.width, from.height);
        glTextureParameteri(gpu->object.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR); // one level only
        glTextureParameteri(gpu->object.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(gpu->object.get(), GL_TEXTURE_WRAP_S, glWrap(to.wrapS));
        glTextureParameteri(gpu->object.get(), GL_TEXTURE_WRAP_T, glWrap(to.wrapT));
    }
    gpu->revision = to.revision();
    glCopyImageSubData(from.color.get(), GL_TEXTURE_2D, 0, 0, 0, 0, gpu->object.get(), GL_TEXTURE_2D, 0, 0, 0,
                       0, from.width, from.height, 1);
}

void Renderer::drawItems(std::span<const RenderItem> items, gl::Program* override, DrawMode mode) {
    Impl& s = *impl_;
    if (std::uint8_t(mode) > std::uint8_t(DrawMode::GBuffer))
        throw std::invalid_argument("sgfx: Renderer::drawItems: invalid DrawMode " +
                                    std::to_string(int(mode)));
    // Geometry-only passes: no effects, no blending, depth test and write for every item.
    const bool depthOnly = mode == DrawMode::DepthOnly || mode == DrawMode::GBuffer;
    if (depthOnly) {
        if (mode == DrawMode::DepthOnly) glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        s.setBlend(BlendMode::Off);
        s.setDepth(DepthState{});
    }
    gl::Program* program = override;
    ProgramKey programKey = ProgramKey::none();
    const ResolvedState* state = nullptr;
    const Material* material = nullptr;
    std::uint32_t effectSet = ~0u;
    std::uint32_t programExtra = 0; // FeatureBatched when the current program draws batches
    // The model matrices of every batch of this list, uploaded at once (one buffer write per
    // list: writing per batch, or changing vertex layouts per batch, stalls llvmpipe).
    s.batchScratch.clear();
    for (std::size_t i = 0, run = 1; i < items.size(); i += run)
        if ((run = batchLength(items.subspan(i))) > 1)
            for (const RenderItem& it : items.subspan(i, run))
                s.batchScratch.push_back(it.model);
    bool batchesBound = s.batchScratch.empty();
    std::size_t batchBase = 0;
    if (!s.batchScratch.empty()) {
        if (!s.batchModels) s.batchModels = gl::createBuffer();
        glNamedBufferData(s.batchModels.get(), GLsizeiptr(s.batchScratch.size() * sizeof(glm::mat4)),
                          s.batchScratch.data(), GL_STREAM_DRAW);
    }
    std::vector<const ShaderSnippet*> snippets;
    for (std::size_t i = 0, run = 1; i < items.size(); i += run) {
        if (options_.submitTriangles && stats_.triangles - s.submittedTriangles >= options_.submitTriangles) {
            glFlush(); // llvmpipe's threads rasterise what is binned while this thread goes on
            s.submittedTriangles = stats_.triangles;
        }
        const RenderItem& item = items[i];
        s.log.item = &item;
        // Repeated meshes: neighbours in the sorted list that differ only in their matrix are
        // drawn as one instanced batch (the trees and buildings of a simulator scene).
        run = batchLength(items.subspan(i));
        if (getenv("SGFX_DBG") && s.frames == 5) fprintf(stderr, "DRAW %s run %zu %s\n", item.node().name.c_str(), run, item.geometry ? item.geometry->name.c_str() : "drawable");
        const std::uint32_t extra = run > 1 ? FeatureBatched : 0u;
        bool programChanged = false;
        if (item.drawable) {
            // Its own base shader: composed with the effects in the main pass; in depth and
            // G-buffer passes its plain or G-buffer variant.
            const ProgramKey key =
                depthOnly ? item.programKey.with(ProgramKey::Mode, std::uint64_t(mode)) : item.programKey;
            if (key != programKey) {
                snippets.clear();
                if (!depthOnly)
                    for (const EffectNode* e : current_->effectSets[item.effectSet].effects)
                        snippets.push_back(&e->snippet());
                const std::uint32_t lighting = FeatureBlend | FeatureBlendKindMask | FeatureSpecular |
                                               FeatureVertexLighting | FeatureLightCountMask |
                                               FeaturePointLights;
                const std::uint32_t features = mode == DrawMode::GBuffer
                                                   ? (item.features & ~lighting) | FeatureGBuffer
                                               : mode == DrawMode::DepthOnly ? item.features & ~FeatureBlend
                                                                             : item.features | viewFeatures_;
                program = &composer_.program(item.drawable->baseShader(), snippets,
                                             features | FeatureWorldPosition);
                programKey = key;
                programChanged = true;
            }
        } else if (!override && (item.programKey != programKey || extra != programExtra)) {
            const EffectSet& set = current_->effectSets[item.effectSet];
            snippets.clear();
            for (const EffectNode* e : set.effects)
                snippets.push_back(&e->snippet());
            const std::uint32_t features =
                item.program()
                    ? (snippets.empty() ? 0u : item.features) // a foreign wrap uses the blend bits
                    : ShaderComposer::withWorldPosition(
                          item.features | viewFeatures_ | extra,
                          std::any_of(snippets.begin(), snippets.end(), [](const ShaderSnippet* sn) {
                              return !sn->vertexCode.empty() || !sn->ambientCode.empty() ||
                                     !sn->colorCode.empty();
                          }));
            program = &composer_.program(item.program(), snippets, features);
            programKey = item.programKey;
            programExtra = extra;
            programChanged = true;
        } else if (depthOnly && override) {
            // Alpha-masked and instanced built-in materials keep their cut-outs and instances in
            // depth passes: their own
            // variant (no effects) with colour writes off; everything else the depth-only program.
            // G-buffer passes: every built-in material's G-buffer variant (normal maps, cut-outs).
            const bool builtin = !item.program();
            const bool own = builtin && (mode == DrawMode::GBuffer || extra ||
                                         (item.features & (FeatureAlphaMask | FeatureInstanced)));
            const std::uint32_t lighting = FeatureBlend | FeatureBlendKindMask | FeatureSpecular |
                                           FeatureVertexLighting | FeatureLightCountMask | FeaturePointLights;
            const std::uint32_t features =
                mode == DrawMode::GBuffer
                    ? (item.features & ~lighting) | extra | FeatureGBuffer | FeatureWorldPosition
                    : ShaderComposer::withWorldPosition(
                          (item.features & ~FeatureBlend) | extra | viewFeatures_, false);
            // The item's own built-in variant, or none() for the override program.
            const ProgramKey key =
                own ? ProgramKey::make(ProgramSource::Builtin, 0, 0, features, mode) : ProgramKey::none();
            if (key != programKey) {
                program = own ? &composer_.program(nullptr, {}, features) : override;
                programKey = key;
                programChanged = true;
            }
        }
        s.log.program = program;
        if (program->get() != s.program) {
            glUseProgram(program->get());
            s.program = program->get();
            ++stats_.programChanges;
            ++stats_.stateChanges;
            programChanged = true;
        }
        if (programChanged) {
            state = nullptr;
            material = nullptr;
            effectSet = ~0u;
        }
        if (!depthOnly && item.effectSet != effectSet) {
            effectSet = item.effectSet;
            const DrawContext ctx{frame_, item};
            for (const EffectNode* e : current_->effectSets[effectSet].effects)
                e->applyUniforms(*program, ctx);
        }
        if (item.state != state) {
            state = item.state;
            validateEnums(*state, item);
            if (mode == DrawMode::Main) {
                s.setBlend(state->blendMode());
                DepthState d = state->depth.value.value_or(DepthState{});
                // Blended surfaces do not hide what is drawn after them, unless asked to.
                if (item.features & FeatureBlend)
                    d.write = d.write && state->transparency.value && state->transparency.value->writeDepth;
                s.setDepth(d);
            }
            unsigned unit = FirstUserUnit;
            for (const auto& [name, tex] : state->textures) {
                if (!tex.value || !*tex.value || unit >= kEffectTextureUnit) continue;
                s.bindTexture(unit, textureFor(**tex.value));
                program->set(name, int(unit++));
            }
            for (const auto& [name, value] : state->uniforms)
                if (value.value) program->set(name, *value.value);
        }
        const Material* m = state->material.value ? state->material.value->get() : nullptr;
        if (m != material) {
            material = m;
            if (m) {
                m->validate(); // NaN or negative colours would reach pixels
                program->set("sgfx_matAmbient", m->ambient);
                program->set("sgfx_matDiffuse", m->diffuse);
                program->set("sgfx_matSpecular", m->specular);
                program->set("sgfx_matShininess", m->shininess);
                program->set("sgfx_matEmissive", m->emissive);
                program->set("sgfx_alphaCutoff", m->alphaCutoff.value_or(0.0f));
                if (m->model == ShadingModel::MetallicRoughness) {
                    program->set("sgfx_matMetallicRoughness", glm::vec2(m->metallic, m->roughness));
                    // The Gouraud option's specular lobe: the Blinn-Phong exponent of the same width.
                    const float a = std::max(m->roughness * m->roughness, 0.03f);
                    program->set("sgfx_matShininess", std::min(2.0f / (a * a) - 2.0f, 4096.0f));
                }
                program->set("sgfx_normalScale", m->normalScale);
                program->set("sgfx_occlusionStrength", m->occlusionStrength);
                if (item.features & FeatureUvTransform)
                    for (std::size_t k = 0; k < kMaterialMapCount; ++k) {
                        const std::string index = "[" + std::to_string(k) + "]";
                        program->set("sgfx_uvTransform" + index, m->mappings[k].matrix());
                        program->set("sgfx_uvSet" + index, m->mappings[k].texCoord);
                    }
                if (m->baseColorTexture) s.bindTexture(BaseUnit, textureFor(*m->baseColorTexture));
                if (m->alphaTexture) s.bindTexture(AlphaUnit, textureFor(*m->alphaTexture));
                if (m->normalTexture) s.bindTexture(NormalUnit, textureFor(*m->normalTexture));
                if (m->metallicRoughnessTexture)
                    s.bindTexture(MetalRoughUnit, textureFor(*m->metallicRoughnessTexture));
                if (m->occlusionTexture) s.bindTexture(OcclusionUnit, textureFor(*m->occlusionTexture));
                if (m->emissiveTexture) s.bindTexture(EmissiveUnit, textureFor(*m->emissiveTexture));
            }
            ++stats_.stateChanges;
        }
        switch (item.faces) {
        case RenderItem::Faces::Back:
            s.setCull(CullFace::Front);
            break;
        case RenderItem::Faces::Front:
            s.setCull(CullFace::Back);
            break;
        case RenderItem::Faces::AsState:
            s.setCull(state->cullFace.value.value_or(CullFace::Back));
            break;
        }
        if (item.drawable) {
            program->set("sgfx_model", item.model);
            item.drawable->draw(*this, *program, item); // binds its own vertex arrays and units
            batchesBound = false;                       // and maybe buffers
            ++stats_.drawCalls;
            stats_.triangles += item.drawable->triangleCount();
            continue;
        }
        const Geometry& g = *item.geometry;
        gl::GeometryBuffers& b = buffersFor(g);
        if (extra) {
            if (!batchesBound) {
                glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBatchBinding, s.batchModels.get());
                batchesBound = true;
            }
            drawBatch(b, run, batchBase, *program);
            batchBase += run;
            stats_.triangles += g.triangleCount() * run;
            continue;
        }
        program->set("sgfx_model", item.model);
        program->set("sgfx_normalMatrix", glm::mat3(glm::transpose(glm::inverse(item.model))));
        glBindVertexArray(b.vao.get());
        const TransparencyDetails* details =
            state->transparency.value ? &*state->transparency.value : nullptr;
        if (details && details->sortTriangles && (item.features & FeatureBlend) && !depthOnly &&
            g.triangleCount() > 0 && g.instances.empty()) {
            // Self-overlapping mesh: its triangles back to front, from an index buffer of this view.
            Impl::SortedMesh& mesh = s.sortedMeshes[{&g, s.camera}];
            if (!mesh.sort || mesh.revision != g.revision() || mesh.owner.expired()) {
                mesh.owner = g.weak_from_this();
                mesh.revision = g.revision();
                mesh.sort = std::make_unique<TriangleDepthSort>(g);
                mesh.indices = gl::createBuffer();
                glNamedBufferData(mesh.indices.get(), GLsizeiptr(mesh.sort->indices().size_bytes()), nullptr,
                                  GL_STREAM_DRAW);
            }
            mesh.lastUse = s.frames;
            if (mesh.sort->update(frame_.view * item.model, details->resortAngle)) {
                glNamedBufferSubData(mesh.indices.get(), 0, GLsizeiptr(mesh.sort->indices().size_bytes()),
                                     mesh.sort->indices().data());
                ++stats_.triangleSorts;
            }
            glVertexArrayElementBuffer(b.vao.get(), mesh.indices.get());
            glDrawElements(GL_TRIANGLES, GLsizei(mesh.sort->indices().size()), GL_UNSIGNED_INT, nullptr);
            glVertexArrayElementBuffer(b.vao.get(), b.indexed ? b.indices.get() : 0);
        } else if (b.instances) {
            if (b.indexed)
                glDrawElementsInstanced(b.mode, GLsizei(b.count), GL_UNSIGNED_INT, nullptr,
                                        GLsizei(b.instances));
            else
                glDrawArraysInstanced(b.mode, 0, GLsizei(b.count), GLsizei(b.instances));
        } else if (b.indexed) {
            glDrawElements(b.mode, GLsizei(b.count), GL_UNSIGNED_INT, nullptr);
        } else {
            glDrawArrays(b.mode, 0, GLsizei(b.count));
        }
        ++stats_.drawCalls;
        stats_.triangles += g.triangleCount();
    }
    glBindVertexArray(0);
    // Leave no buffer bound to the batch binding: Mesa leaks a buffer still bound to an indexed
    // storage binding when the context is destroyed (LeakSanitizer).
    if (!s.batchScratch.empty()) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBatchBinding, 0);
    if (mode == DrawMode::DepthOnly) glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    s.log.item = nullptr;
    s.log.program = nullptr;
}

std::size_t Renderer::batchLength(std::span<const RenderItem> items) const {
    const RenderItem& first = items.front();
    // Built-in materials only (a program of the user's does not read instance matrices); blended
    // items keep their one-by-one path (triangle sorting).
    if (!options_.autoInstancing || first.drawable || first.program() || !first.geometry->instances.empty() ||
        (first.features & FeatureBlend))
        return 1;
    std::size_t n = 1;
    while (n < items.size()) {
        const RenderItem& it = items[n];
        if (it.geometry != first.geometry || it.state != first.state || it.effectSet != first.effectSet ||
            it.faces != first.faces || it.programKey != first.programKey || it.features != first.features)
            break;
        ++n;
    }
    return n >= options_.minInstanceBatch ? n : 1;
}

void Renderer::drawBatch(const gl::GeometryBuffers& b, std::size_t count, std::size_t base,
                         gl::Program& program) {
    program.set("sgfx_batchBase", int(base));
    glBindVertexArray(b.vao.get());
    if (b.indexed)
        glDrawElementsInstanced(b.mode, GLsizei(b.count), GL_UNSIGNED_INT, nullptr, GLsizei(count));
    else
        glDrawArraysInstanced(b.mode, 0, GLsizei(b.count), GLsizei(count));
    ++stats_.drawCalls;
    ++stats_.instanceBatches;
}

namespace {
template <class T> void flipRows(std::vector<T>& data, int width, int height, int channels) {
    // GL's rows run bottom to top; images are stored top row first.
    const std::size_t row = std::size_t(width) * channels;
    for (int y = 0; y < height / 2; ++y)
        std::swap_ranges(data.begin() + std::ptrdiff_t(y * row), data.begin() + std::ptrdiff_t((y + 1) * row),
                         data.begin() + std::ptrdiff_t((height - 1 - y) * row));
}
} // namespace

FloatImage Renderer::readPixelsLinear() {
    context_.assertOwnerThread();
    gl::RenderTarget& t = impl_->scene;
    FloatImage img{t.width, t.height, std::vector<float>(std::size_t(t.width) * t.height * 4)};
    if (!t.fbo) return img;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t.fbo.get());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    // Reading an sRGB target gives the stored (encoded) values: decode them.
    glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_FLOAT, img.rgba.data());
    if (t.colorFormat == GL_SRGB8_ALPHA8)
        for (std::size_t i = 0; i < img.rgba.size(); ++i)
            if (i % 4 != 3) {
                const float c = img.rgba[i];
                img.rgba[i] = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
            }
    flipRows(img.rgba, t.width, t.height, 4);
    return img;
}

Image Renderer::readPixels() {
    context_.assertOwnerThread();
    gl::RenderTarget& t = impl_->scene;
    Image img;
    img.width = t.width;
    img.height = t.height;
    img.channels = 4;
    img.pixels.resize(std::size_t(t.width) * t.height * 4);
    if (!t.fbo) return img;
    if (t.colorFormat != GL_SRGB8_ALPHA8) {
        // Linear float target: encode once here, as the sRGB framebuffer would have.
        const FloatImage f = readPixelsLinear();
        for (std::size_t i = 0; i < f.rgba.size(); ++i) {
            float c = std::isfinite(f.rgba[i]) ? std::clamp(f.rgba[i], 0.0f, 1.0f) : 0.0f;
            if (i % 4 != 3) c = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
            img.pixels[i] = std::uint8_t(std::lround(c * 255.0f));
        }
        return img;
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t.fbo.get());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_BYTE, img.pixels.data());
    flipRows(img.pixels, t.width, t.height, 4);
    return img;
}

void Renderer::blitToWindow() {
    gl::RenderTarget& t = impl_->scene;
    if (!context_.isWindow() || !t.fbo) return;
    // The target already holds sRGB-encoded values: copy them without conversion.
    glDisable(GL_FRAMEBUFFER_SRGB);
    glBlitNamedFramebuffer(t.fbo.get(), 0, 0, 0, t.width, t.height, 0, 0, context_.width(), context_.height(),
                           GL_COLOR_BUFFER_BIT, GL_LINEAR);
}

void Renderer::present() {
    if (!context_.isWindow()) {
        // Headless: submit the frame. Without a flush llvmpipe keeps queueing frames and its
        // memory grew by ~60 MB over 3000 frames before levelling off (measured).
        glFlush();
        return;
    }
    blitToWindow();
    context_.swapBuffers();
}

} // namespace sgfx

#include "sgfx/gl/Objects.h"

#include <glm/gtc/type_ptr.hpp>
#include <sgfx_glad/gl.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace sgfx::gl {

LiveCounts& liveObjects() {
    static LiveCounts counts;
    return counts;
}

long LiveCounts::total() const {
    long t = 0;
    for (const auto& c : counts)
        t += c.load();
    return t;
}

template <Kind K> void Object<K>::reset() {
    if (!name_) return;
    // Deleting needs the owning context current; GL silently ignores calls without one, so a
    // late destruction leaks on the driver side but never crashes.
    if (sgfx_glad_glGetString) {
        switch (K) {
        case Kind::Buffer:
            glDeleteBuffers(1, &name_);
            break;
        case Kind::VertexArray:
            glDeleteVertexArrays(1, &name_);
            break;
        case Kind::Texture:
            glDeleteTextures(1, &name_);
            break;
        case Kind::Framebuffer:
            glDeleteFramebuffers(1, &name_);
            break;
        case Kind::Renderbuffer:
            glDeleteRenderbuffers(1, &name_);
            break;
        case Kind::Shader:
            glDeleteShader(name_);
            break;
        case Kind::Program:
            glDeleteProgram(name_);
            break;
        case Kind::Query:
            glDeleteQueries(1, &name_);
            break;
        case Kind::Sampler:
            glDeleteSamplers(1, &name_);
            break;
        case Kind::Count:
            break;
        }
    }
    --liveObjects().counts[std::size_t(K)];
    name_ = 0;
}

template class Object<Kind::Buffer>;
template class Object<Kind::VertexArray>;
template class Object<Kind::Texture>;
template class Object<Kind::Framebuffer>;
template class Object<Kind::Renderbuffer>;
template class Object<Kind::Shader>;
template class Object<Kind::Program>;
template class Object<Kind::Query>;
template class Object<Kind::Sampler>;

BufferObject createBuffer() {
    GLuint n = 0;
    glCreateBuffers(1, &n);
    return BufferObject(n);
}
BufferObject createStorageBuffer(std::size_t bytes, const void* data) {
    BufferObject b = createBuffer();
    glNamedBufferData(b.get(), GLsizeiptr(bytes), data, GL_DYNAMIC_DRAW);
    return b;
}
void writeBuffer(const BufferObject& buffer, std::size_t offset, std::size_t bytes, const void* data) {
    if (bytes) glNamedBufferSubData(buffer.get(), GLintptr(offset), GLsizeiptr(bytes), data);
}
void readBuffer(const BufferObject& buffer, std::size_t offset, std::size_t bytes, void* data) {
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    if (bytes) glGetNamedBufferSubData(buffer.get(), GLintptr(offset), GLsizeiptr(bytes), data);
}
void bindStorageBuffer(unsigned binding, const BufferObject& buffer) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buffer.get());
}
void dispatchCompute(const glm::uvec3& groups) {
    glDispatchCompute(groups.x, groups.y, groups.z);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
}
void finish() {
    glFinish();
}
void drawPulled(const VertexArrayObject& empty, unsigned mode, int count, int instances) {
    glBindVertexArray(empty.get());
    glDrawArraysInstanced(GLenum(mode), 0, count, instances);
}
VertexArrayObject createVertexArray() {
    GLuint n = 0;
    glCreateVertexArrays(1, &n);
    return VertexArrayObject(n);
}
TextureObject createTexture(unsigned target) {
    GLuint n = 0;
    glCreateTextures(target, 1, &n);
    return TextureObject(n);
}
TextureObject createTexture2D(unsigned format, int width, int height, int filter, int levels) {
    TextureObject t = createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.get(), levels, format, width, height);
    glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, filter);
    glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, filter);
    glTextureParameteri(t.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return t;
}
TextureObject createTextureCube(unsigned format, int size, int levels) {
    TextureObject t = createTexture(GL_TEXTURE_CUBE_MAP);
    glTextureStorage2D(t.get(), levels, format, size, size);
    glTextureParameteri(t.get(), GL_TEXTURE_MIN_FILTER, levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    glTextureParameteri(t.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(t.get(), GL_TEXTURE_MAX_LEVEL, levels - 1);
    for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
        glTextureParameteri(t.get(), wrap, GL_CLAMP_TO_EDGE);
    return t;
}
void writeTexture(const TextureObject& texture, int level, int layer, int width, int height, unsigned format,
                  unsigned type, const void* data) {
    if (layer < 0)
        glTextureSubImage2D(texture.get(), level, 0, 0, width, height, format, type, data);
    else
        glTextureSubImage3D(texture.get(), level, 0, 0, layer, width, height, 1, format, type, data);
}
void readTexture(const TextureObject& texture, int level, unsigned format, unsigned type, std::size_t bytes,
                 void* data) {
    glGetTextureImage(texture.get(), level, format, type, GLsizei(bytes), data);
}
FramebufferObject createFramebuffer() {
    GLuint n = 0;
    glCreateFramebuffers(1, &n);
    return FramebufferObject(n);
}
FramebufferObject createFramebuffer(const TextureObject& colour) {
    FramebufferObject f = createFramebuffer();
    glNamedFramebufferTexture(f.get(), GL_COLOR_ATTACHMENT0, colour.get(), 0);
    return f;
}
QueryObject createQuery(unsigned target) {
    GLuint n = 0;
    glCreateQueries(target, 1, &n);
    return QueryObject(n);
}
SamplerObject createSampler() {
    GLuint n = 0;
    glCreateSamplers(1, &n);
    return SamplerObject(n);
}
SamplerObject createComparisonSampler() {
    SamplerObject s = createSampler();
    glSamplerParameteri(s.get(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glSamplerParameteri(s.get(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    glSamplerParameteri(s.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(s.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
        glSamplerParameteri(s.get(), wrap, GL_CLAMP_TO_EDGE);
    return s;
}

// ---------------------------------------------------------------- Program
namespace {
using ShaderObject = Object<Kind::Shader>;

ShaderObject compile(GLenum stage, const std::string& src, std::span<const std::string> names,
                     std::string_view description) {
    ShaderObject s(glCreateShader(stage));
    const char* text = src.c_str();
    glShaderSource(s.get(), 1, &text, nullptr);
    glCompileShader(s.get());
    GLint ok = 0;
    glGetShaderiv(s.get(), GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetShaderiv(s.get(), GL_INFO_LOG_LENGTH, &len);
        std::string log(std::size_t(std::max(len, 1)), '\0');
        glGetShaderInfoLog(s.get(), len, nullptr, log.data());
        const char* stageName = stage == GL_VERTEX_SHADER     ? "vertex"
                                : stage == GL_GEOMETRY_SHADER ? "geometry"
                                                              : "fragment";
        throw ShaderError("sgfx: " + std::string(stageName) + " shader of " + std::string(description) +
                          " failed to compile:\n" + ShaderComposer::translateLog(log.c_str(), names));
    }
    return s;
}
} // namespace

Program::Program(const ComposedProgram& c)
    : description_(c.description) {
    std::vector<ShaderObject> stages;
    if (!c.compute.empty())
        stages.push_back(compile(GL_COMPUTE_SHADER, c.compute, c.vertexSources, c.description));
    else
        stages.push_back(compile(GL_VERTEX_SHADER, c.vertex, c.vertexSources, c.description));
    if (!c.geometry.empty())
        stages.push_back(compile(GL_GEOMETRY_SHADER, c.geometry, c.geometrySources, c.description));
    if (c.compute.empty() && (!c.fragment.empty() || c.feedbackVaryings.empty()))
        stages.push_back(compile(GL_FRAGMENT_SHADER, c.fragment, c.fragmentSources, c.description));
    name_ = glCreateProgram();
    ++liveObjects().counts[std::size_t(Kind::Program)];
    for (const ShaderObject& st : stages)
        glAttachShader(name_, st.get());
    if (!c.feedbackVaryings.empty()) {
        std::vector<const char*> names;
        for (const std::string& v : c.feedbackVaryings)
            names.push_back(v.c_str());
        glTransformFeedbackVaryings(name_, GLsizei(names.size()), names.data(),
                                    c.feedbackInterleaved ? GL_INTERLEAVED_ATTRIBS : GL_SEPARATE_ATTRIBS);
    }
    glLinkProgram(name_);
    for (const ShaderObject& st : stages)
        glDetachShader(name_, st.get());
    GLint ok = 0;
    glGetProgramiv(name_, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetProgramiv(name_, GL_INFO_LOG_LENGTH, &len);
        std::string log(std::size_t(std::max(len, 1)), '\0');
        glGetProgramInfoLog(name_, len, nullptr, log.data());
        glDeleteProgram(name_);
        --liveObjects().counts[std::size_t(Kind::Program)];
        name_ = 0;
        throw ShaderError("sgfx: program " + description_ + " failed to link:\n" + std::string(log.c_str()));
    }
}

Program::~Program() {
    if (!name_) return;
    if (sgfx_glad_glGetString) glDeleteProgram(name_);
    --liveObjects().counts[std::size_t(Kind::Program)];
}

int Program::location(std::string_view uniform) {
    for (const auto& [n, loc] : locations_)
        if (n == uniform) return loc;
    std::string key(uniform);
    const int loc = glGetUniformLocation(name_, key.c_str());
    locations_.emplace_back(std::move(key), loc);
    return loc;
}

void Program::set(std::string_view uniform, const UniformValue& v) {
    set(location(uniform), v);
}

void Program::setUnsigned(std::string_view uniform, std::uint32_t v) {
    const int loc = location(uniform);
    if (loc >= 0) glProgramUniform1ui(name_, loc, v);
}

void Program::setInt3(std::string_view uniform, const glm::ivec3& v) {
    const int loc = location(uniform);
    if (loc >= 0) glProgramUniform3i(name_, loc, v.x, v.y, v.z);
}

void Program::setInt4(std::string_view uniform, const glm::ivec4& v) {
    const int loc = location(uniform);
    if (loc >= 0) glProgramUniform4i(name_, loc, v.x, v.y, v.z, v.w);
}

void Program::set(int loc, const UniformValue& v) {
    if (loc < 0) return;
    std::visit(
        [&](const auto& x) {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, int>)
                glProgramUniform1i(name_, loc, x);
            else if constexpr (std::is_same_v<T, float>)
                glProgramUniform1f(name_, loc, x);
            else if constexpr (std::is_same_v<T, glm::vec2>)
                glProgramUniform2fv(name_, loc, 1, glm::value_ptr(x));
            else if constexpr (std::is_same_v<T, glm::vec3>)
                glProgramUniform3fv(name_, loc, 1, glm::value_ptr(x));
            else if constexpr (std::is_same_v<T, glm::vec4>)
                glProgramUniform4fv(name_, loc, 1, glm::value_ptr(x));
            else if constexpr (std::is_same_v<T, glm::mat3>)
                glProgramUniformMatrix3fv(name_, loc, 1, GL_FALSE, glm::value_ptr(x));
            else
                glProgramUniformMatrix4fv(name_, loc, 1, GL_FALSE, glm::value_ptr(x));
        },
        v);
}

// ---------------------------------------------------------------- RenderTarget
namespace {
std::string statusName(GLenum s) {
    switch (s) {
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT:
        return "INCOMPLETE_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT:
        return "INCOMPLETE_MISSING_ATTACHMENT";
    case GL_FRAMEBUFFER_UNSUPPORTED:
        return "UNSUPPORTED";
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE:
        return "INCOMPLETE_MULTISAMPLE";
    default:
        return "status 0x" + std::to_string(s);
    }
}
} // namespace

static std::string formatName(GLenum f) {
    switch (f) {
    case GL_SRGB8_ALPHA8:
        return "SRGB8_ALPHA8";
    case GL_RGBA16F:
        return "RGBA16F";
    case GL_RGBA32F:
        return "RGBA32F";
    default:
        return "format 0x" + std::to_string(f);
    }
}

void RenderTarget::resize(int w, int h, unsigned format, int sampleCount) {
    sampleCount = std::max(sampleCount, 1);
    if (w == width && h == height && format == colorFormat && sampleCount == samples && fbo) return;
    GLint maxSize = 0, maxViewport[2] = {0, 0};
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
    const int maxW = std::min(maxSize, maxViewport[0]), maxH = std::min(maxSize, maxViewport[1]);
    if (w <= 0 || h <= 0 || w > maxW || h > maxH)
        throw std::invalid_argument("sgfx: render target size " + std::to_string(w) + "x" +
                                    std::to_string(h) + " is outside the driver's 1x1.." +
                                    std::to_string(maxW) + "x" + std::to_string(maxH));
    const bool ms = sampleCount > 1;
    auto make = [&](GLenum internalFormat, GLint filter) {
        if (!ms) return createTexture2D(internalFormat, w, h, filter);
        TextureObject t = createTexture(GL_TEXTURE_2D_MULTISAMPLE);
        glTextureStorage2DMultisample(t.get(), sampleCount, internalFormat, w, h, GL_TRUE);
        return t;
    };
    color = make(format, GL_LINEAR);
    depth = make(GL_DEPTH_COMPONENT32F, GL_NEAREST);
    fbo = createFramebuffer();
    glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
    glNamedFramebufferTexture(fbo.get(), GL_DEPTH_ATTACHMENT, depth.get(), 0);
    const GLenum status = glCheckNamedFramebufferStatus(fbo.get(), GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error("sgfx: scene framebuffer " + std::to_string(w) + "x" + std::to_string(h) +
                                 (ms ? " with " + std::to_string(sampleCount) + " samples" : std::string()) +
                                 " (colour " + formatName(format) +
                                 ", depth DEPTH_COMPONENT32F) is incomplete: " + statusName(status));
    width = w;
    height = h;
    colorFormat = format;
    samples = sampleCount;
}

} // namespace sgfx::gl

#include "render/GpuUpload.h"

#include "sgfx/Image.h"
#include "sgfx/RenderQueue.h"
#include "sgfx/ShaderComposer.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace sgfx::render {

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

namespace {

// One vertex attribute in its own buffer, or disabled when the array is empty. `integer`:
// glVertexArrayAttribIFormat, for inputs the shader reads as integers (joint indices).
template <class T>
void uploadAttribute(gl::GeometryBuffers& b, gl::BufferObject& buf, GLuint index, const std::vector<T>& data,
                     GLint components, GLenum type = GL_FLOAT, bool integer = false) {
    if (data.empty()) {
        glDisableVertexArrayAttrib(b.vao.get(), index);
        return;
    }
    if (!buf) buf = gl::createBuffer();
    glNamedBufferData(buf.get(), GLsizeiptr(data.size() * sizeof(T)), data.data(), GL_STATIC_DRAW);
    glVertexArrayVertexBuffer(b.vao.get(), index, buf.get(), 0, sizeof(T));
    if (integer)
        glVertexArrayAttribIFormat(b.vao.get(), index, components, type, 0);
    else
        glVertexArrayAttribFormat(b.vao.get(), index, components, type, GL_FALSE, 0);
    glVertexArrayAttribBinding(b.vao.get(), index, index);
    glEnableVertexArrayAttrib(b.vao.get(), index);
}

template <class T>
void uploadAttribute(gl::GeometryBuffers& b, GLuint index, const std::vector<T>& data, GLint components) {
    uploadAttribute(b, b.attributes[index], index, data, components);
}

// Skinning inputs at locations 10..13: joint indices as integers (the shader reads uvec4), weights.
void uploadSkin(gl::GeometryBuffers& b, const Geometry& g) {
    uploadAttribute(b, b.skinAttributes[0], 10, g.joints0, 4, GL_UNSIGNED_SHORT, true);
    uploadAttribute(b, b.skinAttributes[1], 11, g.weights0, 4);
    uploadAttribute(b, b.skinAttributes[2], 12, g.joints1, 4, GL_UNSIGNED_SHORT, true);
    uploadAttribute(b, b.skinAttributes[3], 13, g.weights1, 4);
}

// Morph displacements in one storage buffer, target-major per attribute (shaders/pose.glsl).
void uploadMorphTargets(gl::GeometryBuffers& b, const Geometry& g) {
    const std::size_t n = g.positions.size(), targets = g.morphTargets.size();
    if (!targets) return;
    bool normals = false, tangents = false;
    for (const MorphTarget& t : g.morphTargets) {
        normals |= !t.normals.empty();
        tangents |= !t.tangents.empty();
    }
    std::vector<glm::vec4> deltas;
    deltas.reserve(n * targets * (1 + normals + tangents));
    auto append = [&](std::vector<glm::vec3> MorphTarget::*attribute) {
        for (const MorphTarget& t : g.morphTargets)
            for (std::size_t v = 0; v < n; ++v)
                deltas.emplace_back((t.*attribute).empty() ? glm::vec3(0.0f) : (t.*attribute)[v], 0.0f);
    };
    append(&MorphTarget::positions);
    b.morphLayout[2] = normals ? int(deltas.size()) : -1;
    if (normals) append(&MorphTarget::normals);
    b.morphLayout[3] = tangents ? int(deltas.size()) : -1;
    if (tangents) append(&MorphTarget::tangents);
    b.morphLayout[0] = int(targets);
    b.morphLayout[1] = int(n);
    if (!b.morphDeltas) b.morphDeltas = gl::createBuffer();
    glNamedBufferData(b.morphDeltas.get(), GLsizeiptr(deltas.size() * sizeof(glm::vec4)), deltas.data(),
                      GL_STATIC_DRAW);
}

template <class T> void uploadStorage(gl::BufferObject& buffer, const std::vector<T>& data) {
    if (!buffer) buffer = gl::createBuffer();
    // An empty array still gets a buffer: a binding without one is undefined to read.
    const T none{};
    glNamedBufferData(buffer.get(), GLsizeiptr(std::max<std::size_t>(data.size(), 1) * sizeof(T)),
                      data.empty() ? &none : data.data(), GL_DYNAMIC_DRAW);
}

} // namespace

void bindPose(const Geometry& g, gl::GeometryBuffers& b) {
    if (b.poseRevision != g.poseRevision()) {
        if (g.skin) uploadStorage(b.jointMatrices, g.jointMatrices());
        if (!g.morphTargets.empty()) uploadStorage(b.morphWeights, g.morphWeights());
        b.poseRevision = g.poseRevision();
    }
    if (g.skin) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kJointsBinding, b.jointMatrices.get());
    if (!g.morphTargets.empty()) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kMorphBinding, b.morphDeltas.get());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kMorphWeightsBinding, b.morphWeights.get());
    }
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
    b.mirroredInstances = 0;
    if (!g.instances.empty()) {
        // Mirroring instances last, so each winding is one contiguous range of instances.
        std::vector<glm::mat4> ordered(g.instances);
        const auto firstMirrored = std::stable_partition(
            ordered.begin(), ordered.end(), [](const glm::mat4& m) { return !RenderItem::isMirroring(m); });
        b.mirroredInstances = std::uint32_t(ordered.end() - firstMirrored);
        auto& buf = b.attributes[6];
        if (!buf) buf = gl::createBuffer();
        glNamedBufferData(buf.get(), GLsizeiptr(ordered.size() * sizeof(glm::mat4)), ordered.data(),
                          GL_STATIC_DRAW);
        glVertexArrayVertexBuffer(b.vao.get(), 6, buf.get(), 0, sizeof(glm::mat4));
        glVertexArrayBindingDivisor(b.vao.get(), 6, 1);
    }
    uploadSkin(b, g);
    uploadMorphTargets(b, g);
    b.poseRevision = 0; // the pose follows at the next bindPose
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

void copyToTexture(const gl::RenderTarget& from, const Texture& to) {
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

} // namespace sgfx::render

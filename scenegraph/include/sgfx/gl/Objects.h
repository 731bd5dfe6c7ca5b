#pragma once
/// @file
/// RAII wrappers for GL objects. Each owns one name, deletes it on destruction, and is counted
/// in liveObjects() so tests can prove a scene and viewer leave nothing behind.
#include "sgfx/Export.h"
#include "sgfx/ShaderComposer.h"
#include "sgfx/StateSet.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace sgfx::gl {

using Name = unsigned int;

enum class Kind : std::uint8_t {
    Buffer,
    VertexArray,
    Texture,
    Framebuffer,
    Renderbuffer,
    Shader,
    Program,
    Query,
    Sampler,
    Count
};

/// How many GL objects of each kind are alive (tests prove scenes leave none behind).
struct SGFX_API LiveCounts {
    std::array<std::atomic<long>, std::size_t(Kind::Count)> counts{};
    long total() const;
    long operator[](Kind k) const { return counts[std::size_t(k)].load(); }
};
SGFX_API LiveCounts& liveObjects();

/// Move-only owner of one GL name of kind K.
template <Kind K> class SGFX_API Object {
public:
    Object() = default;
    explicit Object(Name n)
        : name_(n) {
        if (n) ++liveObjects().counts[std::size_t(K)];
    }
    Object(Object&& o) noexcept
        : name_(std::exchange(o.name_, 0)) {}
    Object& operator=(Object&& o) noexcept {
        if (this != &o) {
            reset();
            name_ = std::exchange(o.name_, 0);
        }
        return *this;
    }
    Object(const Object&) = delete;
    Object& operator=(const Object&) = delete;
    ~Object() { reset(); }

    Name get() const { return name_; }
    explicit operator bool() const { return name_ != 0; }
    void reset();

private:
    Name name_ = 0;
};

using BufferObject = Object<Kind::Buffer>;
using VertexArrayObject = Object<Kind::VertexArray>;
using TextureObject = Object<Kind::Texture>;
using FramebufferObject = Object<Kind::Framebuffer>;
using RenderbufferObject = Object<Kind::Renderbuffer>;
using QueryObject = Object<Kind::Query>;
using SamplerObject = Object<Kind::Sampler>;

SGFX_API BufferObject createBuffer();
SGFX_API VertexArrayObject createVertexArray();
SGFX_API TextureObject createTexture(unsigned target);
/// A 2D texture for a pass's own use (`levels` mip levels, 1 by default): `filter` (GL_NEAREST or
/// GL_LINEAR) both ways, clamped to its edges.
SGFX_API TextureObject createTexture2D(unsigned format, int width, int height,
                                       int filter = 0x2600 /* GL_NEAREST */, int levels = 1);
/// A cube map of size² faces with `levels` mips, trilinear (seamless where the renderer enables
/// it) and clamped: node-owned environment maps.
SGFX_API TextureObject createTextureCube(unsigned format, int size, int levels);
/// Writes texels into level `level` of a 2D texture (layer < 0) or one face of a cube map
/// (layer = face, OpenGL's order); `format` and `type` describe `data` (GL_RGB, GL_FLOAT...).
SGFX_API void writeTexture(const TextureObject& texture, int level, int layer, int width, int height,
                           unsigned format, unsigned type, const void* data);
/// Reads level `level` of a texture into `data` (`bytes` long); GL must have finished drawing it.
SGFX_API void readTexture(const TextureObject& texture, int level, unsigned format, unsigned type,
                          std::size_t bytes, void* data);
/// A buffer of `bytes` bytes (filled from `data` when not null) for shader storage: node-owned
/// arrays read by vertex or compute shaders (Gaussian splats, their sort keys and order).
SGFX_API BufferObject createStorageBuffer(std::size_t bytes, const void* data = nullptr);
/// Writes `bytes` bytes at `offset` of a buffer.
SGFX_API void writeBuffer(const BufferObject& buffer, std::size_t offset, std::size_t bytes,
                          const void* data);
/// Reads `bytes` bytes at `offset` of a buffer (waits for the GPU's writes to it).
SGFX_API void readBuffer(const BufferObject& buffer, std::size_t offset, std::size_t bytes, void* data);
/// Binds a buffer (or none) to shader storage binding `binding` (`layout(std430, binding = N)`).
SGFX_API void bindStorageBuffer(unsigned binding, const BufferObject& buffer);
/// Runs the bound compute program (Renderer::useProgram) over `groups` work groups; its writes
/// are visible to every later command (a full barrier).
SGFX_API void dispatchCompute(const glm::uvec3& groups);
/// Waits until the GPU has run every command issued so far (glFinish): CPU timing of GPU work
/// (ParticleUpdate::Auto's measurement), never on a frame's normal path.
SGFX_API void finish();
/// Draws `instances` instances of `count` vertices without attributes (an empty vertex array is
/// bound for it): shaders that pull their data by gl_VertexID / gl_InstanceID. `mode` is GL's.
SGFX_API void drawPulled(const VertexArrayObject& empty, unsigned mode, int count, int instances);
SGFX_API FramebufferObject createFramebuffer();
/// A framebuffer drawing into level 0 of `colour`.
SGFX_API FramebufferObject createFramebuffer(const TextureObject& colour);
SGFX_API QueryObject createQuery(unsigned target);
/// A sampler object with GL's default state (bound to a unit, it overrides the sampling state of
/// whatever texture is bound there).
SGFX_API SamplerObject createSampler();
/// A depth-comparison sampler (shadow maps read as `sampler2DShadow`): GL_COMPARE_REF_TO_TEXTURE
/// with GL_LEQUAL (1 where the reference is at most the stored depth), GL_LINEAR both ways (2×2
/// percentage-closer filtering of the comparisons), clamped to the edges.
SGFX_API SamplerObject createComparisonSampler();

/// Linked program with a uniform-location cache.
class SGFX_API Program {
public:
    /// Compiles and links; throws ShaderError with the driver log translated to original lines.
    explicit Program(const ComposedProgram& composed);
    Program(Program&&) = delete;
    ~Program();

    Name get() const { return name_; }
    const std::string& description() const { return description_; }
    int location(std::string_view uniform);
    void set(std::string_view uniform, const UniformValue& v);
    void set(int location, const UniformValue& v);
    /// Types a StateSet's uniforms do not carry: `uint` and `ivec3` uniforms.
    void setUnsigned(std::string_view uniform, std::uint32_t v);
    void setInt3(std::string_view uniform, const glm::ivec3& v);
    void setInt4(std::string_view uniform, const glm::ivec4& v);

    /// Renderer bookkeeping: which frame's per-program uniforms were last uploaded.
    std::uint64_t frameStamp = 0;

private:
    Name name_ = 0;
    std::string description_;
    /// Few uniforms per program: a flat list searched by string_view never allocates per draw.
    std::vector<std::pair<std::string, int>> locations_;
};

/// A texture's GPU copy: the GL object and what it was made from.
class SGFX_API Texture {
public:
    TextureObject object;
    unsigned target = 0;
    std::uint64_t revision = 0;
};

/// A Geometry's GPU copy: one interleaved-free VBO per attribute, an index buffer and a VAO.
struct SGFX_API GeometryBuffers {
    VertexArrayObject vao;
    /// position, normal, tangent, texcoord, colour, texcoord1, instance matrices (locations 6..9)
    std::array<BufferObject, 7> attributes;
    std::uint32_t instances = 0; ///< 0: not instanced
    /// The last `mirroredInstances` instance matrices mirror (negative determinant): uploaded after
    /// the others and drawn with the other winding as front.
    std::uint32_t mirroredInstances = 0;
    BufferObject indices;
    std::uint64_t revision = 0;
    std::uint32_t count = 0;
    bool indexed = false;
    unsigned mode = 0;
    /// Posed meshes: joint indices and weights (locations 10..13), morph displacements (static),
    /// and the joint matrices and morph weights of the pose last uploaded.
    std::array<BufferObject, 4> skinAttributes;
    BufferObject morphDeltas, jointMatrices, morphWeights;
    std::uint64_t poseRevision = 0;
    int morphLayout[4] = {0, 0, -1, -1}; ///< targets, vertices, first normal, first tangent
};

/// A colour + depth render target whose attachments are textures (readable by later passes).
struct SGFX_API RenderTarget {
    FramebufferObject fbo;
    TextureObject color;
    TextureObject depth;
    int width = 0, height = 0;
    unsigned colorFormat = 0; ///< GL internal format of `color`
    int samples = 1;          ///< > 1: multisample textures (GL_TEXTURE_2D_MULTISAMPLE)
    /// (Re)allocates for a new size or colour format (GL_SRGB8_ALPHA8 by default); throws
    /// std::invalid_argument for a size outside the driver's limits and std::runtime_error naming
    /// the attachment formats when the framebuffer is incomplete.
    void resize(int w, int h, unsigned format = 0x8C43 /* GL_SRGB8_ALPHA8 */, int samples = 1);
};

} // namespace sgfx::gl

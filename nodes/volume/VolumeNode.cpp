#include <sgfx/nodes/volume/VolumeNode.h>

#include "ParameterChecks.h"

#include <sgfx/FrameSetup.h>
#include <sgfx/Image.h>
#include <sgfx/Renderer.h>
#include <sgfx/StateSet.h>
#include <sgfx/gl/Objects.h>

#include <sgfx_glad/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <stdexcept>

namespace sgfx {

namespace {

constexpr unsigned kDensityUnit = Renderer::kFirstDrawableUnit; // +0..2: a drawable's own units
constexpr int kMaxBlock = 8;                                    // voxels per empty-space cell

void check(const char* name, float v, double lo, double hi, bool openLow = false) {
    nodes::checkRange("VolumeParameters", name, v, lo, hi, openLow);
}

// The density (a grid or the application's GLSL function) goes to the stage that samples it: the
// fragment shader for the march and slices, the vertex shader for splats (one sample per kernel).
BaseShader makeShader(const std::string& function, bool half, VolumeMethod method = VolumeMethod::Raymarch) {
    static const char* names[3][3] = {{"volume_box.vert", "volume_march.frag", "volume"},
                                      {"volume_slice.vert", "volume_slice.frag", "volume_slices"},
                                      {"volume_splat.vert", "volume_splat.frag", "volume_splats"}};
    const auto& files = names[int(method)];
    const bool splats = method == VolumeMethod::Splatting;
    std::string vertex = nodes::shaderWithIncludes(files[0]);
    std::string fragment = nodes::shaderWithIncludes(files[1]);
    std::string defines = "#define SGFX_VOLUME_DENSITY_UNIT " + std::to_string(kDensityUnit) + "\n";
    std::string name = half ? "volume_half" : files[2];
    if (half) defines += "#define SGFX_VOLUME_HALF\n";
    std::string& sampler = splats ? vertex : fragment;
    if (!function.empty()) {
        defines += "#define SGFX_VOLUME_FUNCTION\n";
        name += "_fn" + std::to_string(std::hash<std::string>{}(function));
        sampler += "\nfloat volumeDensity(vec3 uvw) {\n" + function + "\n}\n";
    }
    vertex = nodes::afterVersion(std::move(vertex), defines);
    fragment = nodes::afterVersion(std::move(fragment), defines);
    return BaseShader{name, files[0], std::move(vertex), files[1], std::move(fragment)};
}

float hashNoise(std::uint32_t x, std::uint32_t y, std::uint32_t z, std::uint32_t seed) {
    std::uint32_t h = x * 374761393u + y * 668265263u + z * 2147483647u + seed * 144665u;
    h = (h ^ (h >> 13)) * 1274126177u;
    return float((h ^ (h >> 16)) & 0xffffff) / 16777215.0f;
}

// Trilinear value noise on a lattice of `cells` per side, periodic.
float valueNoise(glm::vec3 p, int cells, std::uint32_t seed) {
    const glm::vec3 q = p * float(cells);
    const glm::ivec3 i = glm::ivec3(glm::floor(q));
    const glm::vec3 f = q - glm::floor(q);
    const glm::vec3 s = f * f * (3.0f - 2.0f * f);
    float v = 0.0f;
    for (int c = 0; c < 8; ++c) {
        const glm::ivec3 o(c & 1, (c >> 1) & 1, (c >> 2) & 1);
        const glm::ivec3 k = (i + o) % cells;
        const float w = (o.x ? s.x : 1 - s.x) * (o.y ? s.y : 1 - s.y) * (o.z ? s.z : 1 - s.z);
        v += w * hashNoise(std::uint32_t(k.x), std::uint32_t(k.y), std::uint32_t(k.z), seed);
    }
    return v;
}

} // namespace

// ---------------------------------------------------------------- grids
VolumeGrid VolumeGrid::constant(float density) {
    VolumeGrid g;
    g.size = glm::ivec3(2);
    g.values.assign(8, density);
    return g;
}

VolumeGrid VolumeGrid::sphere(int n, float radius, float edge) {
    VolumeGrid g;
    g.size = glm::ivec3(n);
    g.values.resize(std::size_t(n) * n * n);
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const glm::vec3 p = (glm::vec3(x, y, z) + 0.5f) / float(n) - 0.5f;
                const float r = glm::length(p);
                g.values[(std::size_t(z) * n + y) * n + x] =
                    edge > 0.0f ? std::clamp((radius - r) / edge + 0.5f, 0.0f, 1.0f)
                                : (r <= radius ? 1.0f : 0.0f);
            }
    return g;
}

VolumeGrid VolumeGrid::noise(int n, std::uint32_t seed, int octaves, float coverage) {
    VolumeGrid g;
    g.size = glm::ivec3(n);
    g.values.resize(std::size_t(n) * n * n);
    std::vector<float> raw(g.values.size());
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const glm::vec3 p = (glm::vec3(x, y, z) + 0.5f) / float(n);
                float v = 0.0f, amp = 0.5f;
                for (int o = 0; o < octaves; ++o, amp *= 0.5f)
                    v += amp * valueNoise(p, 4 << o, seed + std::uint32_t(o));
                // Fade towards the faces so the medium does not end in a flat wall.
                const glm::vec3 e = glm::min(p, 1.0f - p) * 8.0f;
                v *= std::clamp(std::min({e.x, e.y, e.z}), 0.0f, 1.0f);
                raw[(std::size_t(z) * n + y) * n + x] = v;
            }
    // Threshold at the quantile that leaves `coverage` of the voxels non-empty.
    std::vector<float> sorted = raw;
    const std::size_t k =
        std::min(sorted.size() - 1, std::size_t(double(1.0f - coverage) * double(sorted.size())));
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(k), sorted.end());
    const float cut = sorted[k];
    for (std::size_t i = 0; i < raw.size(); ++i)
        g.values[i] = std::max(0.0f, raw[i] - cut) / std::max(1e-6f, 1.0f - cut) * 2.0f;
    return g;
}

namespace {
float halfToFloat(std::uint16_t h) {
    const std::uint32_t sign = (h >> 15) & 1, exp = (h >> 10) & 0x1f, man = h & 0x3ff;
    float v;
    if (exp == 0)
        v = std::ldexp(float(man), -24);
    else if (exp == 31)
        v = man ? std::numeric_limits<float>::quiet_NaN() : std::numeric_limits<float>::infinity();
    else
        v = std::ldexp(float(man | 0x400), int(exp) - 25);
    return sign ? -v : v;
}
} // namespace

VolumeGrid VolumeGrid::loadRaw(const std::filesystem::path& file, glm::ivec3 size, Format format) {
    const std::string what = "sgfx: VolumeGrid::loadRaw '" + file.string() + "'";
    if (glm::any(glm::lessThan(size, glm::ivec3(1))) || glm::any(glm::greaterThan(size, glm::ivec3(2048))))
        throw std::invalid_argument(what + ": size " + std::to_string(size.x) + "x" + std::to_string(size.y) +
                                    "x" + std::to_string(size.z) + " is outside 1..2048 per axis");
    const std::size_t bytesPer = format == Format::R8 ? 1 : format == Format::R16F ? 2 : 4;
    const std::size_t count = std::size_t(size.x) * std::size_t(size.y) * std::size_t(size.z);
    std::ifstream in(file, std::ios::binary | std::ios::ate);
    if (!in) throw std::runtime_error(what + ": cannot open the file");
    const auto actual = std::size_t(in.tellg());
    if (actual != count * bytesPer)
        throw std::runtime_error(what + ": expected " + std::to_string(count * bytesPer) + " bytes for " +
                                 std::to_string(size.x) + "x" + std::to_string(size.y) + "x" +
                                 std::to_string(size.z) + " values of " + std::to_string(bytesPer) +
                                 " bytes, the file has " + std::to_string(actual));
    std::vector<unsigned char> bytes(actual);
    in.seekg(0);
    in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(actual));
    VolumeGrid g;
    g.size = size;
    g.format = format;
    g.values.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        if (format == Format::R8) {
            g.values[i] = float(bytes[i]) / 255.0f;
        } else if (format == Format::R16F) {
            g.values[i] = halfToFloat(std::uint16_t(bytes[2 * i] | (bytes[2 * i + 1] << 8)));
        } else {
            std::memcpy(&g.values[i], &bytes[4 * i], 4);
        }
    }
    g.validate();
    return g;
}

void VolumeGrid::validate() const {
    if (glm::any(glm::lessThan(size, glm::ivec3(1))) || glm::any(glm::greaterThan(size, glm::ivec3(2048))))
        throw std::invalid_argument("sgfx: VolumeGrid: size " + std::to_string(size.x) + "x" +
                                    std::to_string(size.y) + "x" + std::to_string(size.z) +
                                    " is outside 1..2048 per axis");
    const std::size_t count = std::size_t(size.x) * std::size_t(size.y) * std::size_t(size.z);
    if (values.size() != count)
        throw std::invalid_argument("sgfx: VolumeGrid: " + std::to_string(values.size()) + " values for " +
                                    std::to_string(count) + " voxels");
    if (std::uint8_t(format) > std::uint8_t(Format::R32F))
        throw std::invalid_argument("sgfx: VolumeGrid: format has an invalid value " +
                                    std::to_string(int(format)));
    for (std::size_t i = 0; i < count; ++i)
        if (!std::isfinite(values[i]) || values[i] < 0.0f || (format == Format::R8 && values[i] > 1.0f))
            throw std::invalid_argument("sgfx: VolumeGrid: value " + nodes::number(values[i]) + " at voxel " +
                                        std::to_string(i) + " is not a finite density" +
                                        (format == Format::R8 ? " in [0, 1] (R8)" : " >= 0"));
}

void VolumeParameters::validate() const {
    for (int i = 0; i < 3; ++i)
        check("size", size[i], 0.0, 1e7, true);
    check("absorption (k_a)", absorption, 0.0, 1e6);
    check("scattering (k_s)", scattering, 0.0, 1e6);
    for (int i = 0; i < 3; ++i)
        check("emission (k_e)", emission[i], 0.0, 1e6);
    check("densityScale", densityScale, 0.0, 1e6);
    for (int i = 0; i < 3; ++i)
        check("lightColor", lightColor[i], 0.0, 1e6);
    check("ambient", ambient, 0.0, 1e6);
    for (int i = 0; i < 3; ++i)
        check("lightDirection", lightDirection[i], -1e6, 1e6);
    if (!(glm::length(lightDirection) > 0.0f))
        nodes::refuse("VolumeParameters", "lightDirection must not be zero");
    check("g", g, -0.999, 0.999);
    if (steps < 1 || steps > 4096)
        nodes::refuse("VolumeParameters", "steps = " + std::to_string(steps) + " is outside [1, 4096]");
    check("stepLength", stepLength, 0.0, 1e6);
    if (lightSteps < 1 || lightSteps > 256)
        nodes::refuse("VolumeParameters",
                      "lightSteps = " + std::to_string(lightSteps) + " is outside [1, 256]");
    check("earlyTermination", earlyTermination, 0.0, 1.0, true);
    if (std::uint8_t(phase) > std::uint8_t(VolumePhase::Rayleigh))
        nodes::refuse("VolumeParameters", "phase has an invalid value " + std::to_string(int(phase)));
    if (slices < 2 || slices > 4096)
        nodes::refuse("VolumeParameters", "slices = " + std::to_string(slices) + " is outside [2, 4096]");
    check("splatSpacing", splatSpacing, 0.0, 1e6, true);
    if (method == VolumeMethod::Splatting) {
        const long long n = volume::splatLattice(glm::dvec3(size), double(splatSpacing)).total();
        if (n > volume::kMaxSplats)
            nodes::refuse("VolumeParameters", "splatSpacing = " + nodes::number(splatSpacing) + " gives " +
                                                  std::to_string(n) + " kernels in the box, more than " +
                                                  std::to_string(volume::kMaxSplats));
    }
    if (std::uint8_t(method) > std::uint8_t(VolumeMethod::Splatting))
        nodes::refuse("VolumeParameters", "method has an invalid value " + std::to_string(int(method)));
    if (std::uint8_t(integration) > std::uint8_t(volume::Integration::Riemann))
        nodes::refuse("VolumeParameters",
                      "integration has an invalid value " + std::to_string(int(integration)));
}

// ---------------------------------------------------------------- GPU state
struct VolumeNode::Gpu {
    /// A vertex buffer of vec3 rewritten each frame, and its vertex array (attribute 0).
    struct Stream {
        gl::BufferObject buffer;
        gl::VertexArrayObject vao;
        std::size_t capacity = 0;
        /// Grows the buffer if needed and writes `data`; `divisor` 1: one vec3 per instance.
        void write(const std::vector<glm::vec3>& data, unsigned divisor);
    };
    gl::TextureObject density, densityMax, transfer;
    gl::VertexArrayObject vao;
    glm::ivec3 maxSize{1};
    Stream slices, splats;

    /// The density, its block maxima and the transfer ramp (null: none) as textures.
    void uploadGrid(const VolumeGrid& grid, const Image* ramp);
    /// View-aligned slices through the box, blended back to front (VolumeMethod::Slicing).
    void drawSlices(Renderer& r, gl::Program& program, const glm::mat4& model, const VolumeParameters& p);
    /// Gaussian kernels at grid points as billboards, sorted back to front (VolumeMethod::Splatting).
    void drawSplats(Renderer& r, gl::Program& program, const glm::mat4& model, const VolumeParameters& p);
    /// The march at half resolution into the frame resources `colour` and `depth`, then
    /// upsampled onto the view by depth; false when they are not alive in this pass.
    bool drawHalf(Renderer& r, gl::Program& program, const std::string& colour, const std::string& depth);
    /// The splats into the float frame resource `colour`, over transparent black, then composited
    /// over the view once; false when it is not alive in this pass.
    bool drawSplatsOffscreen(Renderer& r, gl::Program& program, const glm::mat4& model,
                             const VolumeParameters& p, const std::string& colour);
};

namespace {
// GL: the node's own draws (its box, slices or splats) from its own vertex array; the renderer has
// no command that draws a drawable's arrays.
void drawArrays(GLuint vao, GLenum mode, GLsizei count, GLsizei instances = 1) {
    glBindVertexArray(vao);
    glDrawArraysInstanced(mode, 0, count, instances);
}
} // namespace

void VolumeNode::Gpu::Stream::write(const std::vector<glm::vec3>& data, unsigned divisor) {
    const auto bytes = GLsizeiptr(data.size() * sizeof(glm::vec3));
    if (!vao || capacity < data.size()) {
        capacity = data.size();
        buffer = gl::createBuffer();
        // GL: the stream's vertex buffer and vertex array (one vec3 attribute, per vertex or per
        // instance), grown here; no command for buffers or vertex arrays yet.
        glNamedBufferData(buffer.get(), bytes, nullptr, GL_STREAM_DRAW);
        vao = gl::createVertexArray();
        glVertexArrayVertexBuffer(vao.get(), 0, buffer.get(), 0, sizeof(glm::vec3));
        glVertexArrayAttribFormat(vao.get(), 0, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao.get(), 0, 0);
        glEnableVertexArrayAttrib(vao.get(), 0);
        glVertexArrayBindingDivisor(vao.get(), 0, divisor); // GL: (as above)
    }
    glNamedBufferSubData(buffer.get(), 0, bytes, data.data()); // GL: this frame's data (as above)
}

namespace {
// Polygons where planes perpendicular to `normal` (world) cut the box, farthest first, as
// triangles in the box frame; `spacing` returns the distance between planes (world metres).
std::vector<glm::vec3> slicePolygons(const glm::mat4& model, glm::vec3 size, glm::vec3 normal, int count,
                                     float& spacing) {
    const glm::vec3 nb = glm::transpose(glm::mat3(model)) * normal; // plane normal in the box frame
    const float offset = glm::dot(normal, glm::vec3(model[3]));
    glm::vec3 corners[8];
    float lo = 1e30f, hi = -1e30f;
    for (int c = 0; c < 8; ++c) {
        corners[c] = (glm::vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1) - 0.5f) * size;
        const float s = glm::dot(nb, corners[c]) + offset;
        lo = std::min(lo, s);
        hi = std::max(hi, s);
    }
    spacing = (hi - lo) / float(count);
    static const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                     {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    const glm::vec3 u = glm::normalize(glm::abs(nb.x) < 0.9f ? glm::cross(nb, glm::vec3(1, 0, 0))
                                                             : glm::cross(nb, glm::vec3(0, 1, 0)));
    const glm::vec3 v = glm::cross(nb, u);
    std::vector<glm::vec3> out;
    for (int k = 0; k < count; ++k) {
        const float s = hi - (float(k) + 0.5f) * spacing;
        glm::vec3 pts[6];
        int n = 0;
        for (const auto& e : edges) {
            const float fa = glm::dot(nb, corners[e[0]]) + offset - s,
                        fb = glm::dot(nb, corners[e[1]]) + offset - s;
            if ((fa < 0) != (fb < 0) && n < 6)
                pts[n++] = corners[e[0]] + (corners[e[1]] - corners[e[0]]) * (fa / (fa - fb));
        }
        if (n < 3) continue;
        glm::vec3 centre(0.0f);
        for (int i = 0; i < n; ++i)
            centre += pts[i];
        centre /= float(n);
        // Around the centre by angle (insertion sort: at most six points).
        float angle[6];
        for (int i = 0; i < n; ++i)
            angle[i] = std::atan2(glm::dot(pts[i] - centre, v), glm::dot(pts[i] - centre, u));
        for (int i = 1; i < n; ++i)
            for (int j = i; j > 0 && angle[j] < angle[j - 1]; --j) {
                std::swap(angle[j], angle[j - 1]);
                std::swap(pts[j], pts[j - 1]);
            }
        for (int i = 1; i + 1 < n; ++i) {
            out.push_back(pts[0]);
            out.push_back(pts[i]);
            out.push_back(pts[i + 1]);
        }
    }
    return out;
}
} // namespace

// ---------------------------------------------------------------- node
std::shared_ptr<VolumeNode> VolumeNode::create(const VolumeParameters& p, VolumeGrid grid) {
    auto n = std::make_shared<VolumeNode>(p, std::move(grid), std::string());
    n->setStateSet(defaultState());
    return n;
}

std::shared_ptr<VolumeNode> VolumeNode::createFunction(const VolumeParameters& p, std::string body) {
    if (body.find_first_not_of(" \t\r\n") == std::string::npos)
        nodes::refuse("VolumeNode::createFunction", "the GLSL body is empty");
    auto n = std::make_shared<VolumeNode>(p, VolumeGrid::constant(1.0f), std::move(body));
    n->setStateSet(defaultState());
    return n;
}

VolumeNode::VolumeNode(const VolumeParameters& p, VolumeGrid grid, std::string function)
    : function_(std::move(function)) {
    p.validate();
    grid.validate();
    parameters_ = p;
    parameters_.lightDirection = glm::normalize(p.lightDirection);
    grid_ = std::move(grid);
    shader_ = makeShader(function_, false);
    halfShader_ = makeShader(function_, true);
    sliceShader_ = makeShader(function_, false, VolumeMethod::Slicing);
    splatShader_ = makeShader(function_, false, VolumeMethod::Splatting);
}

VolumeNode::~VolumeNode() = default;

std::shared_ptr<StateSet> VolumeNode::defaultState() {
    auto s = std::make_shared<StateSet>();
    s->blend.set(BlendMode::Premultiplied);
    s->cullFace.set(CullFace::Front);
    s->depth.set(DepthState{.test = false, .write = false, .func = CompareFunc::Always});
    TransparencyDetails d;
    d.twoPass = false;
    s->transparency.set(d);
    return s;
}

void VolumeNode::setParameters(const VolumeParameters& p) {
    p.validate();
    parameters_ = p;
    parameters_.lightDirection = glm::normalize(p.lightDirection);
    dirtyBound();
}

void VolumeNode::setGrid(VolumeGrid grid) {
    grid.validate();
    grid_ = std::move(grid);
    gridDirty_ = true;
}

void VolumeNode::setTransferFunction(std::shared_ptr<Image> ramp) {
    if (ramp && (ramp->width < 1 || ramp->height < 1 ||
                 ramp->pixels.size() != std::size_t(ramp->width) * ramp->height * ramp->channels))
        nodes::refuse("VolumeNode::setTransferFunction",
                      "the ramp image is empty or its pixel data is short");
    transfer_ = std::move(ramp);
    gridDirty_ = true;
}

const BaseShader& VolumeNode::baseShader() const {
    if (parameters_.method == VolumeMethod::Slicing) return sliceShader_;
    if (parameters_.method == VolumeMethod::Splatting) return splatShader_;
    return parameters_.halfResolution ? halfShader_ : shader_;
}

BoundingSphere VolumeNode::computeBound() const {
    BoundingSphere s;
    s.center = glm::vec3(0.0f);
    s.radius = 0.5f * glm::length(parameters_.size);
    return s;
}

// The blackboard names of this node's offscreen targets (several volumes may be drawn in one
// view): premultiplied colour, and at half resolution the linear depth where each ray stopped.
std::string VolumeNode::halfName(const char* what) const {
    char buf[64];
    std::snprintf(buf, sizeof buf, "volume.%s@%p", what, static_cast<const void*>(this));
    return buf;
}

// The march stops at the view's one scene depth (the opaque items' depth), read while it draws;
// at half resolution it draws into two targets of the renderer's pool first (half the draw
// target's size, odd sides rounding down).
void VolumeNode::setupFrame(FrameSetup& f) const {
    f.requestSceneDepth({.when = PassPhase::AfterOpaque});
    f.sampleInMainPass(std::string(resources::SceneDepth));
    if (parameters_.method == VolumeMethod::Splatting) {
        // Splats accumulate in floats: in an 8-bit target each kernel's small opacity and
        // radiance would round away, more so the more (and fainter) the kernels.
        f.offscreenTargetInMainPass(halfName("splatColour"), {.format = format::Rgba32F});
        return;
    }
    if (!parameters_.halfResolution || parameters_.method != VolumeMethod::Raymarch) return;
    const SizeRule half = SizeRule::half(SizeRule::Round::Down);
    f.offscreenTargetInMainPass(halfName("halfColour"), {.format = format::Rgba16F, .size = half});
    f.offscreenTargetInMainPass(halfName("halfDepth"), {.format = format::R32F, .size = half});
}

void VolumeNode::releaseGLObjects() {
    gpu_.reset();
    gridDirty_ = true;
}

namespace {
// A coarse grid (kMaxBlock voxels per cell) of the density's maxima, dilated by a voxel so
// trilinear filtering never reaches into a skipped cell.
std::vector<float> blockMaxima(const VolumeGrid& grid, glm::ivec3 maxSize) {
    const glm::ivec3 n = grid.size;
    std::vector<float> maxima(std::size_t(maxSize.x) * maxSize.y * maxSize.z, 0.0f);
    for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
            for (int x = 0; x < n.x; ++x) {
                const float v = grid.values[(std::size_t(z) * n.y + y) * n.x + x];
                if (v <= 0.0f) continue;
                for (int dz = -1; dz <= 1; ++dz)
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            const glm::ivec3 c =
                                glm::clamp(glm::ivec3(x + dx, y + dy, z + dz), glm::ivec3(0), n - 1) /
                                kMaxBlock;
                            float& m = maxima[(std::size_t(c.z) * maxSize.y + c.y) * maxSize.x + c.x];
                            m = std::max(m, v);
                        }
            }
    return maxima;
}

void setMarchUniforms(gl::Program& program, const VolumeParameters& p, const glm::mat4& model, bool skip) {
    program.set("u_worldToBox", glm::inverse(model));
    program.set("u_boxSize", p.size);
    program.set("u_absorption", p.absorption);
    program.set("u_scattering", p.scattering);
    program.set("u_emission", p.emission);
    program.set("u_densityScale", p.densityScale);
    program.set("u_lightColor", p.lightColor);
    program.set("u_ambient", p.ambient);
    program.set("u_lightDirection", p.lightDirection);
    program.set("u_phase", int(p.phase));
    program.set("u_g", p.g);
    program.set("u_steps", p.steps);
    program.set("u_stepLength", p.stepLength);
    program.set("u_lightSteps", p.lightSteps);
    program.set("u_threshold", p.earlyTermination);
    program.set("u_integration", int(p.integration));
    program.set("u_jitter", p.jitter ? 1 : 0);
    program.set("u_skip", skip ? 1 : 0);
    program.set("u_countSamples", p.debugSampleCount ? 1 : 0);
}
} // namespace

void VolumeNode::Gpu::uploadGrid(const VolumeGrid& grid, const Image* ramp) {
    // The density (linear filtering, clamped to its edges) and a coarse grid of its maxima.
    const glm::ivec3 n = grid.size;
    static const GLenum formats[] = {GL_R8, GL_R16F, GL_R32F};
    density = gl::createTexture(GL_TEXTURE_3D);
    // GL: the node's 3D textures (density, then its block maxima), made, filled and sampled as
    // set here; the renderer has no command for uploading textures.
    glTextureStorage3D(density.get(), 1, formats[int(grid.format)], n.x, n.y, n.z);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(density.get(), 0, 0, 0, 0, n.x, n.y, n.z, GL_RED, GL_FLOAT, grid.values.data());
    // GL: the density's sampling: clamped to its edges, linear (as the upload above).
    for (GLenum p : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
        glTextureParameteri(density.get(), p, GL_CLAMP_TO_EDGE);
    glTextureParameteri(density.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(density.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    maxSize = (n + kMaxBlock - 1) / kMaxBlock;
    const std::vector<float> maxima = blockMaxima(grid, maxSize);
    densityMax = gl::createTexture(GL_TEXTURE_3D);
    // GL: the block maxima texture (as the density above).
    glTextureStorage3D(densityMax.get(), 1, GL_R32F, maxSize.x, maxSize.y, maxSize.z);
    glTextureSubImage3D(densityMax.get(), 0, 0, 0, 0, maxSize.x, maxSize.y, maxSize.z, GL_RED, GL_FLOAT,
                        maxima.data());
    glTextureParameteri(densityMax.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(densityMax.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    transfer = {};
    if (ramp) {
        const Image& img = *ramp;
        std::vector<unsigned char> rgba(std::size_t(img.width) * 4, 255);
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < std::min(img.channels, 3); ++c)
                rgba[std::size_t(x) * 4 + std::size_t(c)] = img.pixel(x, 0)[img.channels == 1 ? 0 : c];
        transfer = gl::createTexture2D(GL_SRGB8_ALPHA8, img.width, 1, GL_LINEAR);
        // GL: the transfer ramp's texels; no texture upload command.
        glTextureSubImage2D(transfer.get(), 0, 0, 0, img.width, 1, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    }
}

void VolumeNode::Gpu::drawSlices(Renderer& r, gl::Program& program, const glm::mat4& model,
                                 const VolumeParameters& p) {
    const glm::mat4& view = r.frame().view;
    const glm::vec3 forward = -glm::vec3(view[0][2], view[1][2], view[2][2]);
    float spacing = 0.0f;
    const std::vector<glm::vec3> tris = slicePolygons(model, p.size, forward, p.slices, spacing);
    if (tris.empty()) return;
    slices.write(tris, 0);
    program.set("u_sliceNormal", forward);
    program.set("u_spacing", spacing);
    r.setCull(CullFace::None); // slices face either way; the renderer sets the next item's faces
    drawArrays(slices.vao.get(), GL_TRIANGLES, GLsizei(tris.size()));
}

// Splatting (lecture 12): the kernels' centres sorted back to front by view depth on the CPU each
// frame (a sort of at most a few 10⁵ keys, a few ms, is cheaper here than a GPU sort pass and
// keeps the node on the renderer's paths), then one instanced strip per kernel.
void VolumeNode::Gpu::drawSplats(Renderer& r, gl::Program& program, const glm::mat4& model,
                                 const VolumeParameters& p) {
    const volume::SplatLattice l = volume::splatLattice(glm::dvec3(p.size), double(p.splatSpacing));
    const glm::mat4& view = r.frame().view;
    // View depth of a box-frame point: the third row of view·model, negated.
    const glm::mat4 vm = view * model;
    const glm::vec4 depthRow = -glm::vec4(vm[0][2], vm[1][2], vm[2][2], vm[3][2]);
    std::vector<std::pair<float, glm::vec3>> keyed;
    keyed.reserve(std::size_t(l.total()));
    for (int z = 0; z < l.count.z; ++z)
        for (int y = 0; y < l.count.y; ++y)
            for (int x = 0; x < l.count.x; ++x) {
                const glm::vec3 c(l.centre({x, y, z}, glm::dvec3(p.size)));
                keyed.emplace_back(glm::dot(depthRow, glm::vec4(c, 1.0f)), c);
            }
    std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<glm::vec3> centres(keyed.size());
    for (std::size_t i = 0; i < keyed.size(); ++i)
        centres[i] = keyed[i].second;
    splats.write(centres, 1);
    const double R = volume::kSplatRadiusSigmas * l.sigma;
    program.set("u_splatRadius", float(R));
    program.set("u_splatSigma", float(l.sigma));
    program.set("u_splatWeight", float(volume::splatFootprint(0.0, l)));
    r.setCull(CullFace::None); // billboards face the eye; the renderer sets the next item's faces
    drawArrays(splats.vao.get(), GL_TRIANGLE_STRIP, 4, GLsizei(centres.size()));
}

namespace {
// Composites a volume's premultiplied offscreen colour over the view with the renderer's
// premultiplied blending (the item's state, back on after endOffscreen): upsampled by depth from
// the half-size `depth` target, or texel for texel when `depth` is empty (full-size splats,
// already hidden per fragment behind the scene).
void compositeOffscreen(Renderer& r, const std::string& colour, const std::string& depth) {
    static const std::string units = "#define SGFX_VOLUME_HALF_UNIT " + std::to_string(kDensityUnit) + "\n";
    static const BaseShader shaders[2] = {
        {"volume_upsample", "blit.vert", std::string(ShaderComposer::fullscreenVertex()),
         "volume_upsample.frag", nodes::afterVersion(nodes::shaderText("volume_upsample.frag"), units)},
        {"volume_composite", "blit.vert", std::string(ShaderComposer::fullscreenVertex()),
         "volume_upsample.frag",
         nodes::afterVersion(nodes::shaderText("volume_upsample.frag"),
                             units + "#define SGFX_VOLUME_SAME_SIZE\n")}};
    const bool half = !depth.empty();
    gl::Program& composite = r.composer().program(shaders[half ? 0 : 1], {}, 0);
    if (half)
        r.bindFrameResource(composite, "u_sceneDepth", resources::SceneDepth); // the march's bound it too
    r.bindTexture(kDensityUnit, r.frameResourceTexture(colour));
    if (half) r.bindTexture(kDensityUnit + 1, r.frameResourceTexture(depth));
    r.drawFullscreen(composite);
}
} // namespace

bool VolumeNode::Gpu::drawHalf(Renderer& r, gl::Program& program, const std::string& colour,
                               const std::string& depth) {
    // Half resolution: march into the half-size targets, then upsample onto the view by depth.
    // One back face per pixel: written, not blended (beginOffscreen turns blending off, and
    // endOffscreen back on, the renderer's premultiplied blending, for the composite).
    if (!r.beginOffscreen({colour, depth})) return false;
    r.clearColour(0, glm::vec4(0.0f));
    r.clearColour(1, glm::vec4(0.0f));
    program.set("u_pixelScale", 2);
    drawArrays(vao.get(), GL_TRIANGLES, 36);
    r.endOffscreen();
    compositeOffscreen(r, colour, depth);
    return true;
}

bool VolumeNode::Gpu::drawSplatsOffscreen(Renderer& r, gl::Program& program, const glm::mat4& model,
                                          const VolumeParameters& p, const std::string& colour) {
    // Premultiplied over, back to front, from transparent black: the target ends with the
    // splats' radiance and 1 − their transmittance, which one composite lays over the scene.
    // beginOffscreen leaves blending off; endOffscreen restores the item's blending.
    if (!r.beginOffscreen({colour})) return false;
    r.clearColour(0, glm::vec4(0.0f));
    r.setBlend(BlendMode::Premultiplied);
    drawSplats(r, program, model, p);
    r.endOffscreen();
    compositeOffscreen(r, colour, {});
    return true;
}

// The grid's textures (density, block maxima, transfer ramp), made or refreshed before the frame's
// draws.
void VolumeNode::compile(Renderer&) const {
    if (!gpu_) {
        gpu_ = std::make_unique<Gpu>();
        gpu_->vao = gl::createVertexArray();
    }
    if (gridDirty_) {
        gpu_->uploadGrid(grid_, transfer_.get());
        gridDirty_ = false;
    }
}

void VolumeNode::draw(Renderer& r, gl::Program& program, const RenderItem& item) const {
    if (!gpu_ || gridDirty_)
        throw std::logic_error("sgfx: VolumeNode '" + name + "' drawn before the renderer compiled it");
    Gpu& g = *gpu_;
    const VolumeParameters& p = parameters_;
    setMarchUniforms(program, p, item.model, p.emptySpaceSkipping && function_.empty());
    program.setInt3("u_maxGridSize", g.maxSize);
    program.set("u_useTransfer", g.transfer ? 1 : 0);
    // A blended volume is drawn after the opaque items, when the scene depth exists; an opaque
    // one (a state of the user's) marches to the far end of the box.
    const bool depth =
        (item.features & FeatureBlend) && r.bindFrameResource(program, "u_sceneDepth", resources::SceneDepth);
    program.set("u_hasSceneDepth", depth ? 1 : 0);
    r.bindTexture(kDensityUnit, g.density.get());
    r.bindTexture(kDensityUnit + 1, g.densityMax.get());
    r.bindTexture(kDensityUnit + 2, g.transfer.get());
    if (p.method == VolumeMethod::Slicing) {
        g.drawSlices(r, program, item.model, p);
        return;
    }
    if (p.method == VolumeMethod::Splatting) {
        // Into their float target while it is alive (the main pass's transparent items), else
        // straight onto the view (an opaque state of the user's).
        if (!depth || !g.drawSplatsOffscreen(r, program, item.model, p, halfName("splatColour")))
            g.drawSplats(r, program, item.model, p);
        return;
    }
    // The node's own box (36 vertices made in the shader): at half resolution while its targets
    // are alive (the main pass's transparent items), else at full resolution.
    if (p.halfResolution && depth && g.drawHalf(r, program, halfName("halfColour"), halfName("halfDepth")))
        return;
    program.set("u_pixelScale", 1);
    drawArrays(g.vao.get(), GL_TRIANGLES, 36);
}

} // namespace sgfx

#include <sgfx/nodes/splat/GaussianSplatNode.h>
#include <sgfx/nodes/splat/SplatMath.h>

#include "ParameterChecks.h"

#include <sgfx/Renderer.h>
#include <sgfx/StateSet.h>
#include <sgfx/gl/Objects.h>

#include <sgfx_glad/gl.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>

namespace sgfx {

namespace {

constexpr unsigned kSplatBinding = 13, kShBinding = 14, kOrderBinding = 15;
// The GPU sort's buffers: keys and values in, keys and values out, the histogram.
constexpr unsigned kKeysIn = 16, kValuesIn = 17, kKeysOut = 18, kValuesOut = 19, kHistogram = 20;
constexpr std::uint32_t kBlock = 2048; // keys per work group in the histogram and scatter steps

std::unique_ptr<gl::Program> computeProgram(const char* file) {
    ComposedProgram c;
    c.compute = nodes::shaderText(file);
    c.vertexSources = {file};
    c.description = file;
    return std::make_unique<gl::Program>(c);
}

BaseShader makeShader() {
    return BaseShader{"gaussian_splat", "splat.vert", nodes::shaderWithIncludes("splat.vert"), "splat.frag",
                      nodes::shaderText("splat.frag")};
}

// A float's bits as an unsigned key with the same order (negative values flipped whole).
std::uint32_t sortableBits(float f) {
    const auto u = std::bit_cast<std::uint32_t>(f);
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}

} // namespace

struct GaussianSplatNode::Gpu {
    gl::BufferObject splats, sh, order; // order: the sorted values (the GPU sort's values too)
    gl::BufferObject keys, keysOut, valuesOut, histogram;
    std::unique_ptr<gl::Program> keysProgram, histogramProgram, scanProgram, scatterProgram;
    gl::VertexArrayObject empty;
    std::size_t count = 0;
    std::vector<std::uint64_t> cpuKeys; // the CPU sort's (inverted depth, index) pairs
    std::vector<std::uint32_t> indices;
};

std::shared_ptr<GaussianSplatNode> GaussianSplatNode::create(SplatCloud cloud) {
    auto n = std::make_shared<GaussianSplatNode>(std::move(cloud));
    n->setStateSet(defaultState());
    return n;
}

std::shared_ptr<GaussianSplatNode> GaussianSplatNode::load(const std::filesystem::path& file) {
    auto n = create(splat::loadPly(file));
    n->name = file.filename().string();
    return n;
}

GaussianSplatNode::GaussianSplatNode(SplatCloud cloud)
    : shader_(makeShader()) {
    cloud.validate();
    cloud_ = std::move(cloud);
}

GaussianSplatNode::~GaussianSplatNode() = default;

void GaussianSplatNode::setCloud(SplatCloud cloud) {
    cloud.validate();
    cloud_ = std::move(cloud);
    dirty_ = true;
    dirtyBound();
}

std::shared_ptr<StateSet> GaussianSplatNode::defaultState() {
    auto s = std::make_shared<StateSet>();
    s->blend.set(BlendMode::Premultiplied);
    s->cullFace.set(CullFace::None);
    s->depth.set(DepthState{.test = true, .write = false, .func = CompareFunc::LessEqual});
    TransparencyDetails d;
    d.twoPass = false;
    s->transparency.set(d);
    return s;
}

BoundingSphere GaussianSplatNode::computeBound() const {
    BoundingSphere s;
    if (cloud_.size() == 0) return s;
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const glm::vec3& p : cloud_.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    s.center = 0.5f * (lo + hi);
    float r = 0.0f;
    for (std::size_t i = 0; i < cloud_.size(); ++i) {
        const glm::vec3& sc = cloud_.scales[i];
        r = std::max(r, glm::length(cloud_.positions[i] - s.center) + 3.0f * std::max({sc.x, sc.y, sc.z}));
    }
    s.radius = r;
    return s;
}

// The cloud's storage buffers: per splat (position, opacity), (scale, 0), rotation (w, x, y, z);
// the SH coefficients; the order, rewritten by every draw's sort.
void GaussianSplatNode::compile(Renderer&) const {
    if (!gpu_) {
        gpu_ = std::make_unique<Gpu>();
        gpu_->empty = gl::createVertexArray();
    }
    if (!dirty_) return;
    Gpu& g = *gpu_;
    const std::size_t n = cloud_.size();
    std::vector<glm::vec4> data(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        data[3 * i] = glm::vec4(cloud_.positions[i], cloud_.opacities[i]);
        data[3 * i + 1] = glm::vec4(cloud_.scales[i], 0.0f);
        data[3 * i + 2] = glm::normalize(cloud_.rotations[i]);
    }
    // Empty buffers are made one element long: a zero-sized storage binding is an error.
    g.splats = gl::createStorageBuffer(std::max<std::size_t>(data.size(), 1) * sizeof(glm::vec4),
                                       n ? data.data() : nullptr);
    g.sh = gl::createStorageBuffer(std::max<std::size_t>(cloud_.sh.size(), 1) * sizeof(glm::vec3),
                                   n ? cloud_.sh.data() : nullptr);
    const std::size_t words = std::max<std::size_t>(n, 1) * sizeof(std::uint32_t);
    g.order = gl::createStorageBuffer(words);
    g.keys = gl::createStorageBuffer(words);
    g.keysOut = gl::createStorageBuffer(words);
    g.valuesOut = gl::createStorageBuffer(words);
    g.histogram = gl::createStorageBuffer(256 * ((std::max<std::size_t>(n, 1) + kBlock - 1) / kBlock) * 4);
    g.count = n;
    dirty_ = false;
}

// Back to front by view depth (the distance along the view axis, as the reference sorts), ties
// by index: one 64-bit key per splat, std::sort.
void GaussianSplatNode::sortOnCpu(const glm::mat4& modelView) const {
    Gpu& g = *gpu_;
    const std::size_t n = cloud_.size();
    g.cpuKeys.resize(n);
    const glm::vec4 row(modelView[0][2], modelView[1][2], modelView[2][2], modelView[3][2]);
    for (std::size_t i = 0; i < n; ++i) {
        const float depth = -glm::dot(row, glm::vec4(cloud_.positions[i], 1.0f));
        g.cpuKeys[i] = (std::uint64_t(~sortableBits(depth)) << 32) | std::uint64_t(i);
    }
    std::sort(g.cpuKeys.begin(), g.cpuKeys.end());
    g.indices.resize(n);
    for (std::size_t i = 0; i < n; ++i)
        g.indices[i] = std::uint32_t(g.cpuKeys[i]);
    gl::writeBuffer(g.order, 0, n * sizeof(std::uint32_t), g.indices.data());
}

// An LSD radix sort of 32-bit keys in four passes of 8 bits: per-block histograms, one exclusive
// scan, a stable scatter; keys and values ping-pong between the two pairs of buffers and end in
// `keys` and `order` (an even number of passes).
void GaussianSplatNode::sortOnGpu(Renderer& r, const glm::mat4& modelView) const {
    Gpu& g = *gpu_;
    if (!g.keysProgram) {
        g.keysProgram = computeProgram("splat_sort_keys.comp");
        g.histogramProgram = computeProgram("splat_sort_histogram.comp");
        g.scanProgram = computeProgram("splat_sort_scan.comp");
        g.scatterProgram = computeProgram("splat_sort_scatter.comp");
    }
    const auto n = std::uint32_t(g.count);
    const std::uint32_t groups = (n + kBlock - 1) / kBlock;
    r.useProgram(*g.keysProgram);
    g.keysProgram->setUnsigned("u_count", n);
    g.keysProgram->set("u_depthRow",
                       glm::vec4(modelView[0][2], modelView[1][2], modelView[2][2], modelView[3][2]));
    gl::bindStorageBuffer(kSplatBinding, g.splats);
    gl::bindStorageBuffer(kKeysIn, g.keys);
    gl::bindStorageBuffer(kValuesIn, g.order);
    gl::dispatchCompute({(n + 255) / 256, 1, 1});
    gl::bindStorageBuffer(kHistogram, g.histogram);
    for (std::uint32_t shift = 0; shift < 32; shift += 8) {
        const bool even = shift % 16 == 0; // even passes read keys/order, odd ones the other pair
        gl::bindStorageBuffer(kKeysIn, even ? g.keys : g.keysOut);
        gl::bindStorageBuffer(kValuesIn, even ? g.order : g.valuesOut);
        gl::bindStorageBuffer(kKeysOut, even ? g.keysOut : g.keys);
        gl::bindStorageBuffer(kValuesOut, even ? g.valuesOut : g.order);
        r.useProgram(*g.histogramProgram);
        g.histogramProgram->setUnsigned("u_count", n);
        g.histogramProgram->setUnsigned("u_shift", shift);
        g.histogramProgram->setUnsigned("u_block", kBlock);
        gl::dispatchCompute({groups, 1, 1});
        r.useProgram(*g.scanProgram);
        g.scanProgram->setUnsigned("u_entries", 256 * groups);
        gl::dispatchCompute({1, 1, 1});
        r.useProgram(*g.scatterProgram);
        g.scatterProgram->setUnsigned("u_count", n);
        g.scatterProgram->setUnsigned("u_shift", shift);
        g.scatterProgram->setUnsigned("u_block", kBlock);
        gl::dispatchCompute({groups, 1, 1});
    }
}

void GaussianSplatNode::sortFor(Renderer& r, const glm::mat4& modelView) const {
    if (!gpu_ || dirty_ || gpu_->count == 0) return;
    if (sort_ == SplatSort::Gpu)
        sortOnGpu(r, modelView);
    else
        sortOnCpu(modelView);
}

std::vector<std::uint32_t> GaussianSplatNode::lastOrder() const {
    if (!gpu_ || gpu_->count == 0) return {};
    std::vector<std::uint32_t> out(gpu_->count);
    gl::readBuffer(gpu_->order, 0, out.size() * sizeof(std::uint32_t), out.data());
    return out;
}

void GaussianSplatNode::draw(Renderer& r, gl::Program& program, const RenderItem& item) const {
    if (!gpu_ || dirty_)
        throw std::logic_error("sgfx: GaussianSplatNode '" + name +
                               "' drawn before the renderer compiled it");
    Gpu& g = *gpu_;
    if (g.count == 0) return;
    sortFor(r, r.frame().view * item.model);
    r.useProgram(program);
    program.set("u_shDegree", cloud_.shDegree);
    gl::bindStorageBuffer(kSplatBinding, g.splats);
    gl::bindStorageBuffer(kShBinding, g.sh);
    gl::bindStorageBuffer(kOrderBinding, g.order);
    gl::drawPulled(g.empty, GL_TRIANGLE_STRIP, 4, int(g.count));
}

void GaussianSplatNode::releaseGLObjects() {
    gpu_.reset();
    dirty_ = true;
}

} // namespace sgfx

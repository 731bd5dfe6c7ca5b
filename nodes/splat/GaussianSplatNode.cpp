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
    gl::BufferObject splats, sh, order;
    gl::VertexArrayObject empty;
    std::size_t count = 0;
    std::vector<std::uint64_t> keys; // the CPU sort's (inverted depth, index) pairs
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
    g.order = gl::createStorageBuffer(std::max<std::size_t>(n, 1) * sizeof(std::uint32_t));
    g.count = n;
    dirty_ = false;
}

// Back to front by view depth (the distance along the view axis, as the reference sorts), ties
// by index: one 64-bit key per splat, std::sort.
void GaussianSplatNode::sortOnCpu(const glm::mat4& modelView) const {
    Gpu& g = *gpu_;
    const std::size_t n = cloud_.size();
    g.keys.resize(n);
    const glm::vec4 row(modelView[0][2], modelView[1][2], modelView[2][2], modelView[3][2]);
    for (std::size_t i = 0; i < n; ++i) {
        const float depth = -glm::dot(row, glm::vec4(cloud_.positions[i], 1.0f));
        g.keys[i] = (std::uint64_t(~sortableBits(depth)) << 32) | std::uint64_t(i);
    }
    std::sort(g.keys.begin(), g.keys.end());
    g.indices.resize(n);
    for (std::size_t i = 0; i < n; ++i)
        g.indices[i] = std::uint32_t(g.keys[i]);
    gl::writeBuffer(g.order, 0, n * sizeof(std::uint32_t), g.indices.data());
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
    const glm::mat4 modelView = r.frame().view * item.model;
    sortOnCpu(modelView);
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

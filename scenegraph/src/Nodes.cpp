#include "sgfx/Billboard.h"
#include "sgfx/Camera.h"
#include "sgfx/Drawable.h"
#include "sgfx/Effect.h"
#include "sgfx/Geometry.h"
#include "sgfx/Group.h"
#include "sgfx/LOD.h"
#include "sgfx/NodeVisitor.h"
#include "sgfx/StateSet.h"
#include "sgfx/gl/Objects.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {
std::string label(const Node& n) {
    return n.name.empty() ? std::string("<unnamed>") : "'" + n.name + "'";
}
} // namespace

// ---------------------------------------------------------------- Node
Node::~Node() = default;

void Node::accept(NodeVisitor& v) {
    v.apply(*this);
}

StateSet& Node::getOrCreateStateSet() {
    if (!stateSet_) stateSet_ = StateSet::create();
    return *stateSet_;
}

void Node::updateBound() const {
    bound_ = computeBound();
    cullingDisabledBelow_ = computeCullingDisabledBelow();
    boundDirty_ = false;
}

void Node::setCullingActive(bool active) {
    cullingActive_ = active;
    boundDirty_ = false; // force the notification up the parents
    dirtyBound();
}

void Node::dirtyBound() {
    if (boundDirty_) return; // parents were told already
    boundDirty_ = true;
    ++boundChanges_;
    for (Group* p : parents_)
        p->dirtyBound();
}

// ---------------------------------------------------------------- Group
Group::~Group() {
    for (auto& c : children_) {
        auto& ps = c->parents_;
        ps.erase(std::find(ps.begin(), ps.end(), this));
    }
}

void Group::accept(NodeVisitor& v) {
    v.apply(*this);
}

void Group::traverse(NodeVisitor& v) {
    for (const auto& c : children_) {
        if (v.accepts(*c)) c->accept(v);
    }
}

void Group::checkAcyclic(const Node& child) const {
    // A cycle appears when `child` is this group or one of its ancestors.
    std::vector<const Node*> stack{this};
    while (!stack.empty()) {
        const Node* n = stack.back();
        stack.pop_back();
        if (n == &child) {
            throw std::invalid_argument("sgfx: adding " + label(child) + " under " + label(*this) +
                                        " would create a cycle in the scene graph");
        }
        for (const Group* p : n->parents())
            stack.push_back(p);
    }
}

void Group::addChild(NodePtr child) {
    insertChild(children_.size(), std::move(child));
}

void Group::insertChild(std::size_t index, NodePtr child) {
    if (!child) throw std::invalid_argument("sgfx: null child added to group " + label(*this));
    checkAcyclic(*child);
    index = std::min(index, children_.size());
    child->parents_.push_back(this);
    children_.insert(children_.begin() + std::ptrdiff_t(index), std::move(child));
    childInserted(index);
    dirtyBound();
}

bool Group::removeChild(const Node* child) {
    auto it =
        std::find_if(children_.begin(), children_.end(), [&](const NodePtr& c) { return c.get() == child; });
    if (it == children_.end()) return false;
    auto& ps = (*it)->parents_;
    ps.erase(std::find(ps.begin(), ps.end(), this));
    const auto index = std::size_t(it - children_.begin());
    children_.erase(it);
    childRemoved(index);
    dirtyBound();
    return true;
}

void Group::removeChildren() {
    while (!children_.empty())
        removeChild(children_.back().get());
}

void Group::replaceChild(std::size_t index, NodePtr child) {
    if (index >= children_.size())
        throw std::out_of_range("sgfx: replaceChild index " + std::to_string(index) + " out of range in " +
                                label(*this));
    if (!child) throw std::invalid_argument("sgfx: null child given to replaceChild in " + label(*this));
    checkAcyclic(*child);
    auto& ps = children_[index]->parents_;
    ps.erase(std::find(ps.begin(), ps.end(), this));
    child->parents_.push_back(this);
    children_[index] = std::move(child);
    dirtyBound();
}

bool Group::computeCullingDisabledBelow() const {
    return std::any_of(children_.begin(), children_.end(),
                       [](const NodePtr& c) { return c->cullingDisabledInSubtree(); });
}

BoundingSphere Group::computeBound() const {
    // Centre from the children's box, then a radius that holds every child sphere: tighter
    // than growing a sphere child by child.
    BoundingBox box;
    for (const auto& c : children_) {
        const BoundingSphere& s = c->bound();
        if (!s.valid()) continue;
        box.expandBy(s.center - glm::vec3(s.radius));
        box.expandBy(s.center + glm::vec3(s.radius));
    }
    BoundingSphere out;
    if (!box.valid()) return out;
    out.center = box.center();
    out.radius = 0.0f;
    for (const auto& c : children_) {
        const BoundingSphere& s = c->bound();
        if (s.valid()) out.radius = std::max(out.radius, glm::length(s.center - out.center) + s.radius);
    }
    return out;
}

// ---------------------------------------------------------------- Transform
void Transform::accept(NodeVisitor& v) {
    v.apply(*this);
}

void Transform::setMatrix(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r]))
                throw std::invalid_argument("sgfx: Transform " + label(*this) + " given a non-finite matrix");
    matrix_ = m;
    maxScale_ = maxAxisScale(m);
    similarity_ = isSimilarity(m);
    dirtyBound();
}

BoundingSphere Transform::computeBound() const {
    return Group::computeBound().transformed(matrix_);
}

// ---------------------------------------------------------------- Billboard
void Billboard::accept(NodeVisitor& v) {
    v.apply(*this);
}

glm::mat4 Billboard::orientation(const glm::vec3& eye, const glm::vec3& up) const {
    auto isFinite = [](const glm::vec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    const bool finite = isFinite(axis) && isFinite(normal);
    if (!finite || std::abs(glm::length(axis) - 1.0f) > 1e-3f ||
        std::abs(glm::length(normal) - 1.0f) > 1e-3f || std::abs(glm::dot(axis, normal)) > 1e-3f)
        throw std::invalid_argument("sgfx: Billboard " + label(*this) +
                                    ": axis and normal must be finite, perpendicular unit vectors");
    if (!isFinite(eye)) return glm::mat4(1.0f);
    if (mode == Mode::AxialRotation) {
        const glm::vec3 across = eye - axis * glm::dot(eye, axis);
        const float len = glm::length(across);
        if (!(len > 1e-6f * glm::length(eye))) return glm::mat4(1.0f); // on the axis
        const glm::vec3 to = across / len;
        const float angle = std::atan2(glm::dot(glm::cross(normal, to), axis), glm::dot(normal, to));
        return glm::rotate(glm::mat4(1.0f), angle, axis);
    }
    const float distance = glm::length(eye);
    if (!(distance > 0.0f)) return glm::mat4(1.0f);
    const glm::vec3 n = eye / distance;
    // The up that stays: the view's, else the rest axis, else anything across the eye.
    glm::vec3 u = isFinite(up) ? up - n * glm::dot(up, n) : glm::vec3(0.0f);
    if (!(glm::length(u) > 1e-6f)) u = axis - n * glm::dot(axis, n);
    if (!(glm::length(u) > 1e-6f))
        u = glm::cross(n, std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
    u = glm::normalize(u);
    // Map the rest frame (axis x normal, axis, normal) onto (u x n, u, n).
    const glm::mat3 from(glm::cross(axis, normal), axis, normal);
    const glm::mat3 to(glm::cross(u, n), u, n);
    return glm::mat4(to * glm::transpose(from));
}

BoundingSphere Billboard::computeBound() const {
    const BoundingSphere rest = Group::computeBound();
    if (!rest.valid()) return rest;
    if (mode == Mode::AxialRotation) {
        const glm::vec3 onAxis = axis * glm::dot(rest.center, axis);
        return {onAxis, rest.radius + glm::length(rest.center - onAxis)};
    }
    return {glm::vec3(0.0f), rest.radius + glm::length(rest.center)};
}

// ---------------------------------------------------------------- LOD
float pixelSize(const glm::vec3& viewCenter, float radius, const glm::mat4& projection, int viewportHeight) {
    const float w = std::abs(projection[2][3]) * glm::length(viewCenter) + projection[3][3];
    const float pixels = radius * std::abs(projection[1][1]) * float(viewportHeight) / w;
    // An eye at the centre (w = 0) sees the sphere as large as can be: the finest level.
    return std::isfinite(pixels) ? pixels : std::numeric_limits<float>::max();
}

void LOD::accept(NodeVisitor& v) {
    v.apply(*this);
}

void LOD::checkRange(std::size_t index, float minPixels, float maxPixels) const {
    auto refuse = [&](const std::string& why) {
        throw std::invalid_argument("sgfx: LOD " + label(*this) + " child " + std::to_string(index) +
                                    ": range [" + std::to_string(minPixels) + ", " +
                                    std::to_string(maxPixels) + ") " + why);
    };
    if (std::isnan(minPixels) || std::isnan(maxPixels)) refuse("has a NaN bound");
    if (minPixels < 0.0f)
        refuse(rangeMode_ == RangeMode::PixelSize ? "has a negative minimum (sizes are in pixels, >= 0)"
                                                  : "has a negative minimum (distances are >= 0)");
    if (std::isinf(minPixels)) refuse("has an infinite minimum (the child would never show)");
    if (minPixels > maxPixels) refuse("has minPixels > maxPixels");
}

void LOD::addChild(NodePtr child, float minPixels, float maxPixels) {
    const std::size_t index = numChildren();
    checkRange(index, minPixels, maxPixels);
    Group::addChild(std::move(child)); // childInserted makes the slot
    ranges_[index] = {minPixels, maxPixels};
}

void LOD::setRange(std::size_t index, float minPixels, float maxPixels) {
    if (index >= ranges_.size())
        throw std::out_of_range("sgfx: LOD " + label(*this) + " has no child " + std::to_string(index));
    checkRange(index, minPixels, maxPixels);
    ranges_[index] = {minPixels, maxPixels};
}

void LOD::setUserSphere(const glm::vec3& center, float radius) {
    if (!std::isfinite(center.x) || !std::isfinite(center.y) || !std::isfinite(center.z) ||
        !(radius > 0.0f) || !std::isfinite(radius))
        throw std::invalid_argument("sgfx: LOD " + label(*this) +
                                    ": user sphere needs a finite centre and a finite radius > 0 (got " +
                                    std::to_string(radius) + ")");
    userSphere_ = BoundingSphere{center, radius};
}

void LOD::setRangeMode(RangeMode mode) {
    if (mode != RangeMode::PixelSize && mode != RangeMode::DistanceFromEye)
        throw std::invalid_argument("sgfx: LOD " + label(*this) + ": range mode " +
                                    std::to_string(int(mode)) + " is not a LOD::RangeMode");
    rangeMode_ = mode;
}

float LOD::fineness(std::size_t index) const {
    const Range& r = ranges_.at(index);
    return rangeMode_ == RangeMode::PixelSize ? r.maxPixels : -r.minPixels;
}

void LOD::childInserted(std::size_t index) {
    ranges_.insert(ranges_.begin() + std::ptrdiff_t(index), Range{});
}

void LOD::childRemoved(std::size_t index) {
    ranges_.erase(ranges_.begin() + std::ptrdiff_t(index));
}

// ---------------------------------------------------------------- Geometry
Geometry::Geometry() = default;
Geometry::~Geometry() = default;

void Geometry::accept(NodeVisitor& v) {
    v.apply(*this);
}

void Drawable::accept(NodeVisitor& v) {
    v.apply(*this);
}

void Geometry::dirty() {
    ++revision_;
    dirtyBound();
}

std::size_t Geometry::triangleCount() const {
    const std::size_t n = elementCount();
    switch (mode) {
    case PrimitiveMode::Triangles:
        return n / 3 * instanceCount();
    case PrimitiveMode::TriangleStrip:
    case PrimitiveMode::TriangleFan:
        return (n >= 3 ? n - 2 : 0) * instanceCount();
    default:
        return 0;
    }
}

std::shared_ptr<Geometry> Geometry::clone() const {
    auto g = Geometry::create();
    g->name = name;
    g->positions = positions;
    g->normals = normals;
    g->tangents = tangents;
    g->texcoords = texcoords;
    g->texcoords1 = texcoords1;
    g->colors = colors;
    g->indices = indices;
    g->instances = instances;
    g->mode = mode;
    g->joints0 = joints0;
    g->joints1 = joints1;
    g->weights0 = weights0;
    g->weights1 = weights1;
    g->skin = skin;
    g->morphTargets = morphTargets;
    g->morphWeights_ = morphWeights_;
    g->setStateSet(stateSet());
    return g;
}

void Geometry::validate() const {
    const std::size_t n = positions.size();
    auto check = [&](std::size_t size, const char* what) {
        if (size != 0 && size != n)
            throw std::invalid_argument("sgfx: geometry " + label(*this) + " has " + std::to_string(size) +
                                        " " + what + " for " + std::to_string(n) + " positions");
    };
    check(normals.size(), "normals");
    check(tangents.size(), "tangents");
    check(texcoords.size(), "texcoords");
    check(texcoords1.size(), "texcoords1");
    check(colors.size(), "colors");
    check(joints0.size(), "joints0");
    check(weights0.size(), "weights0");
    check(joints1.size(), "joints1");
    check(weights1.size(), "weights1");
    validatePose();
    for (std::size_t i = 0; i < instances.size(); ++i)
        for (int k = 0; k < 16; ++k)
            if (!std::isfinite(instances[i][k / 4][k % 4]))
                throw std::invalid_argument("sgfx: geometry " + label(*this) + " instances[" +
                                            std::to_string(i) + "] has a NaN or infinite element");
    for (std::size_t i = 0; i < indices.size(); ++i) {
        if (indices[i] >= n)
            throw std::invalid_argument("sgfx: geometry " + label(*this) + " index[" + std::to_string(i) +
                                        "] = " + std::to_string(indices[i]) + " is out of range (" +
                                        std::to_string(n) + " vertices)");
    }
}

BoundingSphere Geometry::computeBound() const {
    BoundingBox box;
    if (posed()) {
        box = posedBox();
    } else {
        for (const auto& p : positions)
            box.expandBy(p);
    }
    BoundingSphere s;
    if (!box.valid()) return s;
    if (posed() && instances.empty())
        return BoundingSphere{box.center(), glm::length(box.max - box.min) * 0.5f};
    if (!instances.empty()) {
        // The box of every instance's transformed box: cheap, and tight enough for culling.
        BoundingBox all;
        for (const glm::mat4& m : instances)
            for (int c = 0; c < 8; ++c)
                all.expandBy(
                    glm::vec3(m * glm::vec4(c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y,
                                            c & 4 ? box.max.z : box.min.z, 1.0f)));
        s.center = all.center();
        s.radius = glm::length(all.max - all.min) * 0.5f;
        return s;
    }
    s.center = box.center();
    float r2 = 0.0f;
    for (const auto& p : positions) {
        const glm::vec3 d = p - s.center;
        r2 = std::max(r2, glm::dot(d, d));
    }
    s.radius = std::sqrt(r2);
    return s;
}

// ---------------------------------------------------------------- Camera, Light, EffectNode
void Camera::accept(NodeVisitor& v) {
    v.apply(*this);
}

void Camera::setPerspective(float fovyDegrees, float zNear, float zFar) {
    if (!(fovyDegrees > 0.0f && fovyDegrees < 180.0f))
        throw std::invalid_argument("sgfx: Camera::setPerspective: fovy " + std::to_string(fovyDegrees) +
                                    " must be in (0, 180) degrees");
    if (!(zNear > 0.0f) || !(zFar > zNear) || !std::isfinite(zFar))
        throw std::invalid_argument("sgfx: Camera::setPerspective: need 0 < near < far (got near " +
                                    std::to_string(zNear) + ", far " + std::to_string(zFar) + ")");
    perspective_ = true;
    fovy_ = fovyDegrees;
    zNear_ = zNear;
    zFar_ = zFar;
    projectionMatrix = perspectiveMatrix_ =
        glm::perspective(glm::radians(fovy_), viewport.aspect(), zNear_, zFar_);
}

void Camera::setLookAt(const glm::vec3& eye, const glm::vec3& center, const glm::vec3& up) {
    const glm::vec3 f = center - eye;
    if (!(glm::length(f) > 0.0f) || !(glm::length(glm::cross(f, up)) > 1e-12f))
        throw std::invalid_argument(
            "sgfx: Camera::setLookAt: eye equals centre or view direction is parallel to up");
    viewMatrix = glm::lookAt(eye, center, up);
}

void Camera::setViewport(int x, int y, int w, int h) {
    if (w <= 0 || h <= 0)
        throw std::invalid_argument("sgfx: Camera::setViewport: size " + std::to_string(w) + "x" +
                                    std::to_string(h) + " must be positive");
    const bool refresh = perspective();
    viewport = {x, y, w, h};
    if (refresh)
        projectionMatrix = perspectiveMatrix_ =
            glm::perspective(glm::radians(fovy_), viewport.aspect(), zNear_, zFar_);
}

AntiAliasing AntiAliasing::parse(std::string_view v) {
    if (v == "none") return none();
    if (v == "msaa") return msaa(4);
    if (v.starts_with("msaa") && v.size() == 5 && v[4] >= '1' && v[4] <= '8') return msaa(v[4] - '0');
    if (v.starts_with("ssaa") && v.size() == 5 && v[4] >= '2' && v[4] <= '4') return ssaa(v[4] - '0');
    if (v == "fxaa") return fxaa(FxaaQuality::Medium);
    if (v == "fxaa-low") return fxaa(FxaaQuality::Low);
    if (v == "fxaa-high") return fxaa(FxaaQuality::High);
    if (v == "taa") return taa();
    if (v.starts_with("smaa")) {
        // smaa[-t2x][-low|-medium|-high|-ultra][-luma|-colour|-depth], each part optional.
        std::string_view rest = v.substr(4);
        auto take = [&](std::string_view part) {
            if (!rest.starts_with(part)) return false;
            rest.remove_prefix(part.size());
            return true;
        };
        AntiAliasing a = take("-t2x") ? smaaT2x() : smaa();
        static constexpr std::string_view presets[] = {"-low", "-medium", "-high", "-ultra"};
        static constexpr std::string_view edges[] = {"-luma", "-colour", "-depth"};
        for (std::size_t i = 0; i < 4; ++i)
            if (take(presets[i])) a.smaaPreset = SmaaPreset(i);
        for (std::size_t i = 0; i < 3; ++i)
            if (take(edges[i])) a.smaaEdge = SmaaEdge(i);
        if (rest.empty()) return a;
    }
    throw std::invalid_argument("anti-aliasing '" + std::string(v) + "' is not one of " +
                                std::string(kNames));
}

std::string AntiAliasing::name() const {
    switch (mode) {
    case Mode::None:
        return "none";
    case Mode::Msaa:
        return "msaa" + std::to_string(samples);
    case Mode::Ssaa:
        return "ssaa" + std::to_string(factor);
    case Mode::Fxaa:
        return fxaaQuality == FxaaQuality::Low    ? "fxaa-low"
               : fxaaQuality == FxaaQuality::High ? "fxaa-high"
                                                  : "fxaa";
    case Mode::Taa:
        return "taa";
    case Mode::Smaa:
    case Mode::SmaaT2x: {
        static const char* const presets[] = {"-low", "-medium", "", "-ultra"};
        static const char* const edges[] = {"", "-colour", "-depth"};
        return std::string(mode == Mode::SmaaT2x ? "smaa-t2x" : "smaa") + presets[std::size_t(smaaPreset)] +
               edges[std::size_t(smaaEdge)];
    }
    }
    return "none";
}

void AntiAliasing::validate() const {
    auto refuse = [](const std::string& what) { throw std::invalid_argument("sgfx: AntiAliasing: " + what); };
    if (std::uint8_t(mode) > std::uint8_t(Mode::SmaaT2x))
        refuse("mode has an invalid value " + std::to_string(int(mode)));
    if (samples < 1 || samples > 64) refuse("samples = " + std::to_string(samples) + " is outside [1, 64]");
    if (factor < 1 || factor > 4) refuse("factor = " + std::to_string(factor) + " is outside [1, 4]");
    if (std::uint8_t(fxaaQuality) > std::uint8_t(FxaaQuality::High))
        refuse("fxaaQuality has an invalid value " + std::to_string(int(fxaaQuality)));
    if (!(taaFeedback >= 0.0f && taaFeedback <= 0.98f))
        refuse("taaFeedback = " + std::to_string(taaFeedback) + " is outside [0, 0.98]");
    if (std::uint8_t(smaaPreset) > std::uint8_t(SmaaPreset::Ultra))
        refuse("smaaPreset has an invalid value " + std::to_string(int(smaaPreset)));
    if (std::uint8_t(smaaEdge) > std::uint8_t(SmaaEdge::Depth))
        refuse("smaaEdge has an invalid value " + std::to_string(int(smaaEdge)));
    if (smaaDiagonalSteps < -1 || smaaDiagonalSteps > 19)
        refuse("smaaDiagonalSteps = " + std::to_string(smaaDiagonalSteps) + " is outside [-1, 19]");
}

void Camera::setAntiAliasing(const AntiAliasing& aa) {
    aa.validate();
    antiAliasing_ = aa;
}

glm::vec3 Camera::eyePosition() const {
    return glm::vec3(glm::inverse(viewMatrix)[3]);
}

void Light::accept(NodeVisitor& v) {
    v.apply(*this);
}

void Light::validate() const {
    const std::string who = "sgfx: Light '" + (name.empty() ? std::string("<unnamed>") : name) + "': ";
    auto refuse = [&](const std::string& why) { throw std::invalid_argument(who + why); };
    auto shown = [](float v) {
        char text[32];
        std::snprintf(text, sizeof text, "%g", double(v));
        return std::string(text);
    };
    if (std::uint8_t(type) > std::uint8_t(LightType::Spot))
        refuse("type " + std::to_string(int(type)) + " is not a LightType");
    if (std::uint8_t(falloff) > std::uint8_t(LightFalloff::InverseSquare))
        refuse("falloff " + std::to_string(int(falloff)) + " is not a LightFalloff");
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(color[i]) || color[i] < 0.0f)
            refuse("color = (" + shown(color.x) + ", " + shown(color.y) + ", " + shown(color.z) +
                   ") must be finite and >= 0");
    if (!std::isfinite(intensity) || intensity < 0.0f)
        refuse("intensity = " + shown(intensity) + " must be finite and >= 0");
    if (!std::isfinite(range) || range < 0.0f)
        refuse("range = " + shown(range) + " must be finite and >= 0 (0: unlimited)");
    if (!std::isfinite(position.x + position.y + position.z)) refuse("position must be finite");
    const bool directed = type == LightType::Directional || type == LightType::Spot;
    if (directed &&
        !(std::isfinite(direction.x + direction.y + direction.z) && glm::length(direction) > 0.0f))
        refuse("direction must be finite and not zero");
    if (type != LightType::Spot) return;
    if (!(innerConeAngle >= 0.0f))
        refuse("innerConeAngle = " + shown(innerConeAngle) + " must be >= 0 (radians)");
    if (!(outerConeAngle > innerConeAngle && outerConeAngle <= 1.5707964f))
        refuse("outerConeAngle = " + shown(outerConeAngle) + " must be > innerConeAngle (" +
               shown(innerConeAngle) + ") and <= pi/2 (radians)");
}
void EffectNode::accept(NodeVisitor& v) {
    v.apply(*this);
}

// ---------------------------------------------------------------- StateSet
namespace {
template <class T> void mergeAttr(StateAttr<T>& inherited, const StateAttr<T>& child) {
    if (!child.value) return;
    if (inherited.value && (inherited.flags & Override) && !(child.flags & Protected)) return;
    inherited = child;
}
} // namespace

ResolvedState ResolvedState::defaults() {
    ResolvedState s;
    s.material.set(Material::create());
    s.blend.set(BlendMode::Off);
    s.depth.set(DepthState{});
    s.cullFace.set(CullFace::Back);
    return s;
}

ResolvedState ResolvedState::merged(const StateSet& c) const {
    ResolvedState s = *this;
    mergeAttr(s.material, c.material);
    mergeAttr(s.program, c.program);
    mergeAttr(s.blend, c.blend);
    mergeAttr(s.depth, c.depth);
    mergeAttr(s.cullFace, c.cullFace);
    mergeAttr(s.renderBin, c.renderBin);
    mergeAttr(s.transparency, c.transparency);
    for (const auto& [name, attr] : c.uniforms)
        mergeAttr(s.uniforms[name], attr);
    for (const auto& [name, attr] : c.textures)
        mergeAttr(s.textures[name], attr);
    return s;
}

void TransparencyDetails::validate() const {
    if (!std::isfinite(depthBias) || std::abs(depthBias) > 1e10f)
        throw std::invalid_argument("sgfx: TransparencyDetails: depthBias = " + std::to_string(depthBias) +
                                    " must be finite and within 1e10 metres");
    if (!std::isfinite(resortAngle) || resortAngle < 0.0f || resortAngle > 180.0f)
        throw std::invalid_argument("sgfx: TransparencyDetails: resortAngle = " +
                                    std::to_string(resortAngle) + " must be in [0, 180] degrees");
}

bool ResolvedState::transparent() const {
    if (renderBin.value) return *renderBin.value == RenderBin::Transparent;
    return blendMode() != BlendMode::Off;
}

void Material::validate() const {
    auto finiteNonNeg = [](glm::vec4 v) {
        for (int i = 0; i < 4; ++i)
            if (!std::isfinite(v[i]) || v[i] < 0.0f) return false;
        return true;
    };
    if (!finiteNonNeg(glm::vec4(ambient, 0)) || !finiteNonNeg(diffuse) ||
        !finiteNonNeg(glm::vec4(specular, 0)) || !finiteNonNeg(glm::vec4(emissive, 0)))
        throw std::invalid_argument(
            "sgfx: Material colours (ambient, diffuse, specular, emissive) must be finite "
            "and non-negative");
    if (!std::isfinite(shininess) || shininess < 0.0f)
        throw std::invalid_argument("sgfx: Material shininess must be finite and >= 0");
    if (alphaCutoff && !(*alphaCutoff >= 0.0f && *alphaCutoff <= 1.0f))
        throw std::invalid_argument("sgfx: Material alphaCutoff must be in [0, 1]");
    auto unit = [](float v, const char* what) {
        if (!(v >= 0.0f && v <= 1.0f))
            throw std::invalid_argument(std::string("sgfx: Material ") + what + " must be in [0, 1], not " +
                                        std::to_string(v));
    };
    unit(metallic, "metallic");
    unit(roughness, "roughness");
    unit(occlusionStrength, "occlusionStrength");
    unit(clearcoat, "clearcoat");
    unit(clearcoatRoughness, "clearcoatRoughness");
    unit(specularFactor, "specularFactor");
    if (!finiteNonNeg(glm::vec4(specularColorFactor, 0)))
        throw std::invalid_argument("sgfx: Material specularColorFactor must be finite and non-negative");
    unit(transmission, "transmission");
    if (!(ior == 0.0f || (ior >= 1.0f && std::isfinite(ior))))
        throw std::invalid_argument("sgfx: Material ior must be 0 or a finite value >= 1, not " +
                                    std::to_string(ior));
    if (!(thickness >= 0.0f && std::isfinite(thickness)))
        throw std::invalid_argument("sgfx: Material thickness must be finite and >= 0, not " +
                                    std::to_string(thickness));
    if (!(attenuationDistance > 0.0f)) // infinity is allowed: no absorption
        throw std::invalid_argument("sgfx: Material attenuationDistance must be > 0, not " +
                                    std::to_string(attenuationDistance));
    for (int i = 0; i < 3; ++i)
        if (!(attenuationColor[i] > 0.0f && attenuationColor[i] <= 1.0f))
            throw std::invalid_argument(
                "sgfx: Material attenuationColor must be in (0, 1] per channel, not " +
                std::to_string(attenuationColor[i]));
    if (!std::isfinite(normalScale)) throw std::invalid_argument("sgfx: Material normalScale must be finite");
    if (!std::isfinite(clearcoatNormalScale))
        throw std::invalid_argument("sgfx: Material clearcoatNormalScale must be finite");
    if (model != ShadingModel::BlinnPhong && model != ShadingModel::MetallicRoughness &&
        model != ShadingModel::Unlit)
        throw std::invalid_argument("sgfx: Material model " + std::to_string(int(model)) +
                                    " is not a ShadingModel");
    for (std::size_t i = 0; i < mappings.size(); ++i) {
        const TextureMapping& t = mappings[i];
        if ((t.texCoord != 0 && t.texCoord != 1) || !std::isfinite(t.rotation) ||
            !std::isfinite(t.offset.x + t.offset.y + t.scale.x + t.scale.y))
            throw std::invalid_argument("sgfx: Material mappings[" + std::to_string(i) +
                                        "] needs texCoord 0 or 1 and a finite offset, rotation and scale");
    }
}

glm::mat3 TextureMapping::matrix() const {
    // KHR_texture_transform: T * R * S, where R turns uv by -rotation in the spec's (v down) terms.
    const float c = std::cos(rotation), s = std::sin(rotation);
    const glm::mat3 t(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1);
    const glm::mat3 r(c, -s, 0, s, c, 0, 0, 0, 1);
    const glm::mat3 sc(scale.x, 0, 0, 0, scale.y, 0, 0, 0, 1);
    return t * r * sc;
}

} // namespace sgfx

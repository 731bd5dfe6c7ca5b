#include "sgfx/DOFTransform.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sgfx {

namespace {

std::string label(const Node& n) {
    return n.name.empty() ? std::string("<unnamed>") : "'" + n.name + "'";
}

bool isRotation(DOFTransform::Kind k) {
    return k == DOFTransform::Kind::RotateX || k == DOFTransform::Kind::RotateY ||
           k == DOFTransform::Kind::RotateZ;
}

bool isScale(DOFTransform::Kind k) {
    return k == DOFTransform::Kind::ScaleX || k == DOFTransform::Kind::ScaleY ||
           k == DOFTransform::Kind::ScaleZ;
}

double limited(const DOFTransform::Axis& a, double v) {
    if (a.limit == DOFTransform::Limit::Clamp) return std::clamp(v, a.min, a.max);
    if (v >= a.min && v < a.max) return v; // exactly as given: no round trip through fmod
    const double span = a.max - a.min;
    double w = std::fmod(v - a.min, span);
    if (w < 0.0) w += span;
    // fmod of a tiny negative can round up to the span itself: [min, max) is half open.
    return w >= span ? a.min : a.min + w;
}

// Finite, affine (last row 0 0 0 1) and invertible: the frame and base are placements.
void checkPlacement(const Node& node, const glm::mat4& m, const char* field) {
    bool ok = m[0][3] == 0.0f && m[1][3] == 0.0f && m[2][3] == 0.0f && m[3][3] == 1.0f;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            ok = ok && std::isfinite(m[c][r]);
    const double det = ok ? glm::determinant(glm::dmat3(glm::mat3(m))) : 0.0;
    if (!ok || !(std::abs(det) > 1e-12))
        throw std::invalid_argument("sgfx: DOFTransform " + label(node) + ": " + field +
                                    " must be a finite, affine, invertible matrix");
}

} // namespace

void DOFTransform::addAxis(std::string axis, Kind kind, double min, double max, Limit limit,
                           std::optional<double> initial) {
    const std::string where = "sgfx: DOFTransform " + label(*this) + " axis '" + axis + "': ";
    if (axis.empty())
        throw std::invalid_argument("sgfx: DOFTransform " + label(*this) + ": an axis needs a name");
    for (const Axis& a : axes_) {
        if (a.name == axis) throw std::invalid_argument(where + "the name is already taken");
        if (a.kind == kind)
            throw std::invalid_argument(where + "the node already has an axis of that kind ('" + a.name +
                                        "'): nest another DOFTransform");
    }
    // At rest by default: no turn, no shift, scale 1.
    const double start = initial.value_or(isScale(kind) ? 1.0 : 0.0);
    if (!std::isfinite(min) || !std::isfinite(max) || !std::isfinite(start))
        throw std::invalid_argument(where + "min, max and the initial value must be finite");
    if (min > max) throw std::invalid_argument(where + "min > max");
    if (limit == Limit::Wrap && !isRotation(kind))
        throw std::invalid_argument(where + "only rotations wrap; clamp translations and scales");
    if (limit == Limit::Wrap && !(min < max)) throw std::invalid_argument(where + "wrapping needs min < max");
    Axis a{std::move(axis), kind, min, max, limit, 0.0};
    a.value = limited(a, start);
    axes_.push_back(std::move(a));
    update();
}

const DOFTransform::Axis* DOFTransform::find(std::string_view axis) const {
    for (const Axis& a : axes_)
        if (a.name == axis) return &a;
    return nullptr;
}

void DOFTransform::unknownAxis(std::string_view axis) const {
    std::string names;
    for (const Axis& a : axes_)
        names += (names.empty() ? "'" : ", '") + a.name + "'";
    throw std::invalid_argument("sgfx: DOFTransform " + label(*this) + " has no axis '" + std::string(axis) +
                                "' (its axes: " + (names.empty() ? std::string("none") : names) + ")");
}

double DOFTransform::set(std::string_view axis, double value) {
    Axis* a = const_cast<Axis*>(find(axis));
    if (!a) unknownAxis(axis);
    if (!std::isfinite(value))
        throw std::invalid_argument("sgfx: DOFTransform " + label(*this) + " axis '" + a->name +
                                    "' given a non-finite value");
    const double v = limited(*a, value);
    if (v != a->value) {
        a->value = v;
        update();
    }
    return v;
}

double DOFTransform::value(std::string_view axis) const {
    const Axis* a = find(axis);
    if (!a) unknownAxis(axis);
    return a->value;
}

void DOFTransform::setFrame(const glm::mat4& put) {
    checkPlacement(*this, put, "the frame (put matrix)");
    put_ = put;
    putInverse_ = glm::inverse(glm::dmat4(put));
    update();
}

void DOFTransform::setFrame(const glm::vec3& origin, const glm::mat3& rotation) {
    glm::mat4 put(rotation);
    put[3] = glm::vec4(origin, 1.0f);
    setFrame(put);
}

void DOFTransform::setBase(const glm::mat4& base) {
    checkPlacement(*this, base, "the base matrix");
    base_ = base;
    update();
}

glm::dmat4 DOFTransform::motion() const {
    glm::dvec3 t(0.0), s(1.0);
    double pitch = 0.0, roll = 0.0, heading = 0.0;
    for (const Axis& a : axes_) {
        switch (a.kind) {
        case Kind::RotateX:
            pitch = a.value;
            break;
        case Kind::RotateY:
            roll = a.value;
            break;
        case Kind::RotateZ:
            heading = a.value;
            break;
        case Kind::TranslateX:
            t.x = a.value;
            break;
        case Kind::TranslateY:
            t.y = a.value;
            break;
        case Kind::TranslateZ:
            t.z = a.value;
            break;
        case Kind::ScaleX:
            s.x = a.value;
            break;
        case Kind::ScaleY:
            s.y = a.value;
            break;
        case Kind::ScaleZ:
            s.z = a.value;
            break;
        }
    }
    // Column-major, right-handed: each rotation written out, then T · Rx · Ry · Rz · S.
    const double cp = std::cos(pitch), sp = std::sin(pitch);
    const double cr = std::cos(roll), sr = std::sin(roll);
    const double ch = std::cos(heading), sh = std::sin(heading);
    const glm::dmat4 rx({1, 0, 0, 0}, {0, cp, sp, 0}, {0, -sp, cp, 0}, {0, 0, 0, 1});
    const glm::dmat4 ry({cr, 0, -sr, 0}, {0, 1, 0, 0}, {sr, 0, cr, 0}, {0, 0, 0, 1});
    const glm::dmat4 rz({ch, sh, 0, 0}, {-sh, ch, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1});
    const glm::dmat4 scale({s.x, 0, 0, 0}, {0, s.y, 0, 0}, {0, 0, s.z, 0}, {0, 0, 0, 1});
    glm::dmat4 m = rx * ry * rz * scale;
    m[3] = glm::dvec4(t, 1.0);
    return m;
}

void DOFTransform::update() {
    // In double: a rotor's put and put⁻¹ cancel to well under a float's step.
    const glm::dmat4 m = glm::dmat4(put_) * motion() * putInverse_ * glm::dmat4(base_);
    Transform::setMatrix(glm::mat4(m));
}

} // namespace sgfx

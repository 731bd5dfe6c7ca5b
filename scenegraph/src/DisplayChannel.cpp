#include "sgfx/DisplayChannel.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <set>
#include <stdexcept>

namespace sgfx {
namespace {

[[noreturn]] void fail(std::string_view where, std::string_view what) {
    throw std::invalid_argument("sgfx: " + std::string(where) + ": " + std::string(what));
}

std::string num(double v) {
    std::string s = std::to_string(v);
    while (s.size() > 1 && s.back() == '0' && s[s.size() - 2] != '.')
        s.pop_back();
    return s;
}

bool finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

} // namespace

OffAxisFrustum OffAxisFrustum::fromAngles(float leftDeg, float rightDeg, float downDeg, float upDeg,
                                          float zNear, float zFar) {
    const float angles[] = {leftDeg, rightDeg, downDeg, upDeg};
    const char* names[] = {"left", "right", "down", "up"};
    for (int i = 0; i < 4; ++i)
        if (!(std::abs(angles[i]) < 90.0f))
            fail("OffAxisFrustum::fromAngles",
                 std::string(names[i]) + " = " + num(angles[i]) + " degrees is outside (-90, 90)");
    OffAxisFrustum f;
    f.zNear = zNear;
    f.zFar = zFar;
    f.left = zNear * std::tan(glm::radians(leftDeg));
    f.right = zNear * std::tan(glm::radians(rightDeg));
    f.bottom = zNear * std::tan(glm::radians(downDeg));
    f.top = zNear * std::tan(glm::radians(upDeg));
    f.validate("OffAxisFrustum::fromAngles");
    return f;
}

OffAxisFrustum OffAxisFrustum::sub(double x0, double x1, double y0, double y1) const {
    OffAxisFrustum f = *this;
    f.left = float(left + (double(right) - left) * x0);
    f.right = float(left + (double(right) - left) * x1);
    f.bottom = float(bottom + (double(top) - bottom) * y0);
    f.top = float(bottom + (double(top) - bottom) * y1);
    return f;
}

glm::mat4 OffAxisFrustum::projection() const {
    return glm::frustum(left, right, bottom, top, zNear, zFar);
}

void OffAxisFrustum::validate(std::string_view where) const {
    const float v[] = {left, right, bottom, top, zNear, zFar};
    const char* names[] = {"left", "right", "bottom", "top", "zNear", "zFar"};
    for (int i = 0; i < 6; ++i)
        if (!std::isfinite(v[i])) fail(where, std::string("frustum.") + names[i] + " is not finite");
    if (!(left < right)) fail(where, "frustum.left = " + num(left) + " is not below right = " + num(right));
    if (!(bottom < top)) fail(where, "frustum.bottom = " + num(bottom) + " is not below top = " + num(top));
    if (!(zNear > 0.0f)) fail(where, "frustum.zNear = " + num(zNear) + " is not positive");
    if (!(zFar > zNear)) fail(where, "frustum.zFar = " + num(zFar) + " is not beyond zNear = " + num(zNear));
}

glm::mat4 DisplayChannel::viewMatrix(const glm::mat4& eyeView) const {
    return glm::inverse(viewOffset) * eyeView;
}

void DisplayChannel::validate() const {
    const std::string where = "channel '" + name + "'";
    if (name.empty()) fail("channel", "has an empty name");
    frustum.validate(where);
    if (!finite(viewOffset)) fail(where, "viewOffset is not finite");
    if (std::abs(glm::determinant(glm::mat3(viewOffset)) - 1.0f) > 1e-3f || viewOffset[0][3] != 0.0f ||
        viewOffset[1][3] != 0.0f || viewOffset[2][3] != 0.0f || viewOffset[3][3] != 1.0f)
        fail(where, "viewOffset is not a rotation and translation");
    constexpr int kMax = 16384;
    if (viewport.width < 1 || viewport.height < 1 || viewport.width > kMax || viewport.height > kMax)
        fail(where, "viewport size " + std::to_string(viewport.width) + "x" +
                        std::to_string(viewport.height) + " is outside 1..16384");
    if (viewport.x < 0 || viewport.y < 0 || viewport.x + viewport.width > kMax ||
        viewport.y + viewport.height > kMax)
        fail(where, "viewport origin (" + std::to_string(viewport.x) + ", " + std::to_string(viewport.y) +
                        ") puts it outside [0, 16384)");
}

void validateChannels(const std::vector<DisplayChannel>& channels) {
    if (channels.empty()) fail("display", "has no channels");
    std::set<std::string> names;
    for (std::size_t i = 0; i < channels.size(); ++i) {
        const DisplayChannel& c = channels[i];
        c.validate();
        if (!names.insert(c.name).second) fail("channel '" + c.name + "'", "the name is used twice");
        for (std::size_t j = 0; j < i; ++j) {
            const Viewport& a = channels[j].viewport;
            const Viewport& b = c.viewport;
            if (a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height)
                fail("channel '" + c.name + "'", "viewport overlaps channel '" + channels[j].name + "'");
        }
    }
}

Viewport compositeViewport(const std::vector<DisplayChannel>& channels) {
    Viewport v{0, 0, 0, 0};
    for (const DisplayChannel& c : channels) {
        v.width = std::max(v.width, c.viewport.x + c.viewport.width);
        v.height = std::max(v.height, c.viewport.y + c.viewport.height);
    }
    return v;
}

} // namespace sgfx

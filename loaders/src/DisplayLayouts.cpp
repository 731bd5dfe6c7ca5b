// The cylinder, dome and general channel layouts: channels turned from the eye's view by yaw,
// pitch and roll (and moved, for the general form), each with its own frustum.
#include "DisplayLayouts.h"
#include "sgfx/DisplayConfig.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <optional>

namespace sgfx::display {
namespace {

constexpr int kMax = DisplayConfig::kMaxChannels;
const Range kAngle{-90.0, 90.0, true, true}; // a frustum edge's angle from the view axis
const Range kTurn{-360.0, 360.0};            // yaw and roll

// The channel's view in the eye's view space: translate(t) · Ry(yaw) · Rx(pitch) · Rz(roll), so the
// channel looks along Ry(yaw)·Rx(pitch)·(0, 0, −1): yaw turns left about +Y, pitch then looks up
// about the turned +X, roll then turns the image about the channel's own view axis.
glm::mat4 offset(double yaw, double pitch, double roll, glm::vec3 translation) {
    glm::mat4 m = glm::translate(glm::mat4(1.0f), translation);
    m = glm::rotate(m, float(glm::radians(yaw)), {0.0f, 1.0f, 0.0f});
    m = glm::rotate(m, float(glm::radians(pitch)), {1.0f, 0.0f, 0.0f});
    return glm::rotate(m, float(glm::radians(roll)), {0.0f, 0.0f, 1.0f});
}

// Angles in degrees of a frustum's edges from the view axis (left and down negative for a frustum
// around the axis), each in (−90, 90), left < right, down < up.
OffAxisFrustum angles(const Object& f, float zNear, float zFar) {
    const double left = f.number("left", kAngle), right = f.number("right", kAngle);
    const double down = f.number("down", kAngle), up = f.number("up", kAngle);
    if (!(left < right)) f.fail("right", num(right) + " is not right of left = " + num(left));
    if (!(down < up)) f.fail("up", num(up) + " is not above down = " + num(down));
    return OffAxisFrustum::fromAngles(float(left), float(right), float(down), float(up), zNear, zFar);
}

// The general form's frustum: angles (left, right, down, up in degrees) or near-plane extents
// (left, right, bottom, top in metres, glFrustum's), and near and far.
OffAxisFrustum frustum(const Object& f) {
    const auto [zNear, zFar] = nearFar(f);
    const bool byAngle = f.has("down") || f.has("up");
    if (byAngle && (f.has("bottom") || f.has("top")))
        f.fail(f.has("bottom") ? "bottom" : "top",
               "mixes near-plane extents (bottom, top in metres) with angles (down, up in degrees)");
    if (byAngle) return angles(f, zNear, zFar);
    const Range extent{-1e6, 1e6};
    OffAxisFrustum out;
    out.left = float(f.number("left", extent));
    out.right = float(f.number("right", extent));
    out.bottom = float(f.number("bottom", extent));
    out.top = float(f.number("top", extent));
    if (!(out.left < out.right)) f.fail("right", num(out.right) + " is not right of left = " + num(out.left));
    if (!(out.bottom < out.top)) f.fail("top", num(out.top) + " is not above bottom = " + num(out.bottom));
    out.zNear = zNear;
    out.zFar = zFar;
    return out;
}

// Places the channels' viewports: where every channel gives an origin, there; where none does, in
// a row in list order from (0, 0). `origins` holds each channel's, `path` names the list.
void place(std::vector<DisplayChannel>& channels,
           const std::vector<std::optional<std::array<int, 2>>>& origins, const std::string& source,
           const std::string& path) {
    const bool any = std::any_of(origins.begin(), origins.end(), [](const auto& o) { return o.has_value(); });
    int x = 0;
    for (std::size_t i = 0; i < channels.size(); ++i) {
        if (any && !origins[i])
            Object::fail(source, path + "[" + std::to_string(i) + "].viewport",
                         "is missing: give every channel a viewport or none (a row in list order)");
        Viewport& v = channels[i].viewport;
        v.x = any ? (*origins[i])[0] : x;
        v.y = any ? (*origins[i])[1] : 0;
        x += v.width;
    }
}

std::optional<std::array<int, 2>> origin(const Object& c) {
    if (!c.has("viewport")) return std::nullopt;
    const Json& v = c.array("viewport", 2, 2, "[x, y] of the channel in the composite, pixels");
    return std::array<int, 2>{integerAt(c.source(), v[0], c.at("viewport") + "[0]", 0, 16383),
                              integerAt(c.source(), v[1], c.at("viewport") + "[1]", 0, 16383)};
}

// The cylinder's yaws: evenly spaced `step` apart and centred on straight ahead, or the file's
// list (left to right, so decreasing).
std::vector<double> cylinderYaws(const Object& o, int n, double step) {
    std::vector<double> yaws(std::size_t(n), 0.0);
    for (int i = 0; i < n; ++i)
        yaws[std::size_t(i)] = (0.5 * (n - 1) - i) * step;
    if (!o.has("yaw")) return yaws;
    const Json& list = o.array("yaw", std::size_t(n), std::size_t(n), "one yaw per projector, degrees");
    for (std::size_t i = 0; i < yaws.size(); ++i) {
        const std::string at = o.at("yaw") + "[" + std::to_string(i) + "]";
        yaws[i] = numberAt(o.source(), list[i], at, kTurn);
        if (i > 0 && !(yaws[i] < yaws[i - 1]))
            Object::fail(o.source(), at,
                         num(yaws[i]) + " is not below the previous projector's " + num(yaws[i - 1]) +
                             " (projectors are listed left to right; yaw positive turns left)");
    }
    return yaws;
}

} // namespace

Layout readCylinder(const Object& root) {
    const Object o =
        root.object("cylinder", {"projectors", "fov", "overlap", "yaw", "resolution", "near", "far"});
    const int n = o.integer("projectors", 1, kMax);
    const Object fov = o.object("fov", {"horizontal", "up", "down"});
    const double h = fov.number("horizontal", {0.0, 180.0, true, true});
    const double up = fov.number("up", kAngle), down = fov.number("down", kAngle);
    if (!(down < up)) fov.fail("up", num(up) + " is not above down = " + num(down));
    if (o.has("overlap") && o.has("yaw"))
        o.fail("overlap", "give overlap (evenly spaced projectors) or yaw (each projector's), not both");
    const double overlap = o.number("overlap", {0.0, h, false, true}, 0.0);
    const double step = h - overlap;
    if (n * step > 360.0 + 1e-9)
        o.fail("projectors", std::to_string(n) + " projectors " + num(step) +
                                 " degrees apart (horizontal − overlap) cover more than 360 degrees");
    const std::vector<double> yaws = cylinderYaws(o, n, step);
    const auto [resX, resY] = o.resolution("resolution");
    const auto [zNear, zFar] = nearFar(o);
    Layout out;
    for (int i = 0; i < n; ++i) {
        DisplayChannel c;
        c.name = "p" + std::to_string(i);
        c.viewOffset = offset(yaws[std::size_t(i)], 0.0, 0.0, glm::vec3(0.0f));
        c.frustum =
            OffAxisFrustum::fromAngles(float(-0.5 * h), float(0.5 * h), float(down), float(up), zNear, zFar);
        c.viewport = {i * resX, 0, resX, resY};
        out.channels.push_back(c);
    }
    return out;
}

Layout readDome(const Object& root) {
    const Object o = root.object("dome", {"channels", "near", "far"});
    const auto [zNear, zFar] = nearFar(o);
    const Json& list = o.array("channels", 1, kMax, "the dome's channels");
    Layout out;
    std::vector<std::optional<std::array<int, 2>>> origins;
    for (std::size_t i = 0; i < list.size(); ++i) {
        const Object c(o.source(), list[i], o.at("channels") + "[" + std::to_string(i) + "]",
                       {"name", "yaw", "pitch", "roll", "fov", "resolution", "viewport"});
        DisplayChannel ch;
        ch.name = c.string("name", "ch" + std::to_string(i));
        const double yaw = c.number("yaw", kTurn), pitch = c.number("pitch", {-90.0, 90.0});
        ch.viewOffset = offset(yaw, pitch, c.number("roll", kTurn, 0.0), glm::vec3(0.0f));
        ch.frustum = angles(c.object("fov", {"left", "right", "down", "up"}), zNear, zFar);
        const auto [w, h] = c.resolution("resolution");
        ch.viewport = {0, 0, w, h};
        origins.push_back(origin(c));
        out.channels.push_back(ch);
    }
    place(out.channels, origins, o.source(), o.at("channels"));
    return out;
}

Layout readChannels(const Object& root) {
    const Json& list = root.array("channels", 1, kMax, "the display's channels");
    Layout out;
    std::vector<std::optional<std::array<int, 2>>> origins;
    for (std::size_t i = 0; i < list.size(); ++i) {
        const Object c(root.source(), list[i], "channels[" + std::to_string(i) + "]",
                       {"name", "offset", "frustum", "resolution", "viewport"});
        DisplayChannel ch;
        ch.name = c.string("name", "");
        if (ch.name.empty()) c.fail("name", "is missing or empty (each channel is named)");
        if (c.has("offset")) {
            const Object off = c.object("offset", {"yaw", "pitch", "roll", "translation"});
            glm::vec3 t(0.0f);
            if (off.has("translation")) {
                const Json& v = off.array("translation", 3, 3, "[x, y, z] metres in the eye's view space");
                for (int k = 0; k < 3; ++k)
                    t[k] =
                        float(numberAt(c.source(), v[std::size_t(k)],
                                       off.at("translation") + "[" + std::to_string(k) + "]", {-1e4, 1e4}));
            }
            ch.viewOffset = offset(off.number("yaw", kTurn, 0.0), off.number("pitch", {-90.0, 90.0}, 0.0),
                                   off.number("roll", kTurn, 0.0), t);
        }
        ch.frustum =
            frustum(c.object("frustum", {"left", "right", "down", "up", "bottom", "top", "near", "far"}));
        const auto [w, h] = c.resolution("resolution");
        ch.viewport = {0, 0, w, h};
        origins.push_back(origin(c));
        out.channels.push_back(ch);
    }
    place(out.channels, origins, root.source(), "channels");
    return out;
}

} // namespace sgfx::display

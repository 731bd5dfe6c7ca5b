// A flat wall of columns × rows screens with bezels, seen from one eye point: one plane, so every
// screen shares the eye's view (identity offset) and looks through its own off-axis frustum, the
// crop of one overall frustum. Bezels are rounded to whole pixels at the screen's pixel pitch and
// the frusta fit the rounded bezels, so the composite (with its bezel gaps) is a pixel-exact crop
// of the overall frustum rendered at the composite's size.
#include "DisplayLayouts.h"
#include "sgfx/DisplayConfig.h"

#include <cmath>
#include <cstdint>
#include <tuple>

namespace sgfx::display {
namespace {

struct Wall {
    int columns = 1, rows = 1;
    double width = 1.0, height = 1.0;    // one screen's image, metres
    double bezelX = 0.0, bezelY = 0.0;   // the gaps between neighbouring images, metres
    double distance = 1.0;               // eye to the wall's plane, metres
    std::array<int, 2> resolution{1, 1}; // one screen, pixels
    std::array<double, 2> eye{0.0, 0.0}; // the eye's foot point relative to the wall's centre
    float zNear = 0.1f, zFar = 1000.0f;
};

Wall readFields(const Object& root) {
    const Object o = root.object(
        "wall", {"columns", "rows", "screen", "bezel", "distance", "resolution", "eye", "near", "far"});
    Wall w;
    constexpr int kMax = DisplayConfig::kMaxChannels;
    w.columns = o.integer("columns", 1, kMax);
    w.rows = o.integer("rows", 1, kMax);
    if (w.columns * w.rows > kMax)
        Object::fail(o.source(), "wall",
                     std::to_string(w.columns) + " columns × " + std::to_string(w.rows) +
                         " rows is more than " + std::to_string(kMax) + " channels");
    const Object screen = o.object("screen", {"width", "height"});
    w.width = screen.number("width", {0.0, 1e3, true});
    w.height = screen.number("height", {0.0, 1e3, true});
    if (o.has("bezel")) {
        const Object bezel = o.object("bezel", {"horizontal", "vertical"});
        w.bezelX = bezel.number("horizontal", {0.0, 1e3}, 0.0);
        w.bezelY = bezel.number("vertical", {0.0, 1e3}, 0.0);
    }
    w.distance = o.number("distance", {0.0, 1e4, true});
    w.resolution = o.resolution("resolution");
    if (o.has("eye")) w.eye = o.pair("eye", {-1e4, 1e4});
    std::tie(w.zNear, w.zFar) = nearFar(o);
    return w;
}

// A bezel in whole pixels at the screen's pitch; `field` names it in errors.
int bezelPixels(const Object& o, const char* field, double metres, double pitch, int screens, int pixels) {
    const double px = std::round(metres / pitch);
    const double composite = double(screens) * pixels + double(screens - 1) * px;
    if (composite > 16384.0)
        Object::fail(o.source(), std::string("wall.") + field,
                     num(metres) + " m is " + num(px) + " pixels at the screen's pitch of " + num(pitch) +
                         " m: the composite would be " + num(composite) + " pixels across, more than 16384");
    return int(px);
}

} // namespace

Layout readWall(const Object& root) {
    const Wall w = readFields(root);
    const auto [resX, resY] = w.resolution;
    const double pitchX = w.width / resX, pitchY = w.height / resY;
    const int gapX = bezelPixels(root, "bezel.horizontal", w.bezelX, pitchX, w.columns, resX);
    const int gapY = bezelPixels(root, "bezel.vertical", w.bezelY, pitchY, w.rows, resY);
    const int compW = w.columns * resX + (w.columns - 1) * gapX;
    const int compH = w.rows * resY + (w.rows - 1) * gapY;

    // The wall's plane is z = −distance in the eye's view space; its centre lies straight ahead of
    // the eye's foot point minus `eye`. A wall point (x, y) metres from the composite's bottom-left
    // corner projects to x · near / distance on the near plane (similar triangles).
    const double scale = double(w.zNear) / w.distance;
    const double x0 = -0.5 * compW * pitchX - w.eye[0], y0 = -0.5 * compH * pitchY - w.eye[1];
    auto frustum = [&](int px0, int px1, int py0, int py1) {
        OffAxisFrustum f;
        f.left = float((x0 + px0 * pitchX) * scale);
        f.right = float((x0 + px1 * pitchX) * scale);
        f.bottom = float((y0 + py0 * pitchY) * scale);
        f.top = float((y0 + py1 * pitchY) * scale);
        f.zNear = w.zNear;
        f.zFar = w.zFar;
        return f;
    };
    Layout out;
    out.overall = frustum(0, compW, 0, compH);
    for (int r = 0; r < w.rows; ++r)
        for (int c = 0; c < w.columns; ++c) {
            DisplayChannel ch;
            ch.name = "c" + std::to_string(c) + "r" + std::to_string(r);
            ch.viewport = {c * (resX + gapX), r * (resY + gapY), resX, resY};
            ch.frustum = frustum(ch.viewport.x, ch.viewport.x + resX, ch.viewport.y, ch.viewport.y + resY);
            out.channels.push_back(ch);
        }
    return out;
}

std::pair<float, float> nearFar(const Object& o) {
    const double zNear = o.number("near", {0.0, 1e6, true}, 0.1);
    const double zFar = o.number("far", {0.0, 1e9, true}, 1000.0);
    if (!(zFar > zNear)) o.fail("far", num(zFar) + " is not beyond near = " + num(zNear));
    return {float(zNear), float(zFar)};
}

} // namespace sgfx::display

// Display descriptions (loaders/DisplayConfig): each layout's channels against the closed form of
// its geometry, the cylinder's seams by rendering, and every kind of bad description.
#include "TestUtil.h"

#include <sgfx/DisplayConfig.h>
#include <sgfx/Group.h>
#include <sgfx/Shapes.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

using namespace sgfx;

namespace {

const std::filesystem::path kConfigs =
    std::filesystem::path(SGFX_SOURCE_DIR) / "demos" / "cluster" / "configs";

// Where a point in the eye's view space lands in a channel: pixels from the channel's bottom-left
// corner (continuous: a pixel's centre is at +0.5), through the channel's view and projection.
glm::dvec2 pixelOf(const DisplayChannel& c, glm::vec3 eyePoint) {
    const glm::vec4 clip = c.frustum.projection() * c.viewMatrix(glm::mat4(1.0f)) * glm::vec4(eyePoint, 1.0f);
    const glm::dvec2 ndc = glm::dvec2(clip) / double(clip.w);
    return {(ndc.x + 1.0) * 0.5 * c.viewport.width, (ndc.y + 1.0) * 0.5 * c.viewport.height};
}

} // namespace

// The 2×2 wall of the example: 0.8 × 0.45 m screens of 160 × 90 pixels (5 mm pitch), bezels of
// 22 mm (4.4 px, rounded to 4) and 17 mm (3.4 px, rounded to 3), 1.2 m from the eye.
TEST(DisplayConfig, WallChannelsAreExactCropsOfTheOverallFrustum) {
    const DisplayConfig wall = DisplayConfig::load(kConfigs / "wall-2x2.json");
    EXPECT_EQ(wall.name, "wall-2x2");
    EXPECT_EQ(wall.layout, "wall");
    ASSERT_EQ(wall.channels.size(), 4u);
    ASSERT_TRUE(wall.overall.has_value());

    const double pitch = 0.005, gapX = 4, gapY = 3, dist = 1.2, n = 0.1;
    const int compW = 2 * 160 + 4, compH = 2 * 90 + 3;
    EXPECT_EQ(wall.composite, (Viewport{0, 0, compW, compH}));
    // The wall's extent with the rounded bezels, centred on the eye's axis, scaled to the near plane.
    const double wallW = 2 * 0.8 + gapX * pitch, wallH = 2 * 0.45 + gapY * pitch;
    const double s = n / dist;
    const OffAxisFrustum& o = *wall.overall;
    EXPECT_NEAR(o.left, -0.5 * wallW * s, 1e-7);
    EXPECT_NEAR(o.right, 0.5 * wallW * s, 1e-7);
    EXPECT_NEAR(o.bottom, -0.5 * wallH * s, 1e-7);
    EXPECT_NEAR(o.top, 0.5 * wallH * s, 1e-7);
    EXPECT_FLOAT_EQ(o.zNear, 0.1f);
    EXPECT_FLOAT_EQ(o.zFar, 500.0f);

    for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 2; ++c) {
            const DisplayChannel& ch = wall.channels[std::size_t(r * 2 + c)];
            SCOPED_TRACE(ch.name);
            EXPECT_EQ(ch.name, "c" + std::to_string(c) + "r" + std::to_string(r));
            EXPECT_EQ(ch.viewOffset, glm::mat4(1.0f)); // one plane: the eye's view
            EXPECT_EQ(ch.viewport, (Viewport{c * (160 + 4), r * (90 + 3), 160, 90}));
            // The screen's edges on the wall, metres from its centre: screen c starts c screens
            // and c rounded bezels from the left edge.
            const double x0 = -0.5 * wallW + c * (0.8 + gapX * pitch),
                         y0 = -0.5 * wallH + r * (0.45 + gapY * pitch);
            EXPECT_NEAR(ch.frustum.left, x0 * s, 1e-7);
            EXPECT_NEAR(ch.frustum.right, (x0 + 0.8) * s, 1e-7);
            EXPECT_NEAR(ch.frustum.bottom, y0 * s, 1e-7);
            EXPECT_NEAR(ch.frustum.top, (y0 + 0.45) * s, 1e-7);
            EXPECT_EQ(ch.frustum.zNear, o.zNear);
            EXPECT_EQ(ch.frustum.zFar, o.zFar);
            // The same frustum as the crop of `overall` to the viewport's share of the composite.
            const Viewport& v = ch.viewport;
            const OffAxisFrustum crop = o.sub(double(v.x) / compW, double(v.x + v.width) / compW,
                                              double(v.y) / compH, double(v.y + v.height) / compH);
            EXPECT_NEAR(ch.frustum.left, crop.left, 1e-7);
            EXPECT_NEAR(ch.frustum.right, crop.right, 1e-7);
            EXPECT_NEAR(ch.frustum.bottom, crop.bottom, 1e-7);
            EXPECT_NEAR(ch.frustum.top, crop.top, 1e-7);
        }
    // Bezels are whole pixels: the gap between neighbouring frusta is 4 (3) of the overall image's
    // pixels, not the 4.4 (3.4) of the raw bezel.
    const double pixelX = (o.right - o.left) / compW, pixelY = (o.top - o.bottom) / compH;
    EXPECT_NEAR((wall.channels[1].frustum.left - wall.channels[0].frustum.right) / pixelX, 4.0, 1e-4);
    EXPECT_NEAR((wall.channels[2].frustum.bottom - wall.channels[0].frustum.top) / pixelY, 3.0, 1e-4);
}

// An eye 0.45 m right of and 0.25 m above the wall's centre: the wall point straight ahead of it
// is 90 and 50 pixels (5 mm pitch) right of and above the composite's centre, in screen c1r1.
TEST(DisplayConfig, WallPointStraightAheadOfAnOffsetEye) {
    const DisplayConfig wall = DisplayConfig::parse(R"({"wall": {"columns": 2, "rows": 2,
        "screen": {"width": 0.8, "height": 0.45}, "bezel": {"horizontal": 0.022, "vertical": 0.017},
        "distance": 1.2, "resolution": [160, 90], "eye": [0.45, 0.25]}})",
                                                    "offset-eye.json");
    EXPECT_EQ(wall.name, "offset-eye");
    const glm::vec3 ahead{0.0f, 0.0f, -1.2f}; // on the wall's plane, straight ahead
    const double cx = 324 / 2.0 + 0.45 / 0.005, cy = 183 / 2.0 + 0.25 / 0.005;
    // Through the overall frustum at the composite's size.
    DisplayChannel whole;
    whole.frustum = *wall.overall;
    whole.viewport = wall.composite;
    const glm::dvec2 p = pixelOf(whole, ahead);
    EXPECT_NEAR(p.x, cx, 1e-3);
    EXPECT_NEAR(p.y, cy, 1e-3);
    // Through screen c1r1, at the same composite pixel; outside the other screens.
    for (const DisplayChannel& ch : wall.channels) {
        const glm::dvec2 q = pixelOf(ch, ahead);
        const bool inside = q.x >= 0 && q.x < ch.viewport.width && q.y >= 0 && q.y < ch.viewport.height;
        EXPECT_EQ(inside, ch.name == "c1r1") << ch.name;
        EXPECT_NEAR(q.x + ch.viewport.x, cx, 1e-3) << ch.name;
        EXPECT_NEAR(q.y + ch.viewport.y, cy, 1e-3) << ch.name;
    }
}

namespace {

// The eye looks along world +Y with Z up; eye-space directions are (x right, y up, −z ahead).
const glm::mat4 kEyeView = glm::lookAt(glm::vec3(0.0f), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1));

// A direction in the eye's view space from yaw (positive left) and elevation, degrees.
glm::dvec3 direction(double yawDeg, double elevationDeg) {
    const double y = glm::radians(yawDeg), e = glm::radians(elevationDeg);
    return {-std::sin(y) * std::cos(e), std::sin(e), -std::cos(y) * std::cos(e)};
}

// Renders `scene` (world space) through one channel of the eye kEyeView: a plain viewer of the
// channel's size whose camera takes the channel's view and projection. Returns the lit pixels.
std::vector<glm::ivec2> litPixels(const DisplayChannel& c, const std::shared_ptr<Node>& scene) {
    auto v = Viewer::createHeadless(c.viewport.width, c.viewport.height);
    Camera& cam = *v->camera();
    cam.viewMatrix = c.viewMatrix(kEyeView);
    cam.projectionMatrix = c.frustum.projection();
    cam.clearColor = {0, 0, 0, 1};
    v->setSceneData(scene);
    v->frame();
    const Image img = v->capture();
    std::vector<glm::ivec2> lit;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (test::pixelAt(img, x, y).g > 128)
                lit.push_back({x, img.height - 1 - y}); // rows from the bottom
    return lit;
}

std::shared_ptr<Material> white() {
    auto m = Material::create();
    m->model = ShadingModel::Unlit;
    m->diffuse = glm::vec4(1.0f);
    return m;
}

const char* const kCylinder =
    R"({"cylinder": {"projectors": 3, "fov": {"horizontal": 60, "up": 20, "down": -20},
    %s "resolution": [48, 32]}})";

DisplayConfig cylinder(const std::string& extra) {
    char text[512];
    std::snprintf(text, sizeof text, kCylinder, extra.c_str());
    return DisplayConfig::parse(text, "cylinder.json");
}

} // namespace

// Three 60° projectors with no overlap (yaw 60, 0, −60): the seam between p0 and p1 is 30° left.
// A point on it maps to p0's right edge and p1's left edge at the same height, by the matrices and
// by rendering a thin vertical pole on the seam.
TEST(DisplayConfig, CylinderSeamMapsToMatchingEdgePixels) {
    const DisplayConfig cyl = cylinder("");
    ASSERT_EQ(cyl.channels.size(), 3u);
    EXPECT_FALSE(cyl.overall.has_value());
    EXPECT_EQ(cyl.composite, (Viewport{0, 0, 144, 32}));
    for (int k = 0; k < 2; ++k) {
        const DisplayChannel &a = cyl.channels[std::size_t(k)], &b = cyl.channels[std::size_t(k + 1)];
        EXPECT_EQ(a.viewport.x + a.viewport.width, b.viewport.x); // left to right in the composite
        const double seam = 30.0 - 60.0 * k;
        for (const double elevation : {-15.0, 0.0, 12.0}) {
            const glm::vec3 p = glm::vec3(10.0 * direction(seam, elevation));
            const glm::dvec2 pa = pixelOf(a, p), pb = pixelOf(b, p);
            EXPECT_NEAR(pa.x, 48.0, 1e-3) << "seam " << k << ", elevation " << elevation;
            EXPECT_NEAR(pb.x, 0.0, 1e-3) << "seam " << k << ", elevation " << elevation;
            EXPECT_NEAR(pa.y, pb.y, 1e-3) << "seam " << k << ", elevation " << elevation;
        }
    }

    // A pole of radius 0.15 m, 10 m away on the p0|p1 seam (0.83 pixel wide on each side at the
    // channels' edges), whose ends project to rows 8 and 24 exactly (pixel boundaries): its
    // centre line lies 10·cos 30° ahead along both channels' axes, so z = ±0.5 · 10 cos 30° · tan 20°.
    const double depth = 10.0 * std::cos(glm::radians(30.0));
    const float halfHeight = float(0.5 * depth * std::tan(glm::radians(20.0)));
    const glm::dvec3 d = direction(30.0, 0.0);
    const glm::vec3 base{float(10.0 * d.x), float(-10.0 * d.z), -halfHeight}; // eye (x, −z) = world (x, y)
    auto pole = shapes::cylinder(0.15f, 2.0f * halfHeight, 32);
    pole->getOrCreateStateSet().material.set(white());
    auto t = Transform::create(glm::translate(glm::mat4(1.0f), base));
    t->addChild(pole);
    std::vector<int> rows[2];
    for (int k = 0; k < 3; ++k) {
        const std::vector<glm::ivec2> lit = litPixels(cyl.channels[std::size_t(k)], t);
        if (k == 2) {
            EXPECT_TRUE(lit.empty()) << "p2 sees the pole";
            continue;
        }
        ASSERT_FALSE(lit.empty()) << cyl.channels[std::size_t(k)].name << " does not see the pole";
        const int edge = k == 0 ? 47 : 0;
        for (const glm::ivec2 p : lit) {
            EXPECT_EQ(p.x, edge) << cyl.channels[std::size_t(k)].name << " lit away from its edge";
            rows[k].push_back(p.y);
        }
        std::sort(rows[k].begin(), rows[k].end());
    }
    std::vector<int> expected;
    for (int y = 8; y < 24; ++y)
        expected.push_back(y);
    EXPECT_EQ(rows[0], expected) << "p0's right edge";
    EXPECT_EQ(rows[1], expected) << "p1's left edge";
}

// With 10° of overlap the projectors turn 50° apart (yaw 50, 0, −50); p0 and p1 share yaw 20..30.
// A point at yaw 25 appears in both, at the columns the angles predict: tan 25°/tan 30° of the
// half-width from each axis (p0: 25° right of its axis, p1: 25° left).
TEST(DisplayConfig, CylinderOverlapShowsThePointInBothChannels) {
    const DisplayConfig cyl = cylinder(R"("overlap": 10,)");
    const double yaws[] = {50.0, 0.0, -50.0};
    for (std::size_t k = 0; k < 3; ++k) {
        const glm::dvec3 axis = glm::dvec3(cyl.channels[k].viewOffset * glm::vec4(0, 0, -1, 0));
        EXPECT_NEAR(glm::length(axis - direction(yaws[k], 0.0)), 0.0, 1e-6) << k;
    }
    const double r = std::tan(glm::radians(25.0)) / std::tan(glm::radians(30.0));
    const double col0 = 24.0 * (1.0 + r), col1 = 24.0 * (1.0 - r); // 43.38 and 4.62
    // Inside the overlap's predicted columns: p0's right (1 + tan20/tan30)·24.. 48, p1's left 0..(1 −
    // tan20/tan30)·24.
    const double inner = std::tan(glm::radians(20.0)) / std::tan(glm::radians(30.0));
    EXPECT_GT(col0, 24.0 * (1.0 + inner));
    EXPECT_LT(col1, 24.0 * (1.0 - inner));
    const glm::vec3 p = glm::vec3(10.0 * direction(25.0, 0.0));
    EXPECT_NEAR(pixelOf(cyl.channels[0], p).x, col0, 1e-3);
    EXPECT_NEAR(pixelOf(cyl.channels[1], p).x, col1, 1e-3);
    EXPECT_NEAR(pixelOf(cyl.channels[0], p).y, 16.0, 1e-3);
    EXPECT_NEAR(pixelOf(cyl.channels[1], p).y, 16.0, 1e-3);

    // Rendered: a sphere of radius 0.3 m there; the centroid of its lit pixels in each channel.
    auto ball = shapes::sphere(0.3f, 32, 16);
    ball->getOrCreateStateSet().material.set(white());
    auto t = Transform::create(glm::translate(glm::mat4(1.0f), glm::vec3(p.x, -p.z, p.y)));
    t->addChild(ball);
    const double predicted[] = {col0, col1};
    for (std::size_t k = 0; k < 2; ++k) {
        const std::vector<glm::ivec2> lit = litPixels(cyl.channels[k], t);
        ASSERT_GE(lit.size(), 4u) << cyl.channels[k].name;
        glm::dvec2 sum(0.0);
        for (const glm::ivec2 q : lit)
            sum += glm::dvec2(q) + 0.5;
        const glm::dvec2 centroid = sum / double(lit.size());
        EXPECT_NEAR(centroid.x, predicted[k], 0.6) << cyl.channels[k].name;
        EXPECT_NEAR(centroid.y, 16.0, 0.6) << cyl.channels[k].name;
    }
    EXPECT_TRUE(litPixels(cyl.channels[2], t).empty()) << "p2 sees the point";
}

// The example cylinder: 3 projectors of 60° with 10° overlap, 20° up, 15° down, 160 × 88 each.
TEST(DisplayConfig, CylinderExample) {
    const DisplayConfig cyl = DisplayConfig::load(kConfigs / "cylinder-3.json");
    EXPECT_EQ(cyl.layout, "cylinder");
    ASSERT_EQ(cyl.channels.size(), 3u);
    EXPECT_EQ(cyl.composite, (Viewport{0, 0, 480, 88}));
    const OffAxisFrustum f = OffAxisFrustum::fromAngles(-30, 30, -15, 20, 0.1f, 1000.0f);
    for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_EQ(cyl.channels[k].name, "p" + std::to_string(k));
        EXPECT_EQ(cyl.channels[k].frustum, f);
        EXPECT_EQ(cyl.channels[k].viewport, (Viewport{int(k) * 160, 0, 160, 88}));
        const glm::dvec3 axis = glm::dvec3(cyl.channels[k].viewOffset * glm::vec4(0, 0, -1, 0));
        EXPECT_NEAR(glm::length(axis - direction(50.0 - 50.0 * double(k), 0.0)), 0.0, 1e-6) << k;
    }
    // Explicit yaws, listed left to right, replace the even spacing.
    const DisplayConfig own = cylinder(R"("yaw": [70, 5, -40],)");
    for (std::size_t k = 0; k < 3; ++k) {
        const glm::dvec3 axis = glm::dvec3(own.channels[k].viewOffset * glm::vec4(0, 0, -1, 0));
        EXPECT_NEAR(glm::length(axis - direction(std::array{70.0, 5.0, -40.0}[k], 0.0)), 0.0, 1e-6) << k;
    }
}

// The dome's channels look where their yaw and pitch say: Ry(yaw)·Rx(pitch)·(0, 0, −1) =
// (−sin yaw cos pitch, sin pitch, −cos yaw cos pitch); their up vectors (sin yaw sin pitch,
// cos pitch, cos yaw sin pitch) turned by the roll about the view axis.
TEST(DisplayConfig, DomeChannelDirections) {
    const DisplayConfig dome = DisplayConfig::load(kConfigs / "dome-5.json");
    EXPECT_EQ(dome.layout, "dome");
    ASSERT_EQ(dome.channels.size(), 5u);
    EXPECT_EQ(dome.composite, (Viewport{0, 0, 384, 192}));
    struct Expected {
        const char* name;
        double yaw, pitch;
        Viewport viewport;
    };
    const Expected expected[] = {{"front", 0, 0, {96, 0, 96, 96}},
                                 {"left", 90, 0, {0, 0, 96, 96}},
                                 {"right", -90, 0, {192, 0, 96, 96}},
                                 {"back", 180, 0, {288, 0, 96, 96}},
                                 {"up", 0, 90, {96, 96, 96, 96}}};
    for (std::size_t i = 0; i < 5; ++i) {
        const DisplayChannel& c = dome.channels[i];
        const Expected& e = expected[i];
        EXPECT_EQ(c.name, e.name);
        EXPECT_EQ(c.viewport, e.viewport) << e.name;
        EXPECT_EQ(c.frustum, OffAxisFrustum::fromAngles(-45, 45, -45, 45, 0.1f, 1000.0f)) << e.name;
        const double y = glm::radians(e.yaw), p = glm::radians(e.pitch);
        const glm::dvec3 axis = glm::dvec3(c.viewOffset * glm::vec4(0, 0, -1, 0));
        const glm::dvec3 up = glm::dvec3(c.viewOffset * glm::vec4(0, 1, 0, 0));
        EXPECT_NEAR(glm::length(axis - direction(e.yaw, e.pitch)), 0.0, 1e-6) << e.name;
        EXPECT_NEAR(
            glm::length(up - glm::dvec3(std::sin(y) * std::sin(p), std::cos(p), std::cos(y) * std::sin(p))),
            0.0, 1e-6)
            << e.name;
        EXPECT_EQ(glm::vec3(c.viewOffset[3]), glm::vec3(0.0f)) << e.name; // at the eye point
    }
    // Roll 90 turns the up vector to the channel's left (−right); no viewports: a row in list order.
    const DisplayConfig rolled = DisplayConfig::parse(R"({"dome": {"channels": [
        {"yaw": 30, "pitch": 20, "roll": 90, "fov": {"left": -40, "right": 40, "down": -30, "up": 30}, "resolution": [32, 24]},
        {"name": "b", "yaw": -30, "pitch": 0, "fov": {"left": -40, "right": 40, "down": -30, "up": 30}, "resolution": [16, 24]}]}})",
                                                      "rolled.json");
    const DisplayChannel& c = rolled.channels[0];
    EXPECT_EQ(c.name, "ch0");
    const double y = glm::radians(30.0);
    const glm::dvec3 right0{std::cos(y), 0.0, -std::sin(y)};
    EXPECT_NEAR(glm::length(glm::dvec3(c.viewOffset * glm::vec4(0, 0, -1, 0)) - direction(30, 20)), 0.0,
                1e-6);
    EXPECT_NEAR(glm::length(glm::dvec3(c.viewOffset * glm::vec4(0, 1, 0, 0)) + right0), 0.0, 1e-6);
    EXPECT_EQ(rolled.channels[0].viewport, (Viewport{0, 0, 32, 24}));
    EXPECT_EQ(rolled.channels[1].viewport, (Viewport{32, 0, 16, 24}));
    EXPECT_EQ(rolled.composite, (Viewport{0, 0, 48, 24}));
}

// The general form: offsets with a translation, frusta by angles or by near-plane extents.
TEST(DisplayConfig, GeneralChannels) {
    const DisplayConfig cfg = DisplayConfig::parse(R"({"name": "pair", "channels": [
        {"name": "l", "offset": {"yaw": 10, "translation": [-0.032, 0, 0]},
         "frustum": {"left": -0.05, "right": 0.04, "bottom": -0.03, "top": 0.035, "near": 0.05, "far": 50},
         "resolution": [40, 30], "viewport": [0, 10]},
        {"name": "r", "frustum": {"left": -40, "right": 35, "down": -25, "up": 30}, "resolution": [40, 30],
         "viewport": [50, 0]}]})",
                                                   "pair.json");
    EXPECT_EQ(cfg.name, "pair");
    EXPECT_EQ(cfg.layout, "channels");
    ASSERT_EQ(cfg.channels.size(), 2u);
    const DisplayChannel &l = cfg.channels[0], &r = cfg.channels[1];
    EXPECT_EQ(l.frustum, (OffAxisFrustum{-0.05f, 0.04f, -0.03f, 0.035f, 0.05f, 50.0f}));
    EXPECT_NEAR(glm::length(glm::vec3(l.viewOffset[3]) - glm::vec3(-0.032f, 0, 0)), 0.0, 1e-7);
    EXPECT_NEAR(glm::length(glm::dvec3(l.viewOffset * glm::vec4(0, 0, -1, 0)) - direction(10, 0)), 0.0, 1e-6);
    EXPECT_EQ(r.frustum, OffAxisFrustum::fromAngles(-40, 35, -25, 30, 0.1f, 1000.0f));
    EXPECT_EQ(r.viewOffset, glm::mat4(1.0f));
    EXPECT_EQ(l.viewport, (Viewport{0, 10, 40, 30}));
    EXPECT_EQ(r.viewport, (Viewport{50, 0, 40, 30}));
    EXPECT_EQ(cfg.composite, (Viewport{0, 0, 90, 40}));
    EXPECT_EQ(cfg.find("r"), &r);
    EXPECT_EQ(cfg.find("x"), nullptr);
}

namespace {

// A wall description with one field replaced (or, with an empty value, removed); `field` is
// written as the JSON text of its key and value.
std::string wallWith(const std::string& key, const std::string& value) {
    std::vector<std::pair<std::string, std::string>> fields = {
        {"columns", "2"},
        {"rows", "2"},
        {"screen", R"({"width": 0.8, "height": 0.45})"},
        {"distance", "1.2"},
        {"resolution", "[160, 90]"}};
    bool replaced = false;
    std::string body;
    for (auto& [k, v] : fields) {
        if (k == key) {
            replaced = true;
            if (value.empty()) continue;
            v = value;
        }
        body += (body.empty() ? "" : ", ") + ("\"" + k + "\": " + v);
    }
    if (!replaced) body += ", \"" + key + "\": " + value;
    return R"({"wall": {)" + body + "}}";
}

std::string domeOf(const std::string& channels) {
    return R"({"dome": {"channels": [)" + channels + "]}}";
}

const char* const kFov = R"("fov": {"left": -40, "right": 40, "down": -30, "up": 30})";

std::string domeChannel(const std::string& extra) {
    return std::string(R"({"yaw": 0, "pitch": 0, )") + kFov + R"(, "resolution": [8, 8])" + extra + "}";
}

// The message of the LoadError that parsing `json` as "bad-display.json" throws ("" if none).
std::string errorOf(const std::string& json) {
    try {
        (void)DisplayConfig::parse(json, "bad-display.json");
    } catch (const LoadError& e) {
        return e.what();
    }
    return "";
}

} // namespace

// Every kind of bad description: a LoadError naming the file, the field's JSON path and the
// reason; never another exception.
TEST(DisplayConfig, ErrorsNameTheFileTheFieldAndTheReason) {
    struct Case {
        std::string json, path, reason;
    };
    std::string tooMany;
    for (int i = 0; i < 65; ++i)
        tooMany += (i ? ", " : "") + domeChannel("");
    const std::string deep = std::string(200, '[') + std::string(200, ']');
    const std::vector<Case> cases = {
        // Missing fields, wrong types, out of range, unknown keys.
        {wallWith("distance", ""), "wall.distance", "is missing"},
        {wallWith("columns", R"("2")"), "wall.columns", "is string (\"2\"), not an integer"},
        {wallWith("columns", "2.5"), "wall.columns", "not an integer"},
        {wallWith("columns", "18446744073709551615"), "wall.columns", "out of range 1..64"},
        {wallWith("columns", "0"), "wall.columns", "out of range 1..64"},
        {wallWith("distance", "-1"), "wall.distance", "-1 is out of range (0, 10000]"},
        {wallWith("distance", "1e400"), "invalid JSON", "number overflow parsing '1e400'"},
        {wallWith("screen", R"({"width": 0.8})"), "wall.screen.height", "is missing"},
        {wallWith("screen", "[0.8, 0.45]"), "wall.screen", "not an object"},
        {wallWith("resolution", "[160]"), "wall.resolution", "has 1 elements, expected 2"},
        {wallWith("resolution", "[0, 90]"), "wall.resolution[0]", "out of range 1..16384"},
        {wallWith("colums", "2"), "wall.colums", "unknown key (expected one of: columns, rows"},
        {wallWith("bezel", R"({"horizontal": 1000})"), "wall.bezel.horizontal", "more than 16384"},
        {wallWith("far", "0.05"), "wall.far", "not beyond near = 0.1"},
        {wallWith("eye", "[0, null]"), "wall.eye[1]", "null"},
        {R"({"wall": 3})", "wall", "not an object"},
        {R"({"name": "x"})", "the description", "has no layout"},
        {R"([1, 2])", "the description", "is array"},
        {R"({"wall": {}, "dome": {}})", "dome", "one layout"},
        {R"({"nmae": "x"})", "nmae", "unknown key"},
        {R"({"name": "", "dome": {}})", "name", "is empty"},
        // Too many channels.
        {wallWith("rows", "9").replace(wallWith("rows", "9").find("\"columns\": 2"), 12, "\"columns\": 8"),
         "wall", "8 columns × 9 rows is more than 64 channels"},
        {domeOf(tooMany), "dome.channels", "has 65 elements, expected 1..64"},
        {R"({"cylinder": {"projectors": 65, "fov": {"horizontal": 5, "up": 5, "down": -5}, "resolution": [8, 8]}})",
         "cylinder.projectors", "out of range 1..64"},
        // Cylinders.
        {R"({"cylinder": {"projectors": 7, "fov": {"horizontal": 60, "up": 5, "down": -5}, "resolution": [8, 8]}})",
         "cylinder.projectors", "cover more than 360 degrees"},
        {R"({"cylinder": {"projectors": 2, "fov": {"horizontal": 60, "up": 5, "down": -5}, "overlap": 60, "resolution": [8, 8]}})",
         "cylinder.overlap", "out of range [0, 60)"},
        {R"({"cylinder": {"projectors": 2, "fov": {"horizontal": 60, "up": 5, "down": -5}, "yaw": [-30, 30], "resolution": [8, 8]}})",
         "cylinder.yaw[1]", "listed left to right"},
        {R"({"cylinder": {"projectors": 2, "fov": {"horizontal": 60, "up": 5, "down": -5}, "overlap": 5, "yaw": [30, -30], "resolution": [8, 8]}})",
         "cylinder.overlap", "not both"},
        {R"({"cylinder": {"projectors": 2, "fov": {"horizontal": 60, "up": -5, "down": 5}, "resolution": [8, 8]}})",
         "cylinder.fov.up", "not above down"},
        {R"({"cylinder": {"projectors": 2, "fov": {"horizontal": 180, "up": 5, "down": -5}, "resolution": [8, 8]}})",
         "cylinder.fov.horizontal", "out of range (0, 180)"},
        // Domes.
        {domeOf(domeChannel("") + ", " + domeChannel(R"(, "viewport": [8, 0])")), "dome.channels[0].viewport",
         "give every channel a viewport or none"},
        {domeOf(domeChannel(R"(, "name": "a", "viewport": [0, 0])") + ", " +
                domeChannel(R"(, "name": "b", "viewport": [4, 4])")),
         "dome", "channel 'b': viewport overlaps channel 'a'"},
        {domeOf(domeChannel(R"(, "name": "a")") + ", " + domeChannel(R"(, "name": "a")")), "dome",
         "channel 'a': the name is used twice"},
        {domeOf(R"({"yaw": 0, "pitch": 95, )" + std::string(kFov) + R"(, "resolution": [8, 8]})"),
         "dome.channels[0].pitch", "out of range [-90, 90]"},
        {domeOf(
             R"({"yaw": 0, "pitch": 0, "fov": {"left": 10, "right": -10, "down": -30, "up": 30}, "resolution": [8, 8]})"),
         "dome.channels[0].fov.right", "not right of left"},
        {domeOf(
             R"({"yaw": 0, "pitch": 0, "fov": {"left": -90, "right": 10, "down": -30, "up": 30}, "resolution": [8, 8]})"),
         "dome.channels[0].fov.left", "out of range (-90, 90)"},
        {domeOf(domeChannel(R"(, "rol": 3)")), "dome.channels[0].rol", "unknown key"},
        // The general form.
        {R"({"channels": [{"name": "a", "frustum": {"left": -1, "right": 1, "down": -1, "up": 1}, "resolution": [8, 8]},
            {"name": "b", "frustum": {"left": -1, "right": 1, "down": -1, "up": 1}, "resolution": [8, 8]},
            {"name": "c", "frustum": {"left": "-1", "right": 1, "down": -1, "up": 1}, "resolution": [8, 8]}]})",
         "channels[2].frustum.left", "not a number"},
        {R"({"channels": [{"name": "a", "frustum": {"left": -1, "right": 1, "bottom": -1, "up": 1}, "resolution": [8, 8]}]})",
         "channels[0].frustum.bottom", "mixes near-plane extents"},
        {R"({"channels": [{"name": "a", "frustum": {"left": -1, "right": 1, "top": 1}, "resolution": [8, 8]}]})",
         "channels[0].frustum.bottom", "is missing"},
        {R"({"channels": [{"frustum": {"left": -1, "right": 1, "down": -1, "up": 1}, "resolution": [8, 8]}]})",
         "channels[0].name", "is missing"},
        {R"({"channels": [{"name": "a", "offset": {"translation": [0, 0]}, "frustum": {"left": -1, "right": 1, "down": -1, "up": 1}, "resolution": [8, 8]}]})",
         "channels[0].offset.translation", "has 2 elements, expected 3"},
        {R"({"channels": []})", "channels", "has 0 elements, expected 1..64"},
        // Not JSON at all: nlohmann's line and column.
        {"{\"wall\": {\n  \"columns\": 2,\n  \"rows\": 2,,\n}}", "invalid JSON",
         "parse error at line 3, column 13"},
        {"{\"wall\": ", "invalid JSON", "line 1, column 10"},
        {deep, "the description", "nested deeper than 16 levels"},
        {"   \n\t ", "the description", "the text is empty"},
    };
    for (const Case& c : cases) {
        std::string message;
        EXPECT_NO_THROW(message = errorOf(c.json)) << c.json; // a LoadError or nothing
        SCOPED_TRACE(c.json.substr(0, 200));
        EXPECT_NE(message.find("'bad-display.json'"), std::string::npos) << message;
        EXPECT_NE(message.find(c.path), std::string::npos) << "path '" << c.path << "' in: " << message;
        EXPECT_NE(message.find(c.reason), std::string::npos) << "reason '" << c.reason << "' in: " << message;
    }
}

// Files: an empty one, one that is not there; the file's path is in the message.
TEST(DisplayConfig, FileErrors) {
    const auto dir = std::filesystem::temp_directory_path() / ("sgfx-display-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const auto empty = dir / "empty.json";
    { std::ofstream(empty).flush(); }
    const auto expectError = [](const std::filesystem::path& file, const std::string& reason) {
        try {
            (void)DisplayConfig::load(file);
            ADD_FAILURE() << file << " loaded";
        } catch (const LoadError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find(file.string()), std::string::npos) << m;
            EXPECT_NE(m.find(reason), std::string::npos) << m;
        }
    };
    expectError(empty, "the text is empty");
    expectError(dir / "missing.json", "cannot be opened");
    std::filesystem::remove_all(dir);
}

// The JSON examples of docs/display-channels.md are descriptions this reader accepts.
TEST(DisplayConfig, DocsExamplesParse) {
    const auto page = std::filesystem::path(SGFX_SOURCE_DIR) / "docs" / "display-channels.md";
    std::ifstream in(page);
    ASSERT_TRUE(in) << page;
    std::string line, block;
    bool inside = false;
    std::vector<std::string> layouts;
    while (std::getline(in, line)) {
        if (!inside && line == "```json") {
            inside = true;
            block.clear();
        } else if (inside && line == "```") {
            inside = false;
            try {
                layouts.push_back(DisplayConfig::parse(block, page.string()).layout);
            } catch (const LoadError& e) {
                ADD_FAILURE() << e.what() << "\n" << block;
            }
        } else if (inside) {
            block += line + "\n";
        }
    }
    EXPECT_EQ(layouts, (std::vector<std::string>{"wall", "cylinder", "dome", "channels"}));
}

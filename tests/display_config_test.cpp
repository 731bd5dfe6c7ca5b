// Display descriptions (loaders/DisplayConfig): each layout's channels against the closed form of
// its geometry, the cylinder's seams by rendering, and every kind of bad description.
#include "TestUtil.h"

#include <sgfx/DisplayConfig.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

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

// The windowed path: a GLFW window on Mesa's GLX. CTest runs this program only under xvfb-run
// (tests/CMakeLists.txt), so a missing display is a failure here, never a skip.
#include "TestUtil.h"

#include <sgfx/GraphicsContext.h>

#include <gtest/gtest.h>
#include <sgfx_glad/gl.h>

#include <cstdlib>

using namespace sgfx;
using namespace sgfx::test;

TEST(Window, GlfwWindowRendersAndPresents) {
    const char* display = std::getenv("DISPLAY");
    ASSERT_TRUE(display && *display) << "no DISPLAY: run this test under xvfb-run (CTest does)";
    std::unique_ptr<GlfwWindow> window;
    try {
        window = std::make_unique<GlfwWindow>(96, 64, "sgfx test");
    } catch (const ContextError& e) {
        FAIL() << e.what();
    }
    Viewer v(std::move(window));
    EXPECT_EQ(v.camera()->viewport.width, 96);
    v.camera()->clearColor = {0.5f, 0.25f, 0.0f, 1};
    v.frame();
    const glm::ivec4 p = pixelAt(v.capture(), 10, 10);
    EXPECT_NEAR(p.r, srgbByte(0.5), 1);
    EXPECT_NEAR(p.g, srgbByte(0.25), 1);
    EXPECT_NEAR(p.b, 0, 1);
    // What reaches the window: the copy present() makes into the back buffer holds the same
    // sRGB bytes (no second encode, no decode).
    v.renderer().blitToWindow();
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    std::uint8_t px[4] = {};
    glReadPixels(10, 10, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, px);
    EXPECT_NEAR(px[0], srgbByte(0.5), 1);
    EXPECT_NEAR(px[1], srgbByte(0.25), 1);
    EXPECT_NEAR(px[2], 0, 1);

    // With display channels the window shows their composite, scaled to the window: two 20×32
    // channels 8 pixels apart (a 48×32 composite) fill the 96×64 window, the gap between them
    // black. (One window per process: a second GLFW window here finds no GL strings.)
    DisplayChannel a, b;
    a.name = "a";
    a.viewport = {0, 0, 20, 32};
    b.name = "b";
    b.viewport = {28, 0, 20, 32};
    v.setChannels({a, b});
    std::uint8_t clear[4] = {}, gap[4] = {};
    v.finalDrawCallback = [&](Viewer&) {
        glReadBuffer(GL_BACK);
        glReadPixels(10, 10, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, clear);
        glReadPixels(47, 30, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, gap); // composite texel 23: the gap
    };
    v.frame();
    EXPECT_EQ(v.capture().width, 48);
    EXPECT_NEAR(clear[0], srgbByte(0.5), 1);
    EXPECT_NEAR(clear[1], srgbByte(0.25), 1);
    EXPECT_EQ(gap[0] + gap[1] + gap[2], 0);
    for (const auto& e : v.renderer().takeGlErrors())
        ADD_FAILURE() << "GL: " << e;
}

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
    for (const auto& e : v.renderer().takeGlErrors())
        ADD_FAILURE() << "GL: " << e;
}

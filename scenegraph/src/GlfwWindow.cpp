#include "sgfx/GraphicsContext.h"

#include <glad/gl.h>
// After glad: GLFW must not pull in the system GL header.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdlib>
#include <string>

namespace sgfx {

namespace {
std::string g_glfwError;
void onGlfwError(int, const char* text) {
    g_glfwError = text ? text : "unknown GLFW error";
}
} // namespace

GlfwWindow::GlfwWindow(int width, int height, const std::string& title) {
    const char* x11 = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((!x11 || !*x11) && (!wayland || !*wayland))
        throw ContextError(
            "sgfx: no display (neither DISPLAY nor WAYLAND_DISPLAY is set); cannot open a window");
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) throw ContextError("sgfx: GLFW could not initialise: " + g_glfwError);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
        glfwTerminate();
        throw ContextError("sgfx: GLFW could not open a " + std::to_string(width) + "x" +
                           std::to_string(height) + " OpenGL 4.5 core window: " + g_glfwError);
    }
    makeCurrent();
    glfwSwapInterval(0);
}

GlfwWindow::~GlfwWindow() {
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

void GlfwWindow::makeCurrent() {
    assertOwnerThread();
    glfwMakeContextCurrent(window_);
    loadGl();
}

void GlfwWindow::swapBuffers() {
    glfwSwapBuffers(window_);
}

GetProcAddressFn GlfwWindow::procAddress() const {
    return reinterpret_cast<GetProcAddressFn>(&glfwGetProcAddress);
}

int GlfwWindow::width() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    return w;
}

int GlfwWindow::height() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    return h;
}

bool GlfwWindow::shouldClose() const {
    return glfwWindowShouldClose(window_);
}

} // namespace sgfx

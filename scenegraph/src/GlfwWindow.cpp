#include "sgfx/GraphicsContext.h"

#include <sgfx_glad/gl.h>
// After glad: GLFW must not pull in the system GL header.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdlib>
#include <string>

#if defined(__SANITIZE_ADDRESS__)
#include <dlfcn.h>
#include <link.h>
#endif

namespace sgfx {

namespace {
std::string g_glfwError;
void onGlfwError(int, const char* text) {
    g_glfwError = text ? text : "unknown GLFW error";
}

// Under LeakSanitizer only. GLFW opens libGL, and through it Mesa's GLX driver, and closes them
// in glfwTerminate, before the leak check at exit: what the driver keeps for the process's
// lifetime is then reported from an "<unknown module>" that no suppression can name. Pinning
// every library loaded once the window's context exists keeps them mapped, so
// tests/sanitizers/lsan.supp names them. A no-op in normal builds.
void pinLoadedLibrariesForLeakReports() {
#if defined(__SANITIZE_ADDRESS__)
    dl_iterate_phdr(
        [](dl_phdr_info* info, std::size_t, void*) {
            if (info->dlpi_name && *info->dlpi_name)
                (void)dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
            return 0;
        },
        nullptr);
#endif
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
    pinLoadedLibrariesForLeakReports();
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

#pragma once
#include "sgfx/Export.h"
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

struct GLFWwindow;

namespace sgfx {

/// Creating or using a context failed (no display, no driver, wrong version); what() says which.
class SGFX_API ContextError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

using ProcAddress = void (*)();
using GetProcAddressFn = ProcAddress (*)(const char*);

/// One OpenGL 4.5 core context. GL calls for it happen only on the thread that created it
/// (checked by assertOwnerThread()). Making it current (re)loads the glad function table
/// from this context's getProcAddress when another kind of context was current before.
/// Driver limits the renderer and the nodes choose by (queried once per context, never on a hot
/// path or during cull).
struct SGFX_API DeviceLimits {
    int maxTextureSize = 0;
    int maxSamples = 0;
    int maxTextureBufferSize = 0;
    int maxTextureImageUnits = 0; ///< fragment stage
};
/// The limits of the most recently created context (every context of a process shares one driver):
/// for code that has no context at hand, such as a drawable choosing its shader during cull.
SGFX_API const DeviceLimits& currentDeviceLimits();

class SGFX_API GraphicsContext {
public:
    virtual ~GraphicsContext() = default;
    virtual void makeCurrent() = 0;
    virtual void swapBuffers() {}
    virtual GetProcAddressFn procAddress() const = 0;
    virtual std::string_view kind() const = 0;
    virtual bool isWindow() const { return false; }
    /// Drawable size for windows; headless contexts render to offscreen targets only.
    virtual int width() const { return 0; }
    virtual int height() const { return 0; }
    virtual bool shouldClose() const { return false; }

    void assertOwnerThread() const;
    const std::string& renderer() const { return renderer_; }
    /// The driver's limits, queried once when the context was made current the first time.
    const DeviceLimits& limits() const { return limits_; }
    const std::string& version() const { return version_; }

protected:
    /// Loads GL through glad for this context and checks the version is at least 4.5.
    void loadGl();
    std::thread::id owner_ = std::this_thread::get_id();

private:
    std::string renderer_, version_;
    DeviceLimits limits_;
};

/// Software OpenGL 4.5 core through Mesa's OSMesa (llvmpipe). Needs no display or GPU.
class SGFX_API OsmesaContext : public GraphicsContext {
public:
    /// sgfx draws into its own framebuffers, so OSMesa's own drawable (the default framebuffer)
    /// only needs to exist: 16x16 unless a program draws into it itself (a benchmark of OSMesa's
    /// buffer against framebuffer objects).
    explicit OsmesaContext(int drawableWidth = 16, int drawableHeight = 16);
    ~OsmesaContext() override;
    void makeCurrent() override;
    /// Makes the context current on a drawable of this size, keeping its pixels' memory when it is
    /// large enough. Throws std::invalid_argument for a size outside 1..16384, ContextError when
    /// OSMesa refuses it.
    void resizeDrawable(int width, int height);
    GetProcAddressFn procAddress() const override;
    std::string_view kind() const override { return "osmesa"; }

private:
    void* ctx_ = nullptr;
    std::vector<unsigned char> buffer_;
    int width_ = 0, height_ = 0;
};

/// Headless OpenGL 4.5 core through EGL: the NVIDIA device platform or Mesa surfaceless.
/// libEGL is loaded at run time, so binaries that never use it do not depend on it.
class SGFX_API EglContext : public GraphicsContext {
public:
    EglContext();
    ~EglContext() override;
    void makeCurrent() override;
    GetProcAddressFn procAddress() const override;
    std::string_view kind() const override { return "egl"; }
    const std::string& platform() const { return platform_; }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::string platform_;
};

/// An interactive GLFW window with an OpenGL 4.5 core context.
/// Throws ContextError("no display ...") where no X11/Wayland display is available.
class SGFX_API GlfwWindow : public GraphicsContext {
public:
    GlfwWindow(int width, int height, const std::string& title);
    ~GlfwWindow() override;
    void makeCurrent() override;
    void swapBuffers() override;
    GetProcAddressFn procAddress() const override;
    std::string_view kind() const override { return "glfw"; }
    bool isWindow() const override { return true; }
    int width() const override;
    int height() const override;
    bool shouldClose() const override;
    GLFWwindow* handle() const { return window_; }

private:
    GLFWwindow* window_ = nullptr;
};

/// Best available headless context: OSMesa unless `preferEgl`, falling back to the other.
SGFX_API std::unique_ptr<GraphicsContext> createHeadlessContext(bool preferEgl = false);

} // namespace sgfx

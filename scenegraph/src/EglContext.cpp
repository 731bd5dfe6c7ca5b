#include "sgfx/GraphicsContext.h"

#include <sgfx_glad/gl.h>
#define EGL_EGL_PROTOTYPES 0
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <dlfcn.h>

#include <cstring>
#include <string>
#include <vector>

namespace sgfx {

// EGL through dlopen: a binary that only uses OSMesa never needs libEGL.
struct EglContext::Impl {
    void* lib = nullptr;
    PFNEGLGETPROCADDRESSPROC getProcAddress = nullptr;
    PFNEGLINITIALIZEPROC initialize = nullptr;
    PFNEGLTERMINATEPROC terminate = nullptr;
    PFNEGLBINDAPIPROC bindApi = nullptr;
    PFNEGLCHOOSECONFIGPROC chooseConfig = nullptr;
    PFNEGLCREATECONTEXTPROC createContext = nullptr;
    PFNEGLDESTROYCONTEXTPROC destroyContext = nullptr;
    PFNEGLMAKECURRENTPROC makeCurrent = nullptr;
    PFNEGLQUERYSTRINGPROC queryString = nullptr;
    PFNEGLGETERRORPROC getError = nullptr;
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;

    template <class F> void load(F& f, const char* name) {
        f = reinterpret_cast<F>(dlsym(lib, name));
        if (!f) throw ContextError(std::string("sgfx: libEGL lacks ") + name);
    }
    std::string error() const {
        char buf[32];
        std::snprintf(buf, sizeof buf, "0x%04x", getError ? unsigned(getError()) : 0u);
        return buf;
    }
};

namespace {
// eglGetProcAddress is per library, not per context: keep the one the current EglContext uses.
PFNEGLGETPROCADDRESSPROC g_eglGetProcAddress = nullptr;
ProcAddress eglProc(const char* name) {
    return reinterpret_cast<ProcAddress>(g_eglGetProcAddress(name));
}

bool hasExtension(const char* list, const char* ext) {
    if (!list) return false;
    const std::size_t n = std::strlen(ext);
    for (const char* p = list; (p = std::strstr(p, ext)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}
} // namespace

EglContext::EglContext()
    : impl_(std::make_unique<Impl>()) {
    Impl& e = *impl_;
    e.lib = dlopen("libEGL.so.1", RTLD_NOW | RTLD_LOCAL);
    if (!e.lib) throw ContextError(std::string("sgfx: cannot load libEGL.so.1: ") + dlerror());
    e.load(e.getProcAddress, "eglGetProcAddress");
    e.load(e.initialize, "eglInitialize");
    e.load(e.terminate, "eglTerminate");
    e.load(e.bindApi, "eglBindAPI");
    e.load(e.chooseConfig, "eglChooseConfig");
    e.load(e.createContext, "eglCreateContext");
    e.load(e.destroyContext, "eglDestroyContext");
    e.load(e.makeCurrent, "eglMakeCurrent");
    e.load(e.queryString, "eglQueryString");
    e.load(e.getError, "eglGetError");

    const char* clientExts = e.queryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto getPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(e.getProcAddress("eglGetPlatformDisplayEXT"));
    auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(e.getProcAddress("eglQueryDevicesEXT"));
    std::string tried;
    // 1. A GPU through the device platform (NVIDIA's headless path).
    if (getPlatformDisplay && queryDevices && hasExtension(clientExts, "EGL_EXT_platform_device")) {
        EGLDeviceEXT devices[16];
        EGLint count = 0;
        if (queryDevices(16, devices, &count)) {
            for (EGLint i = 0; i < count && e.display == EGL_NO_DISPLAY; ++i) {
                EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
                EGLint maj = 0, min = 0;
                if (d != EGL_NO_DISPLAY && e.initialize(d, &maj, &min)) {
                    e.display = d;
                    platform_ = "device " + std::to_string(i);
                }
            }
        }
        tried += "device platform; ";
    }
    // 2. Mesa's surfaceless platform (software or any Mesa driver).
    if (e.display == EGL_NO_DISPLAY && getPlatformDisplay &&
        hasExtension(clientExts, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        EGLint maj = 0, min = 0;
        if (d != EGL_NO_DISPLAY && e.initialize(d, &maj, &min)) {
            e.display = d;
            platform_ = "surfaceless";
        }
        tried += "surfaceless platform; ";
    }
    if (e.display == EGL_NO_DISPLAY)
        throw ContextError("sgfx: no usable EGL display (tried: " +
                           (tried.empty() ? std::string("nothing") : tried) + "EGL error " + e.error() + ")");
    if (!e.bindApi(EGL_OPENGL_API)) throw ContextError("sgfx: EGL cannot bind the desktop OpenGL API");
    const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint n = 0;
    if (!e.chooseConfig(e.display, configAttribs, &config, 1, &n) || n < 1) config = nullptr; // configless
    const EGLint ctxAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                 4,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
    e.context = e.createContext(e.display, config, EGL_NO_CONTEXT, ctxAttribs);
    if (e.context == EGL_NO_CONTEXT)
        throw ContextError("sgfx: EGL (" + platform_ +
                           ") could not create an OpenGL 4.5 core context: EGL error " + e.error());
    makeCurrent();
}

EglContext::~EglContext() {
    Impl& e = *impl_;
    if (e.context != EGL_NO_CONTEXT) {
        e.makeCurrent(e.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        e.destroyContext(e.display, e.context);
    }
    // The display is left initialised: other EGL users in the process may share it.
}

void EglContext::makeCurrent() {
    assertOwnerThread();
    Impl& e = *impl_;
    if (!e.makeCurrent(e.display, EGL_NO_SURFACE, EGL_NO_SURFACE, e.context))
        throw ContextError("sgfx: eglMakeCurrent (surfaceless) failed: EGL error " + e.error());
    g_eglGetProcAddress = e.getProcAddress;
    loadGl();
}

GetProcAddressFn EglContext::procAddress() const {
    return &eglProc;
}

} // namespace sgfx

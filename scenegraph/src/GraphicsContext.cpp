#include "sgfx/GraphicsContext.h"

#include <sgfx_glad/gl.h>

#include <cstdio>
#include <cstdlib>

namespace sgfx {

namespace {
// glad keeps one process-wide function table; remember whose getProcAddress filled it.
GetProcAddressFn g_loadedFrom = nullptr;
DeviceLimits g_limits; // of the most recently created context
} // namespace

void GraphicsContext::loadGl() {
    const GetProcAddressFn proc = procAddress();
    if (g_loadedFrom != proc) {
        if (!sgfx_gladLoadGL(reinterpret_cast<SGFX_GLADloadfunc>(proc)))
            throw ContextError("sgfx: could not load OpenGL functions through the " + std::string(kind()) +
                               " context");
        g_loadedFrom = proc;
    }
    if (!renderer_.empty()) return;
    const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const auto* v = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    if (!r || !v)
        throw ContextError("sgfx: glGetString returned NULL on the " + std::string(kind()) +
                           " context (is libGL linked into an OSMesa binary?)");
    renderer_ = r;
    version_ = v;
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor < 45)
        throw ContextError("sgfx: OpenGL 4.5 core is required, the " + std::string(kind()) +
                           " context gives " + version_ + " (" + renderer_ + ")");
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &limits_.maxTextureSize);
    glGetIntegerv(GL_MAX_SAMPLES, &limits_.maxSamples);
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &limits_.maxTextureBufferSize);
    glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &limits_.maxTextureImageUnits);
    g_limits = limits_;
}

const DeviceLimits& currentDeviceLimits() {
    return g_limits;
}

void GraphicsContext::assertOwnerThread() const {
    if (std::this_thread::get_id() != owner_) {
        std::fprintf(stderr, "sgfx: GL call for the %.*s context from a thread that does not own it\n",
                     int(kind().size()), kind().data());
        std::abort();
    }
}

std::unique_ptr<GraphicsContext> createHeadlessContext(bool preferEgl) {
    if (preferEgl) {
        try {
            return std::make_unique<EglContext>();
        } catch (const ContextError&) {
            return std::make_unique<OsmesaContext>();
        }
    }
    try {
        return std::make_unique<OsmesaContext>();
    } catch (const ContextError&) {
        return std::make_unique<EglContext>();
    }
}

} // namespace sgfx

#include "sgfx/GraphicsContext.h"

#include <sgfx_glad/gl.h>
// After glad, so osmesa.h's GL/gl.h include is a no-op.
#include <GL/osmesa.h>

namespace sgfx {

namespace {
// All rendering goes to sgfx's own framebuffers; OSMesa needs a drawable, so give it a tiny one.
constexpr int kBufferSize = 16;
} // namespace

OsmesaContext::OsmesaContext() {
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           24,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           4,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           5,
                           0};
    ctx_ = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx_) throw ContextError("sgfx: OSMesa could not create an OpenGL 4.5 core context (Mesa too old?)");
    buffer_ = std::make_unique<unsigned char[]>(kBufferSize * kBufferSize * 4);
    makeCurrent();
}

OsmesaContext::~OsmesaContext() {
    if (ctx_) OSMesaDestroyContext(static_cast<OSMesaContext>(ctx_));
}

void OsmesaContext::makeCurrent() {
    assertOwnerThread();
    if (!OSMesaMakeCurrent(static_cast<OSMesaContext>(ctx_), buffer_.get(), GL_UNSIGNED_BYTE, kBufferSize,
                           kBufferSize))
        throw ContextError("sgfx: OSMesaMakeCurrent failed");
    loadGl();
}

GetProcAddressFn OsmesaContext::procAddress() const {
    return reinterpret_cast<GetProcAddressFn>(&OSMesaGetProcAddress);
}

} // namespace sgfx

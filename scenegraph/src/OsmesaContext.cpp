#include "sgfx/GraphicsContext.h"

#include <sgfx_glad/gl.h>
// After glad, so osmesa.h's GL/gl.h include is a no-op.
#include <GL/osmesa.h>

#include <stdexcept>
#include <string>

namespace sgfx {

OsmesaContext::OsmesaContext(int drawableWidth, int drawableHeight) {
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
    try {
        resizeDrawable(drawableWidth, drawableHeight);
    } catch (...) {
        OSMesaDestroyContext(static_cast<OSMesaContext>(ctx_));
        throw;
    }
}

OsmesaContext::~OsmesaContext() {
    if (ctx_) OSMesaDestroyContext(static_cast<OSMesaContext>(ctx_));
}

namespace {
// Makes `context` current on `memory` (RGBA8, width × height); false when OSMesa refuses.
bool bind(void* context, unsigned char* memory, int width, int height) {
    return OSMesaMakeCurrent(static_cast<OSMesaContext>(context), memory, GL_UNSIGNED_BYTE, width, height);
}
} // namespace

void OsmesaContext::makeCurrent() {
    assertOwnerThread();
    if (!bind(ctx_, buffer_.data(), width_, height_)) throw ContextError("sgfx: OSMesaMakeCurrent failed");
    loadGl();
}

void OsmesaContext::resizeDrawable(int width, int height) {
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        throw std::invalid_argument("OsmesaContext::resizeDrawable: " + std::to_string(width) + "x" +
                                    std::to_string(height) + " is outside 1..16384");
    assertOwnerThread();
    // A larger drawable gets a new block, bound before the old one is freed: OSMesa changes
    // nothing when it refuses, so on failure the old binding and its memory stay valid.
    const std::size_t bytes = std::size_t(width) * std::size_t(height) * 4;
    std::vector<unsigned char> grown;
    if (buffer_.size() < bytes) grown.resize(bytes);
    unsigned char* memory = grown.empty() ? buffer_.data() : grown.data();
    if (!bind(ctx_, memory, width, height))
        throw ContextError("sgfx: OSMesa refused a " + std::to_string(width) + "x" + std::to_string(height) +
                           " drawable; the context keeps its " + std::to_string(width_) + "x" +
                           std::to_string(height_) + " one");
    if (!grown.empty()) buffer_.swap(grown); // the block moves with the swap: the binding holds
    width_ = width, height_ = height;
    loadGl();
}

GetProcAddressFn OsmesaContext::procAddress() const {
    return reinterpret_cast<GetProcAddressFn>(&OSMesaGetProcAddress);
}

} // namespace sgfx

// Reading the scene target back (captures, tests) and presenting it to a window.
#include "render/RendererImpl.h"
#include "sgfx/GraphicsContext.h"
#include "sgfx/Image.h"

#include <sgfx_glad/gl.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace sgfx {

namespace {
template <class T> void flipRows(std::vector<T>& data, int width, int height, int channels) {
    // GL's rows run bottom to top; images are stored top row first.
    const std::size_t row = std::size_t(width) * channels;
    for (int y = 0; y < height / 2; ++y)
        std::swap_ranges(data.begin() + std::ptrdiff_t(y * row), data.begin() + std::ptrdiff_t((y + 1) * row),
                         data.begin() + std::ptrdiff_t((height - 1 - y) * row));
}
} // namespace

FloatImage Renderer::readPixelsLinear() {
    return readPixelsLinear(impl_->scene);
}

FloatImage Renderer::readPixelsLinear(const gl::RenderTarget& t) {
    context_.assertOwnerThread();
    FloatImage img{t.width, t.height, std::vector<float>(std::size_t(t.width) * t.height * 4)};
    if (!t.fbo) return img;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t.fbo.get());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    // Reading an sRGB target gives the stored (encoded) values: decode them.
    glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_FLOAT, img.rgba.data());
    if (t.colorFormat == GL_SRGB8_ALPHA8)
        for (std::size_t i = 0; i < img.rgba.size(); ++i)
            if (i % 4 != 3) {
                const float c = img.rgba[i];
                img.rgba[i] = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
            }
    flipRows(img.rgba, t.width, t.height, 4);
    return img;
}

Image Renderer::readPixels() {
    return readPixels(impl_->scene);
}

Image Renderer::readPixels(const gl::RenderTarget& t) {
    context_.assertOwnerThread();
    Image img;
    img.width = t.width;
    img.height = t.height;
    img.channels = 4;
    img.pixels.resize(std::size_t(t.width) * t.height * 4);
    if (!t.fbo) return img;
    if (t.colorFormat != GL_SRGB8_ALPHA8) {
        // Linear float target: encode once here, as the sRGB framebuffer would have.
        const FloatImage f = readPixelsLinear(t);
        for (std::size_t i = 0; i < f.rgba.size(); ++i) {
            float c = std::isfinite(f.rgba[i]) ? std::clamp(f.rgba[i], 0.0f, 1.0f) : 0.0f;
            if (i % 4 != 3) c = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
            img.pixels[i] = std::uint8_t(std::lround(c * 255.0f));
        }
        return img;
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t.fbo.get());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_BYTE, img.pixels.data());
    flipRows(img.pixels, t.width, t.height, 4);
    return img;
}

void Renderer::blitToWindow() {
    blitToWindow(impl_->scene);
}

void Renderer::blitToWindow(const gl::RenderTarget& t) {
    if (!context_.isWindow() || !t.fbo) return;
    // The target already holds sRGB-encoded values: copy them without conversion.
    glDisable(GL_FRAMEBUFFER_SRGB);
    glBlitNamedFramebuffer(t.fbo.get(), 0, 0, 0, t.width, t.height, 0, 0, context_.width(), context_.height(),
                           GL_COLOR_BUFFER_BIT, GL_LINEAR);
}

void Renderer::present() {
    present(impl_->scene);
}

void Renderer::present(const gl::RenderTarget& shown) {
    if (!context_.isWindow()) {
        // Headless: submit the frame. Without a flush llvmpipe keeps queueing frames and its
        // memory grew by ~60 MB over 3000 frames before levelling off (measured).
        glFlush();
        return;
    }
    blitToWindow(shown);
    context_.swapBuffers();
}

void Renderer::copySceneInto(gl::RenderTarget& composite, glm::ivec2 size, const glm::ivec4& region) {
    context_.assertOwnerThread();
    const gl::RenderTarget& scene = impl_->scene;
    if (!scene.fbo || region.z != scene.width || region.w != scene.height || region.x < 0 || region.y < 0 ||
        region.x + region.z > size.x || region.y + region.w > size.y)
        throw std::invalid_argument("sgfx: Renderer::copySceneInto: region " + std::to_string(region.z) +
                                    "x" + std::to_string(region.w) + " at (" + std::to_string(region.x) +
                                    ", " + std::to_string(region.y) + ") does not fit a " +
                                    std::to_string(size.x) + "x" + std::to_string(size.y) +
                                    " composite or the " + std::to_string(scene.width) + "x" +
                                    std::to_string(scene.height) + " scene target");
    gl::StateCache& cache = impl_->cache;
    const bool remade = !composite.fbo || composite.width != size.x || composite.height != size.y ||
                        composite.colorFormat != scene.colorFormat;
    composite.resize(size.x, size.y, scene.colorFormat);
    // Through the cache: the composite bound with sRGB conversion off (the blit copies the stored,
    // already encoded values), no scissor, every colour channel written.
    cache.bindFramebuffer(composite.fbo.get(), size, false);
    cache.setScissor(false);
    cache.setColourMask(true);
    if (remade) {
        const glm::vec4 black(0.0f, 0.0f, 0.0f, 1.0f);
        glClearNamedFramebufferfv(composite.fbo.get(), GL_COLOR, 0, &black[0]);
    }
    glBlitNamedFramebuffer(scene.fbo.get(), composite.fbo.get(), 0, 0, scene.width, scene.height, region.x,
                           region.y, region.x + region.z, region.y + region.w, GL_COLOR_BUFFER_BIT,
                           GL_NEAREST);
}

} // namespace sgfx

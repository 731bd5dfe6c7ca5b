#include "render/ResourcePool.h"

#include <sgfx_glad/gl.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace sgfx::render {

unsigned ResourcePool::acquire(const ResolvedDesc& desc, std::string_view name) {
    for (Entry& e : entries_)
        if (!e.inUse && e.desc == desc) {
            e.inUse = true;
            e.lastUse = frame_;
            return e.texture.get();
        }
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    if (desc.width < 1 || desc.height < 1 || desc.width > maxSize || desc.height > maxSize)
        throw std::invalid_argument("sgfx: frame graph resource '" + std::string(name) + "' is " +
                                    std::to_string(desc.width) + "x" + std::to_string(desc.height) +
                                    ", outside the driver's 1.." + std::to_string(maxSize));
    Entry& e = entries_.emplace_back();
    e.desc = desc;
    if (desc.samples > 1) {
        e.texture = gl::createTexture(GL_TEXTURE_2D_MULTISAMPLE);
        glTextureStorage2DMultisample(e.texture.get(), desc.samples, desc.format, desc.width, desc.height,
                                      GL_TRUE);
    } else {
        e.texture = gl::createTexture2D(desc.format, desc.width, desc.height,
                                        desc.filter == Filter::Nearest ? GL_NEAREST : GL_LINEAR, desc.levels());
        if (desc.mipmaps && desc.filter == Filter::Linear)
            glTextureParameteri(e.texture.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        if (desc.wrapS == Wrap::Repeat) glTextureParameteri(e.texture.get(), GL_TEXTURE_WRAP_S, GL_REPEAT);
        if (desc.wrapS == Wrap::MirroredRepeat)
            glTextureParameteri(e.texture.get(), GL_TEXTURE_WRAP_S, GL_MIRRORED_REPEAT);
    }
    e.inUse = true;
    e.lastUse = frame_;
    ++made_;
    return e.texture.get();
}

void ResourcePool::release(unsigned texture, const ResolvedDesc&) {
    for (Entry& e : entries_)
        if (e.texture.get() == texture) e.inUse = false;
}

void ResourcePool::beginFrame(std::uint64_t frame, std::uint64_t keepFrames) {
    frame_ = frame;
    // A texture from outside the pool (a view's target) may be deleted and its name reused before
    // the next frame: framebuffers that attach one live for a frame only.
    std::erase_if(framebuffers_, [](const Framebuffer& f) { return f.external; });
    for (auto it = entries_.begin(); it != entries_.end();) {
        if (!it->inUse && frame - it->lastUse > keepFrames) {
            dropFramebuffersOf(it->texture.get());
            it = entries_.erase(it);
        } else {
            ++it;
        }
    }
}

void ResourcePool::dropFramebuffersOf(unsigned texture) {
    std::erase_if(framebuffers_, [&](const Framebuffer& f) {
        return std::any_of(f.attachments.begin(), f.attachments.end(),
                           [&](const auto& a) { return a.second == texture; });
    });
}

unsigned ResourcePool::framebuffer(const std::vector<std::pair<unsigned, unsigned>>& attachments,
                                   std::string_view pass) {
    for (const Framebuffer& f : framebuffers_)
        if (f.attachments == attachments) return f.fbo.get();
    Framebuffer& f = framebuffers_.emplace_back();
    f.attachments = attachments;
    f.fbo = gl::createFramebuffer();
    std::vector<GLenum> drawBuffers;
    for (const auto& [point, attached] : attachments) {
        const unsigned texture = attached; // a copy: clang 14 cannot capture a structured binding
        f.external = f.external || std::none_of(entries_.begin(), entries_.end(),
                                                [&](const Entry& e) { return e.texture.get() == texture; });
        glNamedFramebufferTexture(f.fbo.get(), point, texture, 0);
        if (point >= GL_COLOR_ATTACHMENT0 && point < GL_COLOR_ATTACHMENT0 + 16) drawBuffers.push_back(point);
    }
    if (drawBuffers.empty()) {
        glNamedFramebufferDrawBuffer(f.fbo.get(), GL_NONE);
        glNamedFramebufferReadBuffer(f.fbo.get(), GL_NONE);
    } else {
        glNamedFramebufferDrawBuffers(f.fbo.get(), GLsizei(drawBuffers.size()), drawBuffers.data());
    }
    const GLenum status = glCheckNamedFramebufferStatus(f.fbo.get(), GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        framebuffers_.pop_back();
        throw std::runtime_error("sgfx: frame graph pass '" + std::string(pass) +
                                 "': its attachments make an incomplete framebuffer (status " +
                                 std::to_string(status) + ")");
    }
    return f.fbo.get();
}

void ResourcePool::clear() {
    framebuffers_.clear();
    entries_.clear();
}

std::size_t ResourcePool::bytesHeld() const {
    std::size_t n = 0;
    for (const Entry& e : entries_)
        n += e.desc.bytes();
    return n;
}

} // namespace sgfx::render

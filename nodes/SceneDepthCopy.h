#pragma once
/// @file
/// A copy of the opaque scene's depth, made after the opaque items (PassStage::AfterOpaque), for
/// effects that draw later and must know where the opaque surfaces are: soft particles, volumes
/// that stop at a wall. One texture per view size (TargetCache); `current` is the copy of the view
/// being drawn. The owner binds it where its shader reads it, at every draw.
#include "TargetCache.h"

#include <sgfx/Renderer.h>
#include <sgfx/gl/Objects.h>

#include <glad/gl.h>

#include <string>

namespace sgfx::nodes {

/// The pass that copies the opaque depth of the view being drawn (see the file comment).
class SceneDepthCopy : public RenderPass {
public:
    explicit SceneDepthCopy(std::string name)
        : name_(std::move(name)) {}
    std::string_view name() const override { return name_; }
    PassStage stage() const override { return PassStage::AfterOpaque; }
    void execute(Renderer& r) override {
        gl::RenderTarget& t = r.currentTarget();
        Target& own = targets_.get(
            r.frame().frameNumber,
            [&](const Target& e) { return e.width == t.width && e.height == t.height; },
            [&](Target& e) {
                e.width = t.width;
                e.height = t.height;
                e.depth = gl::createTexture2D(GL_DEPTH_COMPONENT32F, t.width, t.height);
                e.fbo = gl::createFramebuffer();
                glNamedFramebufferTexture(e.fbo.get(), GL_DEPTH_ATTACHMENT, e.depth.get(), 0);
            });
        // Resolves a multisample depth too (one sample per pixel).
        glBlitNamedFramebuffer(t.fbo.get(), own.fbo.get(), 0, 0, t.width, t.height, 0, 0, t.width, t.height,
                               GL_DEPTH_BUFFER_BIT, GL_NEAREST);
        current_ = own.depth.get();
    }
    /// The copy for the view being drawn (0 before the first copy).
    unsigned current() const { return current_; }
    void releaseGLObjects() {
        targets_.clear();
        current_ = 0;
    }

private:
    struct Target {
        int width = 0, height = 0;
        gl::TextureObject depth;
        gl::FramebufferObject fbo;
        std::uint64_t lastUse = 0;
    };
    std::string name_;
    TargetCache<Target> targets_;
    unsigned current_ = 0;
};

} // namespace sgfx::nodes

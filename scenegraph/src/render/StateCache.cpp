#include "render/StateCache.h"

#include "render/GpuUpload.h"

#include <sgfx_glad/gl.h>

namespace sgfx::gl {

bool StateCache::useProgram(unsigned program) {
    if (program == program_) return false;
    glUseProgram(program);
    program_ = program;
    ++*stateChanges_;
    return true;
}

void StateCache::bindTexture(unsigned unit, unsigned texture, unsigned sampler) {
    bindSampler(unit, sampler);
    if (units_[unit] == texture) return;
    glBindTextureUnit(unit, texture);
    units_[unit] = texture;
    ++*stateChanges_;
}

void StateCache::bindSampler(unsigned unit, unsigned sampler) {
    if (!samplersKnown_) {
        // After invalidate(): no unit is assumed free of a sampler object; one call frees them all
        // (the renderer requires kTrackedUnits combined units).
        glBindSamplers(0, GLsizei(kTrackedUnits), nullptr);
        samplers_.fill(0);
        samplersKnown_ = true;
        ++*stateChanges_;
    }
    if (samplers_[unit] == sampler) return;
    glBindSampler(unit, sampler);
    samplers_[unit] = sampler;
    ++*stateChanges_;
}

void StateCache::setBlend(BlendMode m) {
    if (blend_ == int(m)) return;
    blend_ = int(m);
    ++*stateChanges_;
    if (m == BlendMode::Off) {
        glDisable(GL_BLEND);
        return;
    }
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    switch (m) {
    case BlendMode::Alpha:
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        break;
    case BlendMode::Premultiplied:
        glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        break;
    case BlendMode::Additive:
        glBlendFunc(GL_SRC_ALPHA, GL_ONE);
        break;
    case BlendMode::Multiply:
        glBlendFunc(GL_DST_COLOR, GL_ZERO);
        break;
    case BlendMode::Off:
        break;
    }
}

void StateCache::setFrontFace(bool mirrored) {
    if (clockwiseFront_ == int(mirrored)) return;
    clockwiseFront_ = int(mirrored);
    ++*stateChanges_;
    glFrontFace(mirrored ? GL_CW : GL_CCW);
}

void StateCache::setCull(CullFace c, bool mirrored) {
    setFrontFace(mirrored);
    if (cull_ == int(c)) return;
    cull_ = int(c);
    ++*stateChanges_;
    if (c == CullFace::None) {
        glDisable(GL_CULL_FACE);
        return;
    }
    glEnable(GL_CULL_FACE);
    glCullFace(c == CullFace::Back ? GL_BACK : GL_FRONT);
}

void StateCache::setDepth(const DepthState& d) {
    if (depthKnown_ && depth_ == d) return;
    depth_ = d;
    depthKnown_ = true;
    ++*stateChanges_;
    if (d.test)
        glEnable(GL_DEPTH_TEST);
    else
        glDisable(GL_DEPTH_TEST);
    glDepthMask(d.write ? GL_TRUE : GL_FALSE);
    glDepthFunc(render::glCompare(d.func));
}

void StateCache::bindFramebuffer(unsigned fbo, glm::ivec2 size, bool srgb) {
    if (fbo != framebuffer_) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        framebuffer_ = fbo;
        ++*stateChanges_;
    }
    if (size != viewport_) {
        glViewport(0, 0, size.x, size.y);
        viewport_ = size;
    }
    if (int(srgb) != srgb_) {
        if (srgb)
            glEnable(GL_FRAMEBUFFER_SRGB);
        else
            glDisable(GL_FRAMEBUFFER_SRGB);
        srgb_ = int(srgb);
    }
}

void StateCache::setColourMask(bool on) {
    if (int(on) == colourMask_) return;
    const GLboolean v = on ? GL_TRUE : GL_FALSE;
    glColorMask(v, v, v, v);
    colourMask_ = int(on);
}

void StateCache::setBlendPerAttachment(const std::vector<std::pair<unsigned, unsigned>>& factors) {
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    for (std::size_t i = 0; i < factors.size(); ++i)
        glBlendFunci(GLuint(i), factors[i].first, factors[i].second);
    blend_ = -2; // no BlendMode: the next setBlend sets every attachment
    ++*stateChanges_;
}

void StateCache::setViewport(const glm::ivec4& rect) {
    glViewport(rect.x, rect.y, rect.z, rect.w);
    viewport_ = glm::ivec2(-1); // not a whole target: unknown to bindFramebuffer
}

void StateCache::setScissor(bool on, const glm::ivec4& rect) {
    if (int(on) == scissor_ && (!on || rect == scissorRect_)) return;
    if (on) {
        glEnable(GL_SCISSOR_TEST);
        glScissor(rect.x, rect.y, rect.z, rect.w);
    } else {
        glDisable(GL_SCISSOR_TEST);
    }
    scissor_ = int(on);
    scissorRect_ = rect;
}

void StateCache::beginOffscreen(unsigned fbo, glm::ivec2 size) {
    Offscreen& o = offscreen_;
    o.known = framebuffer_ != ~0u && viewport_ != glm::ivec2(-1);
    if (o.known) {
        o.framebuffer = framebuffer_;
        o.viewport = glm::ivec4(0, 0, viewport_);
    } else {
        GLint b = 0;
        glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &b);
        glGetIntegerv(GL_VIEWPORT, &o.viewport[0]);
        o.framebuffer = unsigned(b);
    }
    o.blend = blend_ == -1 ? glIsEnabled(GL_BLEND) == GL_TRUE : blend_ != int(BlendMode::Off);
    if (fbo != framebuffer_) {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        framebuffer_ = fbo;
        ++*stateChanges_;
    }
    if (size != viewport_) {
        glViewport(0, 0, size.x, size.y);
        viewport_ = size;
    }
    // Offscreen targets are written, not blended, unless the caller sets a blend inside; the
    // cache records Off, so such a setBlend takes effect, and endOffscreen restores the state.
    o.blendState = blend_;
    if (o.blend) glDisable(GL_BLEND);
    blend_ = int(BlendMode::Off);
}

void StateCache::endOffscreen() {
    const Offscreen& o = offscreen_;
    if (o.blendState >= 0) {
        setBlend(BlendMode(o.blendState));
    } else {
        // Unknown or per-attachment: the enable flag as it was; the factors are known only if
        // nothing was blended inside.
        if (o.blend)
            glEnable(GL_BLEND);
        else
            glDisable(GL_BLEND);
        blend_ = blend_ == int(BlendMode::Off) ? o.blendState : -1;
    }
    if (o.known) {
        if (o.framebuffer != framebuffer_) {
            glBindFramebuffer(GL_FRAMEBUFFER, o.framebuffer);
            framebuffer_ = o.framebuffer;
            ++*stateChanges_;
        }
        const glm::ivec2 size(o.viewport.z, o.viewport.w);
        if (size != viewport_) {
            glViewport(0, 0, size.x, size.y);
            viewport_ = size;
        }
        return;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, o.framebuffer);
    glViewport(o.viewport.x, o.viewport.y, o.viewport.z, o.viewport.w);
    framebuffer_ = ~0u;
    viewport_ = glm::ivec2(-1);
}

void StateCache::invalidate() {
    scissor_ = -1;
    framebuffer_ = ~0u;
    viewport_ = glm::ivec2(-1);
    srgb_ = colourMask_ = -1;
    program_ = 0;
    blend_ = cull_ = clockwiseFront_ = -1;
    depthKnown_ = false;
    units_.fill(0);
    samplersKnown_ = false;
}

} // namespace sgfx::gl

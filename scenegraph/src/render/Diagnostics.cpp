#include "render/Diagnostics.h"

#include "render/RendererImpl.h"
#include "sgfx/Node.h"

#include <sgfx_glad/gl.h>

#include <algorithm>
#include <cstdio>

namespace sgfx {
namespace render {

void DebugLog::add(std::string_view message) {
    if (messages.size() >= 64) return; // an error storm: the first ones say enough
    std::string site = "[" + std::string(stage) + "]";
    if (item)
        site +=
            " drawing '" + (item->node().name.empty() ? std::string("<unnamed>") : item->node().name) + "'";
    if (program) site += " with " + program->description();
    messages.push_back(site + ": " + std::string(message));
}

namespace {
[[maybe_unused]] void GLAPIENTRY onDebugMessage(GLenum source, GLenum type, GLuint, GLenum severity, GLsizei,
                                                const GLchar* message, const void* user) {
    // Compiler messages already become a ShaderError with translated lines.
    if (source == GL_DEBUG_SOURCE_SHADER_COMPILER) return;
    // Synchronous output: this runs inside the offending call, so the recorded site is exact.
    if (type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH)
        static_cast<DebugLog*>(const_cast<void*>(user))->add(message);
}
} // namespace

void enableDebugOutput([[maybe_unused]] DebugLog& log) {
#ifdef SGFX_GL_DEBUG
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(onDebugMessage, &log);
#endif
}

void disableDebugOutput() {
#ifdef SGFX_GL_DEBUG
    glDebugMessageCallback(nullptr, nullptr);
#endif
}

void pollGlErrors(DebugLog& log) {
    for (GLenum e; (e = glGetError()) != GL_NO_ERROR;) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "glGetError: 0x%04x", unsigned(e));
        log.add(buf);
    }
}

void PassTimers::begin(bool on, std::string name) {
    if (!on) return;
    timers_.emplace_back(std::move(name), gl::createQuery(GL_TIME_ELAPSED));
    glBeginQuery(GL_TIME_ELAPSED, timers_.back().second.get());
}

void PassTimers::end(bool on) {
    if (on) glEndQuery(GL_TIME_ELAPSED);
}

void PassTimers::collect(std::vector<FrameStats::PassTime>& into) {
    for (auto& [name, query] : timers_) {
        GLuint64 ns = 0;
        glGetQueryObjectui64v(query.get(), GL_QUERY_RESULT, &ns);
        into.push_back({name, double(ns) * 1e-6});
    }
    timers_.clear();
}

} // namespace render

std::vector<std::string> Renderer::takeGlErrors() {
    // Errors the debug output did not report (no KHR_debug, or SGFX_GL_DEBUG off).
    render::pollGlErrors(impl_->log);
    return std::exchange(impl_->log.messages, {});
}

void Renderer::warn(std::string message) {
    if (std::find(impl_->warnings.begin(), impl_->warnings.end(), message) == impl_->warnings.end())
        impl_->warnings.push_back(std::move(message));
}

std::vector<std::string> Renderer::takeWarnings() {
    return std::exchange(impl_->warnings, {});
}

} // namespace sgfx

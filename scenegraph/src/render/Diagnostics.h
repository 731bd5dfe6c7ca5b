#pragma once
// What the renderer reports about itself (private to the renderer): GL errors and debug messages
// with the call site that caused them, and GPU timers of the passes (RendererOptions::timePasses).
#include "sgfx/RenderQueue.h"
#include "sgfx/Renderer.h"
#include "sgfx/gl/Objects.h"

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace sgfx::render {

/// Where the renderer is, so a GL error names its call site: the pass, and the item being drawn.
struct DebugLog {
    std::string_view stage = "outside a frame";
    const RenderItem* item = nullptr;
    const gl::Program* program = nullptr;
    std::vector<std::string> messages;

    void add(std::string_view message);
};

/// With SGFX_GL_DEBUG: synchronous KHR_debug output, errors and high-severity messages into `log`.
void enableDebugOutput(DebugLog& log);
void disableDebugOutput();
/// Errors glGetError still holds (no KHR_debug, or SGFX_GL_DEBUG off), added to `log`.
void pollGlErrors(DebugLog& log);

/// GPU time queries of one frame, begun and ended around each timed pass and read at its end.
class PassTimers {
public:
    void begin(bool on, std::string name);
    void end(bool on);
    /// Waits for every query of the frame and appends its time; forgets them.
    void collect(std::vector<FrameStats::PassTime>& into);
    void clear() { timers_.clear(); }
    std::size_t count() const { return timers_.size(); }

private:
    std::vector<std::pair<std::string, gl::QueryObject>> timers_;
};

} // namespace sgfx::render

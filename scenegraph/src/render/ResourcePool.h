#pragma once
// The renderer's textures for frame-graph resources: reused across views and frames by
// description, handed from a resource whose life ended to a later one with the same description
// within a frame (the frame graph's aliasing), and released after a few frames unused. Also the
// framebuffers that attach them, made once per attachment set.
#include "sgfx/FrameGraph.h"
#include "sgfx/gl/Objects.h"

#include <cstdint>
#include <map>
#include <vector>

namespace sgfx::render {

class ResourcePool final : public ResourceAllocator {
public:
    unsigned acquire(const ResolvedDesc& desc, std::string_view name) override;
    void release(unsigned texture, const ResolvedDesc& desc) override;

    /// Starts a frame: textures idle for more than `keepFrames` frames are deleted.
    void beginFrame(std::uint64_t frame, std::uint64_t keepFrames = 3);
    /// A framebuffer with these attachments (GL attachment point → texture), made on first use
    /// and checked complete; deleted with any of its textures.
    unsigned framebuffer(const std::vector<std::pair<unsigned, unsigned>>& attachments,
                         std::string_view pass);
    void clear();

    std::size_t bytesHeld() const; ///< every texture the pool holds, in use or not
    std::size_t texturesMade() const { return made_; }
    std::size_t textureCount() const { return entries_.size(); }

private:
    struct Entry {
        ResolvedDesc desc;
        gl::TextureObject texture;
        bool inUse = false;
        std::uint64_t lastUse = 0;
    };
    struct Framebuffer {
        std::vector<std::pair<unsigned, unsigned>> attachments;
        gl::FramebufferObject fbo;
        bool external = false; ///< attaches a texture the pool does not own
    };
    void dropFramebuffersOf(unsigned texture);
    std::vector<Entry> entries_;
    std::vector<Framebuffer> framebuffers_;
    std::uint64_t frame_ = 0;
    std::size_t made_ = 0;
};

} // namespace sgfx::render

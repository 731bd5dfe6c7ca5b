#pragma once
// The Viewer's display channels (Viewer::setChannels): a camera per channel, synchronised with the
// eye camera each frame, and the composite target their images are copied into.
#include "sgfx/Camera.h"
#include "sgfx/DisplayChannel.h"
#include "sgfx/Image.h"
#include "sgfx/Renderer.h"
#include "sgfx/gl/Objects.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace sgfx {

class ViewerChannels {
public:
    /// Validated (validateChannels); `channels` must not be empty.
    explicit ViewerChannels(std::vector<DisplayChannel> channels);

    const std::vector<DisplayChannel>& channels() const { return channels_; }
    Camera& camera(std::size_t i) { return *cameras_.at(i); }
    const FrameStats& stats() const { return total_; }
    const FrameStats& channelStats(std::size_t i) const { return stats_.at(i); }
    const gl::RenderTarget& composite() const { return composite_; }

    /// Renders every channel from `eye` and copies each image into its rectangle of the composite.
    void render(Renderer& renderer, const Camera& eye, double time, std::uint64_t frameNumber);
    /// Channel i's rectangle of the composite `all` (top row first, as captures are).
    Image crop(const Image& all, std::size_t i) const;

private:
    void sync(const Camera& eye, std::size_t i);

    std::vector<DisplayChannel> channels_;
    std::vector<std::shared_ptr<Camera>> cameras_;
    std::vector<FrameStats> stats_;
    FrameStats total_;
    std::uint64_t eyeHistoryEpoch_ = 0;
    gl::RenderTarget composite_;
};

} // namespace sgfx

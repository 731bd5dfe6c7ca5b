// Display channels of a Viewer: one persistent camera per channel (the renderer keys TAA history,
// per-triangle orders and anti-aliasing targets by camera), the eye's settings copied each frame,
// each channel's image copied on the GPU into its rectangle of one composite.
#include "ViewerChannels.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>

namespace sgfx {

namespace {

// Counts and times summed; pass times listed channel after channel.
void addStats(FrameStats& total, const FrameStats& s) {
    total.drawCalls += s.drawCalls;
    total.triangles += s.triangles;
    total.programChanges += s.programChanges;
    total.stateChanges += s.stateChanges;
    total.culledNodes += s.culledNodes;
    total.items += s.items;
    total.triangleSorts += s.triangleSorts;
    total.instanceBatches += s.instanceBatches;
    total.passTimes.insert(total.passTimes.end(), s.passTimes.begin(), s.passTimes.end());
    total.fragments += s.fragments;
    total.geometryPasses += s.geometryPasses;
    total.occlusionTested += s.occlusionTested;
    total.occlusionCulled += s.occlusionCulled;
    total.submissions += s.submissions;
    total.cullMs += s.cullMs;
    total.drawMs += s.drawMs;
}

} // namespace

ViewerChannels::ViewerChannels(std::vector<DisplayChannel> channels)
    : channels_(std::move(channels)) {
    if (channels_.empty()) throw std::invalid_argument("sgfx: ViewerChannels: no channels");
    validateChannels(channels_);
    for (std::size_t i = 0; i < channels_.size(); ++i)
        cameras_.push_back(Camera::create());
    stats_.resize(channels_.size());
}

// The eye's settings, the channel's view and frustum. The channel keeps its frustum's near and
// far planes: computeNearFar would fit each channel's planes to what that channel sees, so depth
// (and what reads it: soft particles, fog through depth, AO) would differ across a seam.
void ViewerChannels::sync(const Camera& eye, std::size_t i) {
    const DisplayChannel& ch = channels_[i];
    Camera& cam = *cameras_[i];
    if (cam.children() != eye.children()) {
        cam.removeChildren();
        for (const NodePtr& child : eye.children())
            cam.addChild(child);
    }
    cam.viewMatrix = ch.viewMatrix(eye.viewMatrix);
    cam.projectionMatrix = ch.frustum.projection();
    cam.viewport = Viewport{0, 0, ch.viewport.width, ch.viewport.height};
    cam.clearColor = eye.clearColor;
    cam.clearColorEnabled = eye.clearColorEnabled;
    cam.clearDepthEnabled = eye.clearDepthEnabled;
    cam.cullingEnabled = eye.cullingEnabled;
    cam.computeNearFar = false;
    cam.nearFarRatio = eye.nearFarRatio;
    cam.nodeMask = eye.nodeMask;
    if (cam.antiAliasing() != eye.antiAliasing()) cam.setAntiAliasing(eye.antiAliasing());
    if (eye.historyEpoch() != eyeHistoryEpoch_) cam.resetHistory(); // a camera cut of the eye
}

void ViewerChannels::render(Renderer& renderer, const Camera& eye, double time, std::uint64_t frameNumber) {
    const Viewport all = compositeViewport(channels_);
    total_ = {};
    for (std::size_t i = 0; i < channels_.size(); ++i) {
        sync(eye, i);
        renderer.render(*cameras_[i], time, frameNumber);
        stats_[i] = renderer.stats();
        addStats(total_, stats_[i]);
        const Viewport& vp = channels_[i].viewport;
        renderer.copySceneInto(composite_, {all.width, all.height}, {vp.x, vp.y, vp.width, vp.height});
    }
    eyeHistoryEpoch_ = eye.historyEpoch();
}

Image ViewerChannels::crop(const Image& all, std::size_t i) const {
    const Viewport& vp = channels_.at(i).viewport;
    Image out;
    out.width = vp.width;
    out.height = vp.height;
    out.channels = all.channels;
    const auto c = std::size_t(all.channels);
    out.pixels.resize(std::size_t(vp.width) * std::size_t(vp.height) * c);
    // The viewport's origin is bottom left; the image's rows run top to bottom.
    const int top = all.height - (vp.y + vp.height);
    for (int y = 0; y < vp.height; ++y) {
        const auto src =
            all.pixels.begin() +
            std::ptrdiff_t((std::size_t(top + y) * std::size_t(all.width) + std::size_t(vp.x)) * c);
        std::copy(src, src + std::ptrdiff_t(std::size_t(vp.width) * c),
                  out.pixels.begin() + std::ptrdiff_t(std::size_t(y) * std::size_t(vp.width) * c));
    }
    return out;
}

} // namespace sgfx

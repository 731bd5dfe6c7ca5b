#pragma once
/// @file
/// Display descriptions (JSON): a wall of screens, a cylinder of projectors, a dome of channels or
/// a general list of channels, read into the DisplayChannel values a multi-channel viewer or the
/// cluster renders. The format: docs/display-channels.md.
#include "sgfx/DisplayChannel.h"
#include "sgfx/Export.h"
#include "sgfx/LoadError.h"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sgfx {

struct SGFX_API DisplayConfig {
    /// The description's "name" (the file's stem when it has none).
    std::string name;
    /// "wall", "cylinder", "dome" or "channels": the layout the file describes.
    std::string layout;
    /// The channels in the file's order (wall: row by row from the bottom, left to right;
    /// cylinder: left to right), checked with validateChannels.
    std::vector<DisplayChannel> channels;
    /// Walls only: the one frustum whose image at the composite's size the channels crop exactly
    /// (each channel's frustum is overall.sub() of its viewport's share of the composite): the
    /// single-view reference render. Empty for the other layouts.
    std::optional<OffAxisFrustum> overall;
    /// compositeViewport(channels).
    Viewport composite{0, 0, 0, 0};

    /// The most channels a description may have.
    static constexpr int kMaxChannels = 64;
    /// The largest description file read (bytes).
    static constexpr std::size_t kMaxFileBytes = 1 << 20;

    /// Reads a description file. Throws LoadError naming the file, the field's JSON path (such as
    /// `wall.columns` or `channels[2].frustum.left`) and the reason.
    static DisplayConfig load(const std::filesystem::path& file);
    /// Reads a description from JSON text; `source` names it in errors (the file's path).
    static DisplayConfig parse(std::string_view json, const std::string& source);

    /// The channel of this name, or nullptr.
    const DisplayChannel* find(std::string_view channelName) const;
};

} // namespace sgfx

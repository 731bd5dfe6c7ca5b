#pragma once
// The layouts of a display description, each from its JSON object (docs/display-channels.md).
#include "DisplayJson.h"

#include <optional>

namespace sgfx::display {

struct Layout {
    std::vector<DisplayChannel> channels;
    std::optional<OffAxisFrustum> overall;
};

/// `root` holds the layout's key ("wall", "cylinder", "dome" or "channels").
Layout readWall(const Object& root);
Layout readCylinder(const Object& root);
Layout readDome(const Object& root);
Layout readChannels(const Object& root);

/// An object's "near" and "far" (metres; defaults 0.1 and 1000), far beyond near.
std::pair<float, float> nearFar(const Object& o);

} // namespace sgfx::display

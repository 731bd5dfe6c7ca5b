// The cylinder, dome and general channel layouts.
#include "DisplayLayouts.h"
#include "sgfx/DisplayConfig.h"

namespace sgfx::display {

Layout readCylinder(const Object& root) {
    root.fail("cylinder", "is not implemented yet");
}

Layout readDome(const Object& root) {
    root.fail("dome", "is not implemented yet");
}

Layout readChannels(const Object& root) {
    root.fail("channels", "is not implemented yet");
}

} // namespace sgfx::display

#pragma once
// The 0.1 spelling, kept in 0.2 only (removed in 0.3). #warning, not a pragma: it shows through
// -isystem, which CMake uses for an imported target's include directories.
#warning "<volume/VolumeMath.h> is deprecated and removed in sgfx 0.3: include <sgfx/nodes/volume/VolumeMath.h>"
#include <sgfx/nodes/volume/VolumeMath.h>

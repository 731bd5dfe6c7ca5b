#pragma once
// The 0.1 spelling, kept in 0.2 only (removed in 0.3). #warning, not a pragma: it shows through
// -isystem, which CMake uses for an imported target's include directories.
#warning "<fog/FogMath.h> is deprecated and removed in sgfx 0.3: include <sgfx/nodes/fog/FogMath.h>"
#include <sgfx/nodes/fog/FogMath.h>

#pragma once
// Deprecated spelling kept for one release (0.2): include <sgfx/nodes/volume/VolumeMath.h> instead.
#pragma GCC warning                                                                                          \
    "<volume/VolumeMath.h> is deprecated and goes away after sgfx 0.2: include <sgfx/nodes/volume/VolumeMath.h>"
#include <sgfx/nodes/volume/VolumeMath.h>

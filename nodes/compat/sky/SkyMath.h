#pragma once
// Deprecated spelling kept for one release (0.2): include <sgfx/nodes/sky/SkyMath.h> instead.
#pragma GCC warning                                                                                          \
    "<sky/SkyMath.h> is deprecated and goes away after sgfx 0.2: include <sgfx/nodes/sky/SkyMath.h>"
#include <sgfx/nodes/sky/SkyMath.h>

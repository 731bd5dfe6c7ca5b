#pragma once
// Deprecated spelling kept for one release (0.2): include <sgfx/nodes/fog/FogMath.h> instead.
#pragma GCC warning                                                                                          \
    "<fog/FogMath.h> is deprecated and goes away after sgfx 0.2: include <sgfx/nodes/fog/FogMath.h>"
#include <sgfx/nodes/fog/FogMath.h>

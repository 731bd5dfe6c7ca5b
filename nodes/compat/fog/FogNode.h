#pragma once
// Deprecated spelling kept for one release (0.2): include <sgfx/nodes/fog/FogNode.h> instead.
#pragma GCC warning                                                                                          \
    "<fog/FogNode.h> is deprecated and goes away after sgfx 0.2: include <sgfx/nodes/fog/FogNode.h>"
#include <sgfx/nodes/fog/FogNode.h>

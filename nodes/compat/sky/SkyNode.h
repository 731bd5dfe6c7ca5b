#pragma once
// Deprecated spelling kept for one release (0.2): include <sgfx/nodes/sky/SkyNode.h> instead.
#pragma GCC warning                                                                                          \
    "<sky/SkyNode.h> is deprecated and goes away after sgfx 0.2: include <sgfx/nodes/sky/SkyNode.h>"
#include <sgfx/nodes/sky/SkyNode.h>

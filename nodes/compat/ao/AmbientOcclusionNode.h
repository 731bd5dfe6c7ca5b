#pragma once
// Deprecated spelling kept for one release (0.2): include <sgfx/nodes/ao/AmbientOcclusionNode.h> instead.
#pragma GCC warning                                                                                          \
    "<ao/AmbientOcclusionNode.h> is deprecated and goes away after sgfx 0.2: include <sgfx/nodes/ao/AmbientOcclusionNode.h>"
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>

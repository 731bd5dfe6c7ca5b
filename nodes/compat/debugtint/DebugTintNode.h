#pragma once
// Deprecated spelling kept for one release (0.2): include <sgfx/nodes/debugtint/DebugTintNode.h> instead.
#pragma GCC warning                                                                                          \
    "<debugtint/DebugTintNode.h> is deprecated and goes away after sgfx 0.2: include <sgfx/nodes/debugtint/DebugTintNode.h>"
#include <sgfx/nodes/debugtint/DebugTintNode.h>

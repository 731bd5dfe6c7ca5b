#pragma once
// Deprecated spelling kept for one release (0.2): include <sgfx/nodes/transparency/OitMath.h> instead.
#pragma GCC warning                                                                                          \
    "<transparency/OitMath.h> is deprecated and goes away after sgfx 0.2: include <sgfx/nodes/transparency/OitMath.h>"
#include <sgfx/nodes/transparency/OitMath.h>

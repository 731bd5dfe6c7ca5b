#pragma once
// Deprecated spelling kept for one release (0.2): include <sgfx/nodes/transparency/TransparencyBin.h>
// instead.
#pragma GCC warning                                                                                          \
    "<transparency/TransparencyBin.h> is deprecated and goes away after sgfx 0.2: include <sgfx/nodes/transparency/TransparencyBin.h>"
#include <sgfx/nodes/transparency/TransparencyBin.h>

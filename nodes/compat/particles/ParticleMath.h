#pragma once
// Deprecated spelling kept for one release (0.2): include <sgfx/nodes/particles/ParticleMath.h> instead.
#pragma GCC warning                                                                                          \
    "<particles/ParticleMath.h> is deprecated and goes away after sgfx 0.2: include <sgfx/nodes/particles/ParticleMath.h>"
#include <sgfx/nodes/particles/ParticleMath.h>

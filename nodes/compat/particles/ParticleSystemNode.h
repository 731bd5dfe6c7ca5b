#pragma once
// Deprecated spelling kept for one release (0.2): include <sgfx/nodes/particles/ParticleSystemNode.h>
// instead.
#pragma GCC warning                                                                                          \
    "<particles/ParticleSystemNode.h> is deprecated and goes away after sgfx 0.2: include <sgfx/nodes/particles/ParticleSystemNode.h>"
#include <sgfx/nodes/particles/ParticleSystemNode.h>

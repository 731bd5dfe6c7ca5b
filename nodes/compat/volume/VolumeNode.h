#pragma once
// Deprecated spelling kept for one release (0.2): include <sgfx/nodes/volume/VolumeNode.h> instead.
#pragma GCC warning                                                                                          \
    "<volume/VolumeNode.h> is deprecated and goes away after sgfx 0.2: include <sgfx/nodes/volume/VolumeNode.h>"
#include <sgfx/nodes/volume/VolumeNode.h>

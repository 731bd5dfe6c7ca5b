#pragma once
// The proving ground at dusk with street lamps: the benchmark of the light list (many lights with
// a range; `polygon --lamps N`).
#include "PolygonScene.h"

#include <sgfx/Group.h>

#include <memory>

namespace polygon {

constexpr float kLampHeight = 6.0f;    // metres above the terrain, the light's height
constexpr float kLampRange = 22.0f;    // metres: the spot's range
constexpr float kLampCandela = 140.0f; // luminous intensity, as glTF gives it (sgfx: / π)

// Turns the scene's sun down to a low, dim, orange dusk sun and its sky ambient to a faint blue,
// and adds `count` street lamps (0..100000) spread evenly along the ring road, then the cross
// roads, on alternate sides: each a pole with an arm, an emissive head and a spot light pointing
// down (inverse-square falloff, range kLampRange, cones 35° and 65°). Returns the lamps' group
// (also a child of scene.root). Throws std::invalid_argument for a count outside 0..100000.
std::shared_ptr<sgfx::Group> addDuskAndStreetLamps(PolygonScene& scene, int count, std::uint64_t seed);

} // namespace polygon

#pragma once
// Texture units of a material program, in one place (private to the renderer and the composer):
//   material maps      0..12  unit = MaterialMap index (the shader's SGFX_MAP_* defines)
//   transmission       13     the copy of the opaque scene transmissive materials sample
//                             (SGFX_UNIT_TRANSMISSION)
//   StateSet textures  14..19 in the StateSet's order
//   frame resources    20..31 effect samplers (snippet order), then Renderer::bindFrameResource
//   a drawable's own   32..47 Renderer::kFirstDrawableUnit: tracked by the cache, never handed out
#include "sgfx/Material.h"
#include "sgfx/Renderer.h"

#include <array>

namespace sgfx::render {

constexpr unsigned materialUnit(MaterialMap map) {
    return unsigned(map);
}
constexpr unsigned kTransmissionUnit = unsigned(kMaterialMapCount);
constexpr unsigned kFirstUserUnit = kTransmissionUnit + 1;
constexpr unsigned kUserUnits = 6;
constexpr unsigned kFirstFrameResourceUnit = kFirstUserUnit + kUserUnits;
constexpr unsigned kHandedOutUnits = Renderer::kFirstDrawableUnit; ///< 0..31: the renderer's
constexpr unsigned kDrawableUnits = 16;
constexpr unsigned kTrackedUnits = Renderer::kFirstDrawableUnit + kDrawableUnits;
static_assert(kFirstFrameResourceUnit + 4 <= kHandedOutUnits, "too few units left for frame resources");

/// The GLSL name of each map's unit (and index into sgfx_uvTransform), `#define`d by the composer.
inline constexpr std::array<const char*, kMaterialMapCount> kMaterialMapDefines = {
    "SGFX_MAP_BASE_COLOR",       "SGFX_MAP_ALPHA",
    "SGFX_MAP_NORMAL",           "SGFX_MAP_METAL_ROUGH",
    "SGFX_MAP_OCCLUSION",        "SGFX_MAP_EMISSIVE",
    "SGFX_MAP_CLEARCOAT",        "SGFX_MAP_CLEARCOAT_ROUGHNESS",
    "SGFX_MAP_CLEARCOAT_NORMAL", "SGFX_MAP_SPECULAR",
    "SGFX_MAP_SPECULAR_COLOR",   "SGFX_MAP_TRANSMISSION",
    "SGFX_MAP_THICKNESS"};

} // namespace sgfx::render

#pragma once
// The lights of a view as the built-in material reads them from shader storage (lights.glsl):
// packed lights, and for many lights a list per screen tile built on the CPU each frame. No GL.
#include "sgfx/RenderQueue.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace sgfx::render {

/// std430 mirror of lights.glsl's SgfxLight.
struct GpuLight {
    glm::vec4 vector; ///< as LightInfo::vector
    glm::vec4 color;  ///< rgb: colour × intensity, w: 1 / range (0: unlimited)
    glm::vec4 spot;   ///< xyz: spot axis, w: cone scale
    glm::vec4 params; ///< x: cone offset, y: 1 = inverse square, z: the light's index in the view
};
/// `index`: its place in the view's lights (RenderQueue::lights, the frame block's order), which
/// the list reorders: effects that name a light (shadows) name it by this index.
GpuLight packLight(const LightInfo& light, int index);

/// Pixels [x0, x1] × [y0, y1] (inclusive, origin bottom left, as gl_FragCoord) that hold the
/// image of a view-space sphere under `projection` (perspective or orthographic), widened by a
/// pixel and clipped to the width × height target. The part of the sphere in front of the near
/// plane lies in a box whose corners all have z < 0, so the hull of their images bounds it.
/// False when no part of it is between the near and far planes or on the target.
bool sphereScreenRect(const glm::vec3& centre, float radius, const glm::mat4& projection, int width,
                      int height, glm::ivec4& rect);

/// The light list of a view (RendererOptions::maxUnrolledLights exceeded).
struct LightList {
    static constexpr int kTileSize = 16; ///< pixels per tile side
    int tilesX = 0, tilesY = 0;
    int global = 0;               ///< lights without a range: the first `global` of `lights`
    std::vector<GpuLight> lights; ///< unranged, then the ranged lights seen in some tile
    /// [2t]: where tile t's list starts in this array, [2t + 1]: its length; then the lists
    /// (indices into `lights`), tiles row by row from the bottom left.
    std::vector<std::uint32_t> tiles;

    /// Rebuilds it for a width × height target; `view` takes world to view space.
    void build(std::span<const LightInfo> all, const glm::mat4& view, const glm::mat4& projection, int width,
               int height);

private:
    std::vector<glm::ivec4> rects_; ///< tile rectangle of each ranged light
};

} // namespace sgfx::render

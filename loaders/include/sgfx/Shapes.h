#pragma once
/// @file
/// Procedural shapes with normals, texcoords and tangents, Z up, centred unless stated.
/// Texture coordinates follow glTF: (0, 0) is the image's top-left corner as seen from the front.
#include "sgfx/Export.h"
#include <sgfx/Geometry.h>

#include <functional>
#include <memory>

namespace sgfx::shapes {

/// Axis-aligned box of the given full size.
SGFX_API std::shared_ptr<Geometry> box(const glm::vec3& size);
/// Quad in the XY plane facing +Z, `width` along X, `height` along Y.
SGFX_API std::shared_ptr<Geometry> quad(float width, float height);
/// Cylinder along +Z from z=0 to z=height.
SGFX_API std::shared_ptr<Geometry> cylinder(float radius, float height, int segments = 16, bool caps = true);
/// Cone along +Z from z=0 (base) to the apex at z=height.
SGFX_API std::shared_ptr<Geometry> cone(float radius, float height, int segments = 16);
SGFX_API std::shared_ptr<Geometry> sphere(float radius, int segments = 16, int rings = 8);
/// Regular grid over [x0,x0+sizeX]×[y0,y0+sizeY] with nx×ny cells; z = height(x, y).
/// Normals come from central differences of `height`.
SGFX_API std::shared_ptr<Geometry> heightfield(float x0, float y0, float sizeX, float sizeY, int nx, int ny,
                                               const std::function<float(float, float)>& height);

/// Appends `src` transformed by `m` into `dst` (same attribute layout; both Triangles).
SGFX_API void append(Geometry& dst, const Geometry& src, const glm::mat4& m);

} // namespace sgfx::shapes

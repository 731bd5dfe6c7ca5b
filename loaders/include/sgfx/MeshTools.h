#pragma once
/// @file
/// Mesh processing the loaders share: normals and tangents for triangle geometry that lacks them.
#include "sgfx/Export.h"
#include <sgfx/Geometry.h>

namespace sgfx {

/// Replaces the normals of a triangle geometry (indexed or not; strips and fans are turned into
/// triangles). creaseAngle (radians) 0: flat, one normal per face; otherwise corners at one
/// position share a smooth normal (angle-weighted) with the faces whose normals lie within the
/// crease angle of their own face's normal, so hard edges stay hard. Vertices are split where
/// normals differ and welded where they agree. Throws std::invalid_argument for other modes or
/// a negative or NaN angle.
SGFX_API void computeNormals(Geometry& geometry, float creaseAngle);

/// Tangents (xyz, w = handedness) from positions, normals and texcoords, with MikkTSpace's main
/// rules: per-face tangents from the texture derivatives, angle-weighted, orthogonalised against
/// the vertex normal, and vertices split where faces disagree in handedness (mirrored UVs).
/// Needs triangles with normals and texcoords; throws std::invalid_argument otherwise.
SGFX_API void computeTangents(Geometry& geometry);

} // namespace sgfx

#pragma once
/// @file
/// Older mesh formats through OpenMesh (Debian's libopenmesh-dev): OBJ, OFF, PLY and STL, read as
/// triangle meshes (polygons are triangulated) with the file's normals, or smooth normals made
/// from the faces when it has none; and written back, so other tools and peer benchmarks can load
/// exactly what sgfx renders. Errors raise LoadError naming the file and the reason.
#include "sgfx/Export.h"
#include <sgfx/GltfLoader.h>

#include <sgfx/Geometry.h>

#include <filesystem>
#include <memory>

namespace sgfx {

/// By the file's extension: .obj, .off, .ply, .stl (ASCII or binary). An OBJ's vertex colours
/// (`v x y z r g b`) become `colors`, as loadMeshModel reads them. Throws LoadError.
SGFX_API std::shared_ptr<Geometry> loadMesh(const std::filesystem::path& file);

/// A model with its materials: for .obj, the `mtllib` materials (Kd, Ka, Ks, Ns, Ke, d/Tr, map_Kd,
/// map_d, map_Bump/bump/norm) and texture coordinates, one Geometry per material in order of first
/// use (vertices split where a corner's texcoord or normal differs, texcoords flipped to glTF's
/// top-left origin); a missing MTL file or unknown material gives geometry with no StateSet (the
/// scene's default material). OBJ vertex colours, `v x y z r g b` as MeshLab, CloudCompare and
/// OpenSceneGraph write them, are sRGB-encoded display values in 0..1, or 0..255 when any component
/// in the file is above 1; they become the Geometry's `colors`, decoded to linear, alpha 1, on the
/// geometries with a coloured vertex (a vertex without a colour there is white, which leaves the
/// material's colour as it is). Other formats: loadMesh's Geometry in a Group. Throws LoadError
/// naming file:line for bad OBJ/MTL lines (a `v` line with 5 or 7+ numbers, a colour component that
/// is not a number, negative or above 255), and the .mtl file and material for a texture that is
/// missing or does not decode.
SGFX_API std::shared_ptr<Group> loadMeshModel(const std::filesystem::path& file);

/// Writes a triangle geometry (positions, normals; for .obj also colours, as writeObj does) by the
/// extension: .obj, .off, .ply, .stl.
/// Throws LoadError naming the file when the geometry is not triangles or the file cannot be written.
SGFX_API void writeMesh(const Geometry& geometry, const std::filesystem::path& file);

} // namespace sgfx

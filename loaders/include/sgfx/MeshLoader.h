#pragma once
// Older mesh formats through OpenMesh (Debian's libopenmesh-dev): OBJ, OFF, PLY and STL, read as
// triangle meshes (polygons are triangulated) with the file's normals, or smooth normals made
// from the faces when it has none; and written back, so other tools and peer benchmarks can load
// exactly what sgfx renders. Errors raise LoadError naming the file and the reason.
#include <sgfx/GltfLoader.h>

#include <sgfx/Geometry.h>

#include <filesystem>
#include <memory>

namespace sgfx {

// By the file's extension: .obj, .off, .ply, .stl (ASCII or binary). Throws LoadError.
std::shared_ptr<Geometry> loadMesh(const std::filesystem::path& file);

// Writes a triangle geometry (positions, normals) by the extension: .obj, .off, .ply, .stl.
// Throws LoadError naming the file when the geometry is not triangles or the file cannot be written.
void writeMesh(const Geometry& geometry, const std::filesystem::path& file);

} // namespace sgfx

#pragma once
/// @file
/// glTF 2.0 into the scene graph (tinygltf from Debian): .gltf with external or base64 buffers,
/// and .glb. Every index, offset, count and type is checked before the data is touched (tinygltf
/// 2.7 accepts many files that break those rules); a bad file raises LoadError naming the file,
/// the element (`meshes[2].primitives[0].indices`) and the reason, and nothing is built.
#include "sgfx/Export.h"
#include <sgfx/Group.h>
#include <sgfx/LoadError.h>
#include <sgfx/MeshOptimize.h>

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sgfx {

/// How glTF content is turned into sgfx nodes (axes, normals, limits).
struct SGFX_API GltfOptions {
    int scene = -1;  ///< the file's default scene (or its first), or this index
    bool zUp = true; ///< rotate glTF's Y-up into sgfx's Z-up at the root
    /// Normals made for primitives without them: 0 = flat (per face, as glTF asks); an angle in
    /// radians smooths faces meeting at less than it (see computeNormals).
    float creaseAngle = 0.0f;
    /// Bytes of decoded vertex, index and image data one load may make. A small file can declare
    /// millions of elements (accessors shared by many primitives, sparse accessors without data,
    /// image headers): past this the load fails with LoadError instead of exhausting memory.
    std::size_t memoryLimit = std::size_t(2) << 30;
    /// Reorder each loaded mesh's triangles and vertices for the vertex cache, overdraw and
    /// vertex fetch (optimizeMeshes, sgfx/MeshOptimize.h): the same triangles, the same image for
    /// opaque meshes; blended, skinned and morphed ones keep their order. loadModel applies it to
    /// the OBJ/OFF/PLY/STL formats too.
    bool optimizeOrder = true;
    /// Levels of detail made at load (addAutoLods, sgfx/MeshOptimize.h) when autoLod.enabled:
    /// each indexed, unskinned, uninstanced mesh of enough triangles gets an LOD whose coarser levels
    /// stay within autoLod.errorPixels on screen (ranges from an upper bound of each level's
    /// Hausdorff distance, hausdorffBound). Off by default: it puts LOD nodes where the file has
    /// meshes (code that walks the loaded graph sees them), and on the foreign city (590k
    /// triangles) it makes the load about 2.2x as long on two cores (the meshes are simplified in
    /// parallel, autoLod.threads) for a frame about 0.7x as long (docs/performance.md, "Automatic
    /// levels of detail"). loadModel applies it to the OBJ/OFF/PLY/STL formats too.
    AutoLodOptions autoLod = {};
};

/// What a load made, for tools and tests.
struct SGFX_API GltfStats {
    std::size_t nodes = 0;      ///< glTF nodes instanced in the scene (each use counts)
    std::size_t meshes = 0;     ///< distinct meshes loaded
    std::size_t primitives = 0; ///< distinct primitives loaded
    std::size_t triangles = 0;  ///< of the distinct meshes, counted once each
    std::size_t materials = 0;
    std::size_t textures = 0;
    std::size_t opaque = 0, masked = 0, blended = 0; ///< materials by alphaMode
    std::size_t tangentsMade = 0;                    ///< primitives given tangents for their normal maps
    std::size_t instances = 0;                       ///< EXT_mesh_gpu_instancing instances drawn
    std::size_t lights = 0; ///< KHR_lights_punctual lights placed (each node that carries one)
    std::size_t skins = 0;      ///< skins (glTF 2.0 Skins)
    std::size_t animations = 0; ///< animations, in the root AnimatedGroup's player
    std::size_t reordered = 0;  ///< geometries reordered by GltfOptions::optimizeOrder
    std::size_t autoLods = 0;   ///< LODs made by GltfOptions::autoLod
    /// Optional extensions the loader ignored, and tinygltf's own warnings.
    std::vector<std::string> warnings;
};

/// Loads the file's scene. Animations, skins and morph targets (issue 26): a file with animations
/// loads as an AnimatedGroup (sgfx/Animation.h) whose player plays the first one, looping, in the
/// update traversal; skinned and morphed meshes are posed on the GPU; nodes keep their names
/// (findNode). Shared meshes stay shared (one Geometry per primitive, used by each
/// node that names the mesh; a node with EXT_mesh_gpu_instancing gets its own instanced copy).
/// Materials use the metallic-roughness model. Supported extensions: KHR_texture_transform,
/// KHR_materials_emissive_strength, EXT_mesh_gpu_instancing, KHR_mesh_quantization,
/// KHR_lights_punctual (Light nodes under their node's Transform; units as sgfx::Light says). A required
/// extension outside that list is a LoadError; an optional one is skipped with a warning (in
/// GltfStats::warnings and on stderr unless `stats` is given). Throws LoadError.
SGFX_API std::shared_ptr<Group> loadGltf(const std::filesystem::path& file, const GltfOptions& options = {},
                                         GltfStats* stats = nullptr);

/// The same from bytes in memory: .glb when they start with "glTF", else .gltf JSON. There is no
/// base directory, so a file that names external buffers or images fails with LoadError (data: URIs
/// and the GLB chunk work). `nameForErrors` stands in for the file name in messages.
SGFX_API std::shared_ptr<Group> loadGltfFromMemory(std::span<const std::byte> bytes,
                                                   std::string_view nameForErrors,
                                                   const GltfOptions& options = {},
                                                   GltfStats* stats = nullptr);

} // namespace sgfx

#pragma once
/// @file
/// One entry point for every model format sgfx reads, chosen by the file's extension (any case):
/// .gltf and .glb through loadGltf; .obj (with its MTL materials), .off, .ply and .stl through
/// loadMeshModel; OpenSceneGraph's formats (.osgt, .osgb, .ive, .osg, .flt, ... see osgExtensions())
/// through loadOsg when sgfx was built with the bridge (without it, .osg/.osgt/.osgb/.osgx/.ive/.flt
/// give a LoadError saying so). Throws LoadError; an unknown extension names the file and the
/// accepted ones.
#include "sgfx/Export.h"
#include <sgfx/GltfLoader.h>

#include <filesystem>
#include <memory>

namespace sgfx {

/// `gltf` applies to glTF files only, but for optimizeOrder and autoLod, which apply to the OBJ,
/// OFF, PLY and STL formats too.
SGFX_API std::shared_ptr<Group> loadModel(const std::filesystem::path& file, const GltfOptions& gltf = {});

} // namespace sgfx

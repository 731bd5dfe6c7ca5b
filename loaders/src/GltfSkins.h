#pragma once
// glTF skins, morph targets and animations for the loader (issue 26): read through the checked
// accessors of GltfAccessors.h, every count, index and time checked, errors naming the element.
#include "GltfAccessors.h"

#include <sgfx/Animation.h>
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace sgfx::gltf {

/// JOINTS_0/WEIGHTS_0 and JOINTS_1/WEIGHTS_1 of a primitive into `g` (n vertices), weights
/// normalised per vertex; a vertex with no weight is bound to joint 0 (and counted in `unweighted`).
void readSkinAttributes(const Context& c, const tinygltf::Primitive& p, const std::string& element,
                        std::size_t n, Geometry& g, std::size_t& unweighted);
/// The primitive's morph targets (POSITION, NORMAL, TANGENT displacements) into `g`.
void readMorphTargets(const Context& c, const tinygltf::Primitive& p, const std::string& element,
                      std::size_t n, Geometry& g);

/// What the loader made for each glTF node: one Transform per use in the scene, and per use the
/// geometries of its mesh (the node's own copies when skinned or morphed).
struct NodeInstances {
    std::vector<std::vector<std::shared_ptr<Transform>>> transforms;           ///< by node index
    std::vector<std::vector<std::vector<std::shared_ptr<Geometry>>>> geometry; ///< by node, then use
};

/// skins[i] with joints resolved to the first Transform made for each joint node; `root` is where
/// joint matrices start (the loaded model's root).
std::vector<std::shared_ptr<Skin>> readSkins(const Context& c, const NodeInstances& nodes,
                                             const std::shared_ptr<Node>& root);

/// Every animation of the file into `player`: one target per use of each animated node.
void readAnimations(const Context& c, const NodeInstances& nodes, AnimationPlayer& player);

} // namespace sgfx::gltf

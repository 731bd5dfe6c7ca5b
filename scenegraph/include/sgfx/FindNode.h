#pragma once
/// @file
/// Reaching nodes by name (osgDB's FindNamedNode; a DOFTransform's axes are set this way).
#include "sgfx/Export.h"
#include "sgfx/Node.h"

#include <functional>
#include <memory>
#include <string_view>
#include <vector>

namespace sgfx {

/// Every node under `root` (root included) that `match` accepts, depth first, pre-order, over all
/// children whatever their node masks; a node reached through several parents is listed once.
/// With `firstOnly`, stops at the first.
SGFX_API std::vector<NodePtr> findNodesIf(Node& root, const std::function<bool(Node&)>& match,
                                          bool firstOnly = false);

/// The first node named `name` (depth first, pre-order, root included), or null.
SGFX_API NodePtr findNode(Node& root, std::string_view name);
/// Every node named `name`, in that order, each once.
SGFX_API std::vector<NodePtr> findNodes(Node& root, std::string_view name);

/// The first node named `name` that is a T (nodes of that name of other types are passed over).
template <class T> std::shared_ptr<T> findNode(Node& root, std::string_view name) {
    const auto found = findNodesIf(
        root, [name](Node& n) { return n.name == name && dynamic_cast<T*>(&n) != nullptr; }, true);
    return found.empty() ? nullptr : std::static_pointer_cast<T>(found.front());
}

} // namespace sgfx

#include "sgfx/FindNode.h"

#include "sgfx/NodeVisitor.h"

#include <unordered_set>

namespace sgfx {

namespace {

// AllChildren: a hidden node (nodeMask 0) is still found, as osgDB's finders do.
class FindVisitor : public NodeVisitor {
public:
    FindVisitor(const std::function<bool(Node&)>& match, bool firstOnly)
        : NodeVisitor(Mode::AllChildren)
        , match_(match)
        , firstOnly_(firstOnly) {}

    void apply(Node& node) override {
        if (done()) return;
        // A shared node's subtree was searched the first time it was reached.
        if (!seen_.insert(&node).second) return;
        if (match_(node)) found.push_back(node.shared_from_this());
        if (!done()) traverse(node);
    }

    std::vector<NodePtr> found;

private:
    bool done() const { return firstOnly_ && !found.empty(); }
    const std::function<bool(Node&)>& match_;
    bool firstOnly_;
    std::unordered_set<const Node*> seen_;
};

} // namespace

std::vector<NodePtr> findNodesIf(Node& root, const std::function<bool(Node&)>& match, bool firstOnly) {
    FindVisitor v(match, firstOnly);
    root.accept(v);
    return std::move(v.found);
}

NodePtr findNode(Node& root, std::string_view name) {
    auto found = findNodesIf(
        root, [name](Node& n) { return n.name == name; }, true);
    return found.empty() ? nullptr : found.front();
}

std::vector<NodePtr> findNodes(Node& root, std::string_view name) {
    return findNodesIf(root, [name](Node& n) { return n.name == name; });
}

} // namespace sgfx

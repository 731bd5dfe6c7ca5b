#pragma once
#include "sgfx/Export.h"
#include "sgfx/Group.h"

#include <vector>

namespace sgfx {

/// A group whose children are each on or off (OSG's osg::Switch). Visitors in ActiveChildren
/// mode (cull, update, intersection, bounds) visit only the children that are on; AllChildren
/// visitors visit all. As in OSG the bound covers only the children that are on, and changing a
/// value dirties it.
class SGFX_API Switch : public Group {
public:
    static std::shared_ptr<Switch> create() { return std::make_shared<Switch>(); }
    void accept(NodeVisitor& v) override;
    void traverse(NodeVisitor& v) override;

    /// As Group::addChild, with the child's value given (others get newChildDefault()).
    using Group::addChild;
    void addChild(NodePtr child, bool on);

    /// Throws std::out_of_range naming the switch for an index >= numChildren().
    void setValue(std::size_t index, bool on);
    bool value(std::size_t index) const;
    const std::vector<bool>& values() const { return values_; }
    void setAllChildrenOn() { setAll(true); }
    void setAllChildrenOff() { setAll(false); }
    /// Turns `index` on and every other child off (out_of_range as setValue, nothing changed).
    void setSingleChildOn(std::size_t index);

    /// The value children added through Group's addChild/insertChild get (default on).
    void setNewChildDefault(bool on) { newChildDefault_ = on; }
    bool newChildDefault() const { return newChildDefault_; }

protected:
    BoundingSphere computeBound() const override;
    void childInserted(std::size_t index) override;
    void childRemoved(std::size_t index) override;

private:
    void setAll(bool on);
    void checkIndex(std::size_t index, const char* what) const;
    std::vector<bool> values_;
    bool newChildDefault_ = true;
};

} // namespace sgfx

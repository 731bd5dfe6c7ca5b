#pragma once
#include "sgfx/Export.h"
#include "sgfx/Group.h"

#include <glm/glm.hpp>

namespace sgfx {

/// Turns its children about its local origin to face the eye of each view that draws it
/// (OSG's osg::Billboard): trees, signs and lights seen from any side as one card. The cull
/// traversal applies the rotation; every other visitor sees the children unrotated (exports,
/// bounds of the rest pose), while bound() holds every orientation.
class SGFX_API Billboard : public Group {
public:
    enum class Mode : std::uint8_t {
        AxialRotation, ///< about `axis` only (trees: they stay upright)
        PointRotEye,   ///< fully towards the eye, `axis` kept as close to the view's up as it can
    };
    static std::shared_ptr<Billboard> create(Mode mode = Mode::AxialRotation) {
        auto b = std::make_shared<Billboard>();
        b->mode = mode;
        return b;
    }
    void accept(NodeVisitor& v) override;

    Mode mode = Mode::AxialRotation;
    /// Unit vectors in the billboard's frame: the rotation axis (AxialRotation) or the up
    /// direction (PointRotEye), and the side of the children that faces the eye. They must be
    /// perpendicular (OSG's defaults: Z up, -Y towards the viewer).
    glm::vec3 axis{0.0f, 0.0f, 1.0f};
    glm::vec3 normal{0.0f, -1.0f, 0.0f};

    /// The rotation that turns `normal` towards an eye at `eye` (the billboard's frame), about
    /// `axis`, or fully with `axis` turned towards the view's `up` (PointRotEye). An eye on the
    /// axis or at the origin leaves the rest pose. Throws std::invalid_argument naming the
    /// billboard when axis or normal is not finite, not unit length or not perpendicular (to
    /// 1e-3).
    glm::mat4 orientation(const glm::vec3& eye, const glm::vec3& up = {0.0f, 0.0f, 1.0f}) const;

protected:
    /// Holds the children under every rotation: about the axis, a sphere on the axis; fully,
    /// a sphere around the origin.
    BoundingSphere computeBound() const override;
};

} // namespace sgfx

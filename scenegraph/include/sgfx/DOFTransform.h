#pragma once
/// @file
/// Articulation driven by a simulation: osgSim::DOFTransform and OpenFlight's DOF bead. A
/// DOFTransform has named axes (rotor angle, gear extension, turret yaw, elevator deflection),
/// each with limits; the simulation sets their values and the node's matrix follows.
#include "sgfx/Export.h"
#include "sgfx/Group.h"

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sgfx {

/// A Transform whose matrix is computed from named degrees of freedom:
///
///     matrix() = put · motion · put⁻¹ · base
///
/// `base` is where the children rest (every axis at 0, scales at 1) in the parent's coordinates;
/// `put` is the DOF's local frame in the parent's coordinates (OpenFlight's local coordinate
/// system: its origin is the pivot, its axes the ones the motion acts along); `motion` is the axes'
/// values in that frame, in osgSim::DOFTransform's default order (MultOrder PRH):
///
///     motion = T(tx, ty, tz) · Rx(pitch) · Ry(roll) · Rz(heading) · S(sx, sy, sz)
///
/// so a point is scaled first, then turned about Z (heading), Y (roll) and X (pitch), then moved:
/// the same matrices as an OpenFlight model loaded through osgSim, and heading innermost, as a
/// turret's yaw sits under its gun's pitch when the two are one node. sgfx is Z up, so RotateZ is
/// a heading. Rotations are right-handed about the frame's axes, in radians; translations in
/// metres. A node has at most one axis of each kind (as a DOF bead does); mechanisms with more
/// (a turret and its gun) nest nodes.
///
/// Visited as a Transform: culling, bounds, queries and exporters see matrix(). Every set()
/// recomputes it through Transform::setMatrix, which dirties the bounds above.
class SGFX_API DOFTransform : public Transform {
public:
    enum class Kind { RotateX, RotateY, RotateZ, TranslateX, TranslateY, TranslateZ, ScaleX, ScaleY, ScaleZ };
    /// Clamp: values outside [min, max] are clamped. Wrap: values are wrapped into [min, max)
    /// (rotations only: a rotor turning on and on, min = 0 and max = 2 pi).
    enum class Limit { Clamp, Wrap };

    struct Axis {
        std::string name; ///< unique on the node, not empty
        Kind kind = Kind::RotateZ;
        double min = 0.0, max = 0.0; ///< radians, metres or scale factors; min <= max (min < max to wrap)
        Limit limit = Limit::Clamp;
        double value = 0.0; ///< the initial value given to addAxis (limited there), then the current one
    };

    static std::shared_ptr<DOFTransform> create() { return std::make_shared<DOFTransform>(); }

    /// Adds an axis at `initial` (default: 0, or 1 for a scale; limited into range). Throws
    /// std::invalid_argument, naming the node and the axis, for an empty or repeated name, a second axis of
    /// the same kind, a non-finite bound or initial value, min > max, or Wrap on a translation or scale or
    /// over an empty range.
    void addAxis(std::string axis, Kind kind, double min, double max, Limit limit = Limit::Clamp,
                 std::optional<double> initial = std::nullopt);
    void addAxis(const Axis& a) { addAxis(a.name, a.kind, a.min, a.max, a.limit, a.value); }

    /// Sets an axis's value, clamped or wrapped into its range, and returns the value kept. Throws
    /// std::invalid_argument for an unknown name (listing the node's axes) or a non-finite value;
    /// then nothing changes.
    double set(std::string_view axis, double value);
    /// The axis's current value; throws std::invalid_argument for an unknown name, as set().
    double value(std::string_view axis) const;
    bool hasAxis(std::string_view axis) const { return find(axis) != nullptr; }
    const std::vector<Axis>& axes() const { return axes_; }

    /// The DOF's local frame (OpenFlight's put matrix): frame coordinates to the parent's. Throws
    /// std::invalid_argument, naming the node, for a non-finite, non-affine or singular matrix.
    void setFrame(const glm::mat4& put);
    /// As setFrame: origin and rotation (whose columns are the frame's axes in the parent).
    void setFrame(const glm::vec3& origin, const glm::mat3& rotation);
    const glm::mat4& frame() const { return put_; }
    /// The children's rest placement in the parent (checked as setFrame).
    void setBase(const glm::mat4& base);
    const glm::mat4& base() const { return base_; }

    /// The motion alone (T · Rx · Ry · Rz · S in the frame), from the current values.
    glm::dmat4 motion() const;

    /// Hidden: the matrix follows the axes. (Through a Transform& it still writes the matrix,
    /// until the next set().)
    void setMatrix(const glm::mat4&) = delete;

private:
    const Axis* find(std::string_view axis) const;
    [[noreturn]] void unknownAxis(std::string_view axis) const;
    void update();
    std::vector<Axis> axes_;
    glm::mat4 put_{1.0f}, base_{1.0f};
    glm::dmat4 putInverse_{1.0};
};

} // namespace sgfx

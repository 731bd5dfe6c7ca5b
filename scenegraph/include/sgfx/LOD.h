#pragma once
#include "sgfx/Export.h"
#include "sgfx/Group.h"

#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace sgfx {

/// Projected diameter, in pixels, of a sphere whose centre is `viewCenter` (view space) under
/// `projection`, for a viewport `viewportHeight` pixels tall: 2r · (P[1][1] / 2) · height / w with
/// w = |P[2][3]| · |viewCenter| + P[3][3]. For a perspective projection w is the distance from the
/// eye (not the view depth, so turning the camera does not switch levels); for an orthographic one
/// w = 1 and the size depends on the view volume's height only. An eye at the centre gives the
/// largest finite float.
SGFX_API float pixelSize(const glm::vec3& viewCenter, float radius, const glm::mat4& projection,
                         int viewportHeight);

/// Level of detail (OSG's osg::LOD). In PixelSize mode (the default; OSG's PIXEL_SIZE_ON_SCREEN)
/// the cull visitor visits exactly the children whose range [minPixels, maxPixels) holds the
/// projected diameter of the LOD's bounding sphere (or of the user sphere). In DistanceFromEye
/// mode (OSG's default, DISTANCE_FROM_EYE_POINT) the range holds the distance from the eye to the
/// sphere's centre, measured as OSG does in the LOD's own frame: under a Transform that scales
/// by 2 a child with range [0, 10) shows to 20 m, so ranges keep their meaning when a model
/// authored in other units is scaled into the scene. A cull with a reference view (a shadow
/// cull) measures from the reference view's eye. Every other visitor sees all children, and the
/// bound is the union of all children, so switching never changes the bound.
class SGFX_API LOD : public Group {
public:
    enum class RangeMode : std::uint8_t { PixelSize, DistanceFromEye };
    /// The range in which a child is drawn: pixels on screen, or distances in the LOD's frame
    /// in DistanceFromEye mode (the field names are PixelSize's).
    struct Range {
        float minPixels = 0.0f;
        float maxPixels = std::numeric_limits<float>::infinity();
        bool contains(float pixels) const { return pixels >= minPixels && pixels < maxPixels; }
    };

    static std::shared_ptr<LOD> create() { return std::make_shared<LOD>(); }
    void accept(NodeVisitor& v) override;

    /// Children added through Group's addChild/insertChild get [0, inf): always shown.
    using Group::addChild;
    /// Throws std::invalid_argument naming the LOD and the child index for a NaN or negative
    /// bound or minPixels > maxPixels; nothing is added then.
    void addChild(NodePtr child, float minPixels, float maxPixels);
    /// Same checks; throws std::out_of_range for a bad index.
    void setRange(std::size_t index, float minPixels, float maxPixels);
    const Range& range(std::size_t index) const { return ranges_.at(index); }
    const std::vector<Range>& ranges() const { return ranges_; }

    /// Throws std::invalid_argument naming the LOD for a value that is not a RangeMode.
    void setRangeMode(RangeMode mode);
    RangeMode rangeMode() const { return rangeMode_; }
    /// How fine child `index` is, larger for finer: its range's upper pixel bound, or minus its
    /// lower distance bound. The finest children are those shown when the LOD is nearest.
    float fineness(std::size_t index) const;

    /// Measure this sphere (LOD's local frame) instead of the bound, like OSG's
    /// USER_DEFINED_CENTER: levels then switch at the same place however the children differ.
    /// Throws std::invalid_argument for a non-finite centre or a radius that is not > 0.
    void setUserSphere(const glm::vec3& center, float radius);
    void clearUserSphere() { userSphere_.reset(); }
    const std::optional<BoundingSphere>& userSphere() const { return userSphere_; }
    /// The sphere whose size selects the children: the user sphere or the bound.
    const BoundingSphere& selectionSphere() const { return userSphere_ ? *userSphere_ : bound(); }

protected:
    void childInserted(std::size_t index) override;
    void childRemoved(std::size_t index) override;
    void checkRange(std::size_t index, float minPixels, float maxPixels) const;

private:
    std::vector<Range> ranges_;
    std::optional<BoundingSphere> userSphere_;
    RangeMode rangeMode_ = RangeMode::PixelSize;
};

} // namespace sgfx

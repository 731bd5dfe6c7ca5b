#pragma once
/// @file
/// One projector on a spherical mirror (OpenSceneGraph's `setUpViewForPanoramicSphericalDisplay` and
/// `setUpViewFor3DSphericalDisplay`): its parameters and the distortion mesh that maps a direction from
/// the eye to a pixel of the projector image. Pure maths, no GL; the renderer is
/// <sgfx/nodes/spherical/SphericalDisplayRig.h>, the `.view` reader <sgfx/OsgViewConfig.h>.
#include "sgfx/Export.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace sgfx {

enum class SphericalDisplayKind : std::uint8_t {
    Panoramic, ///< setUpViewForPanoramicSphericalDisplay: 360° around, the mesh from directions
    ThreeD,    ///< setUpViewFor3DSphericalDisplay: the mesh from projector rays
};

/// One point of an intensity map: the angle in degrees (0..180, see intensityAt) and the
/// brightness in percent.
struct SGFX_API IntensityPoint {
    float angleDeg = 0.0f;
    float percent = 100.0f;
    bool operator==(const IntensityPoint&) const = default;
};

/// The parameters a `.view` file gives; defaults are OSG's (View_readLocalData in
/// src/osgWrappers/deprecated-dotosg/osgViewer/View.cpp: radius 1, collar 0.45, screen 0).
struct SGFX_API SphericalDisplayParams {
    static constexpr int kMaxIntensityPoints = 32;
    SphericalDisplayKind kind = SphericalDisplayKind::Panoramic;
    double radius = 1.0;    ///< the mirror's radius
    double collar = 0.45;   ///< the collar's radius; the projector sits sqrt(radius² − collar²) below
    unsigned screenNum = 0; ///< OSG's screen; kept, no meaning headless
    /// Sorted by angle, angles distinct; empty: 100 % everywhere (OSG: no intensity map).
    std::vector<IntensityPoint> intensityMap;
    /// OSG's projectorMatrix in column-vector form (the transpose of the file's row-vector matrix):
    /// a direction d becomes (P·(d,1)).xyz / w, as osg::Vec3 * osg::Matrix does.
    glm::dmat4 projector{1.0};

    /// Throws std::invalid_argument naming the field: radius not finite or <= 0, collar outside
    /// [0, radius), more than kMaxIntensityPoints points, angles outside [0, 180] or not increasing,
    /// percent not finite or negative, a non-finite projector.
    void validate() const;
    bool operator==(const SphericalDisplayParams&) const = default;
};

/// OSG's intensity map (readIntensityImage in View.cpp): linear between the points, the end values
/// held beyond them, percent × 0.01. Empty map: 1.
SGFX_API double intensityAt(const std::vector<IntensityPoint>& map, double angleDeg);

/// One vertex of the distortion mesh: where it lands on the projector image (pixels, origin bottom
/// left), the direction from the eye it shows (display frame: +Y forward, +Z up, +X right, as OSG's
/// cube faces), and the angle the intensity map is read at, degrees.
struct SGFX_API WarpVertex {
    glm::vec2 pixel{0.0f};
    glm::vec3 direction{0.0f, 1.0f, 0.0f};
    float angleDeg = 0.0f;
};

struct SGFX_API WarpMesh {
    std::vector<WarpVertex> vertices;
    std::vector<std::uint32_t> indices; ///< triangles
};

/// The distortion mesh for a projector image of width × height pixels. `steps` vertices a side;
/// 0 takes OSG's (160 panoramic, 50 3D). Throws std::invalid_argument for bad params (validate),
/// sizes outside 1..16384 or steps outside {0} ∪ [2, 1024].
SGFX_API WarpMesh sphericalWarpMesh(const SphericalDisplayParams& p, int width, int height, int steps = 0);

/// The direction (display frame) and intensity angle OSG's 3D mesh gives the point `pixel` of the
/// image (create3DSphericalDisplayDistortionMesh, off-centre projection): exact, not interpolated.
SGFX_API WarpVertex sphericalThreeDAt(const SphericalDisplayParams& p, int width, int height,
                                      glm::vec2 pixel);

} // namespace sgfx

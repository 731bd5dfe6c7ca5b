#pragma once
/// @file
/// A spherical-mirror display channel (OSG's setUpViewForPanoramicSphericalDisplay and
/// setUpViewFor3DSphericalDisplay): six 90° render-to-texture cameras around the eye, then the
/// distortion mesh (sgfx::sphericalWarpMesh) drawn into the projector image, sampling the faces and
/// multiplied by the intensity map.
#include "sgfx/Camera.h"
#include "sgfx/Export.h"
#include "sgfx/Geometry.h"
#include "sgfx/Group.h"
#include "sgfx/SphericalDisplay.h"

#include <glm/glm.hpp>

#include <array>
#include <memory>

namespace sgfx {

struct SGFX_API SphericalDisplaySetup {
    int width = 1024, height = 1024; ///< the projector image, pixels
    int faceSize = 512;              ///< each cube face, pixels (OSG: 512)
    float zNear = 0.1f, zFar = 1000.0f;
    int meshSteps = 0; ///< sphericalWarpMesh's steps; 0 = OSG's
    /// Throws std::invalid_argument naming the field (sizes outside 1..16384, faceSize outside
    /// 1..8192, 0 < zNear < zFar finite, meshSteps).
    void validate() const;
};

/// The camera arrangement: put `root` under the viewer (setSceneData), call configureOutputCamera
/// on the viewer's camera, and setEyeView each frame with the eye's view matrix (world → view,
/// looking down −Z, as Camera::viewMatrix). Faces are +X, −X, +Y, −Y, +Z, −Z of the display frame
/// (+Y the eye's forward, +Z its up, +X its right), OSG's right, left, front, back, top, bottom.
class SGFX_API SphericalDisplayRig {
public:
    /// Throws std::invalid_argument for bad params or setup.
    static std::shared_ptr<SphericalDisplayRig> create(const SphericalDisplayParams& params,
                                                       const SphericalDisplaySetup& setup, NodePtr scene);

    const std::shared_ptr<Group>& root() const { return root_; }
    const std::array<std::shared_ptr<Camera>, 6>& faces() const { return faces_; }
    const std::shared_ptr<Geometry>& mesh() const { return mesh_; }
    const SphericalDisplayParams& params() const { return params_; }
    const SphericalDisplaySetup& setup() const { return setup_; }

    /// Points the six face cameras from the eye of `view` (throws std::invalid_argument for a
    /// non-finite or singular matrix; the old view stays).
    void setEyeView(const glm::mat4& view);
    /// Viewport of the projector image, black clear, no culling of the mesh needed.
    void configureOutputCamera(Camera& output) const;
    /// Display frame (+Y forward, +Z up) → face view (looking down −Z), for face 0..5.
    static glm::mat4 faceRotation(int face);

private:
    SphericalDisplayParams params_;
    SphericalDisplaySetup setup_;
    std::shared_ptr<Group> root_;
    std::array<std::shared_ptr<Camera>, 6> faces_;
    std::shared_ptr<Geometry> mesh_;
};

} // namespace sgfx

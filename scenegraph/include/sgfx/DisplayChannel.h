#pragma once
// Display channels: one eye point, several views of it (the screens of a wall, the projectors of a
// cylinder or dome). Each channel turns the eye's view by its own offset and looks through its own
// off-axis frustum; its image is one rectangle of the display's composite.
#include "sgfx/Camera.h"
#include "sgfx/Export.h"

#include <glm/glm.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace sgfx {

/// An off-axis perspective frustum (glFrustum's): the image's edges on the near plane, in the
/// channel's view space, metres; left < right, bottom < top, 0 < zNear < zFar.
struct SGFX_API OffAxisFrustum {
    float left = -0.1f, right = 0.1f, bottom = -0.1f, top = 0.1f;
    float zNear = 0.1f, zFar = 1000.0f;

    /// From angles in degrees from the view axis: left and down negative, right and up positive
    /// (each in (-90, 90), left < right, down < up).
    static OffAxisFrustum fromAngles(float leftDeg, float rightDeg, float downDeg, float upDeg, float zNear,
                                     float zFar);
    /// The part of this frustum between fractions x0..x1 of its width and y0..y1 of its height
    /// (0 left/bottom, 1 right/top): a screen's share of a wall's overall frustum.
    OffAxisFrustum sub(double x0, double x1, double y0, double y1) const;
    /// glm::frustum(left, right, bottom, top, zNear, zFar).
    glm::mat4 projection() const;
    /// Throws std::invalid_argument naming `where` and the field (non-finite, left >= right, ...).
    void validate(std::string_view where) const;
    bool operator==(const OffAxisFrustum&) const = default;
};

/// One channel of a display.
struct SGFX_API DisplayChannel {
    std::string name;
    /// The channel's view in the eye's view space (rotation, then translation from the eye point):
    /// the channel's camera sits at viewOffset's origin and looks down its −Z. Identity: the eye's view.
    glm::mat4 viewOffset{1.0f};
    OffAxisFrustum frustum;
    /// Where the channel's image lies in the display's composite, pixels, origin bottom left; its
    /// width and height are the channel's resolution.
    Viewport viewport;

    /// The channel's view matrix for the eye's view matrix: inverse(viewOffset) · eyeView.
    glm::mat4 viewMatrix(const glm::mat4& eyeView) const;
    /// Throws std::invalid_argument naming the channel and the field.
    void validate() const;
};

/// Checks a display's channels: each valid, names unique and non-empty, viewports inside
/// [0, 16384)² and not overlapping. Throws std::invalid_argument naming the channel and field.
SGFX_API void validateChannels(const std::vector<DisplayChannel>& channels);

/// The composite's size: the bounding box of the channels' viewports from (0, 0).
SGFX_API Viewport compositeViewport(const std::vector<DisplayChannel>& channels);

} // namespace sgfx

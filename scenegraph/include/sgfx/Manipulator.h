#pragma once
/// @file
/// Camera manipulators (OSG's osgGA vocabulary): they turn input into a view matrix. Input comes
/// as plain numbers (pixels, seconds, key axes), so any window system, a replay or a test can
/// drive them. World space is Z up, as everywhere in sgfx.
#include "sgfx/Export.h"
#include <glm/glm.hpp>

namespace sgfx {

class Camera;

/// Which mouse button a drag is made with.
enum class MouseButton : unsigned char { Left, Right, Middle };

/// Turns input into a view: the base of OrbitManipulator and FlyManipulator.
class SGFX_API CameraManipulator {
public:
    virtual ~CameraManipulator() = default;

    /// Frames the box [min, max] so all of it is in view for a vertical field of view of
    /// `fovyDegrees` and a viewport of aspect width/height, seen from azimuth `yawDegrees`
    /// (0: from -Y looking +Y) and elevation `pitchDegrees`. An empty or inverted box frames a
    /// unit box at the origin.
    void home(const glm::vec3& min, const glm::vec3& max, float fovyDegrees, float aspect,
              float yawDegrees = 30.0f, float pitchDegrees = 25.0f);
    /// Puts the eye at `eye` looking at `target` (the pitch kept within ±89°).
    virtual void setLookAt(const glm::vec3& eye, const glm::vec3& target) = 0;

    /// A drag of `pixels` (x right, y down, as window systems report them) in a viewport of
    /// `viewportHeight` pixels.
    virtual void drag(MouseButton button, glm::vec2 pixels, float viewportHeight) = 0;
    /// Wheel steps (positive: away from the user, in towards the scene).
    virtual void scroll(float steps) = 0;
    /// Movement keys held for `seconds`: axes.x right(+)/left(−), .y forward/back, .z up/down,
    /// each in [−1, 1]; `fast` multiplies the speed by 4.
    virtual void move(glm::vec3 axes, float seconds, bool fast) = 0;

    virtual glm::vec3 eye() const = 0;
    /// The point the view is turned towards (the orbit's centre; for flying, one `focus` ahead).
    virtual glm::vec3 target() const = 0;
    glm::mat4 viewMatrix() const;
    /// Writes the view matrix into the camera.
    void apply(Camera& camera) const;

    /// The home radius: the scale the speeds and clip planes follow.
    float sceneRadius() const { return radius_; }

protected:
    float radius_ = 1.0f;
};

/// Turns around a centre: left drag orbits, right drag (or the wheel) zooms, middle drag pans;
/// WASD slide the centre over the ground plane, Q/E lower and raise it.
class SGFX_API OrbitManipulator : public CameraManipulator {
public:
    void setLookAt(const glm::vec3& eye, const glm::vec3& target) override;
    void drag(MouseButton button, glm::vec2 pixels, float viewportHeight) override;
    void scroll(float steps) override;
    void move(glm::vec3 axes, float seconds, bool fast) override;
    glm::vec3 eye() const override;
    glm::vec3 target() const override { return centre; }

    glm::vec3 centre{0.0f};
    float distance = 1.0f;
    float yaw = 0.0f, pitch = 0.0f; ///< radians; yaw 0 looks along +Y, pitch > 0 looks down
};

/// Flies: left drag looks around, WASD move along the view, Q/E down/up, the wheel changes speed.
class SGFX_API FlyManipulator : public CameraManipulator {
public:
    void setLookAt(const glm::vec3& eye, const glm::vec3& target) override;
    void drag(MouseButton button, glm::vec2 pixels, float viewportHeight) override;
    void scroll(float steps) override;
    void move(glm::vec3 axes, float seconds, bool fast) override;
    glm::vec3 eye() const override { return position; }
    glm::vec3 target() const override { return position + focus * direction(); }
    glm::vec3 direction() const;

    glm::vec3 position{0.0f};
    float yaw = 0.0f, pitch = 0.0f; ///< radians, as the orbit's
    float speed = 1.0f;             ///< metres per second
    float focus = 1.0f;             ///< distance to target()
};

} // namespace sgfx

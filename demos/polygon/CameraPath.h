#pragma once
// The proving ground's deterministic camera path, shared by the sgfx demo and the
// OpenSceneGraph peer benchmark so both render exactly the same views.
// World: Z up, metres; the ground spans [-extent/2, extent/2]^2 around the origin.
#include <glm/glm.hpp>

#include <cmath>

namespace polygon {

struct CameraPose {
    glm::vec3 eye;
    glm::vec3 target;
    glm::vec3 up{0, 0, 1};
};

constexpr float kPathFovyDegrees = 60.0f;
constexpr float kPathNear = 0.5f;
constexpr float kPathFar = 2000.0f;

// t in [0, 1): one lap. The camera circles at 55 % of the half-extent, rising and falling
// between 12 and 42 m, looking at a point a quarter-lap ahead and slightly inwards, so views
// sweep across terrain, roads, buildings, trees and the glass panes near the centre.
inline CameraPose cameraPose(float t, float extent) {
    const float twoPi = 6.28318530718f;
    const float r = 0.55f * 0.5f * extent;
    const float a = twoPi * t;
    const float b = a + 0.9f;
    CameraPose p;
    p.eye = glm::vec3(r * std::cos(a), r * std::sin(a), 27.0f + 15.0f * std::sin(2.0f * a));
    p.target = glm::vec3(0.6f * r * std::cos(b), 0.6f * r * std::sin(b), 4.0f);
    return p;
}

} // namespace polygon

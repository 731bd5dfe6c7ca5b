#include "StreetLamps.h"

#include <sgfx/Camera.h>
#include <sgfx/Geometry.h>
#include <sgfx/Shapes.h>
#include <sgfx/StateSet.h>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace polygon {

namespace {

constexpr float kRoadHalfWidth = 4.5f; // PolygonScene's roads are 9 m wide
constexpr float kArm = 2.0f;           // the head hangs this far over the road

std::shared_ptr<sgfx::StateSet> material(const glm::vec3& diffuse,
                                         const glm::vec3& emissive = glm::vec3(0.0f)) {
    auto m = sgfx::Material::create();
    m->ambient = diffuse;
    m->diffuse = glm::vec4(diffuse, 1.0f);
    m->emissive = emissive;
    auto s = sgfx::StateSet::create();
    s->material.set(m);
    return s;
}

// One lamp at the origin, its pole at the origin and its head kArm along +X.
std::shared_ptr<sgfx::Group> lampPrototype() {
    auto lamp = sgfx::Group::create();
    lamp->name = "street_lamp";
    auto pole = sgfx::shapes::cylinder(0.08f, kLampHeight + 0.2f, 8, false);
    pole->setStateSet(material(glm::vec3(0.25f)));
    auto arm = sgfx::shapes::box({kArm + 0.1f, 0.08f, 0.08f});
    sgfx::shapes::append(*pole, *arm,
                         glm::translate(glm::mat4(1.0f), {0.5f * kArm, 0.0f, kLampHeight + 0.15f}));
    lamp->addChild(pole);
    auto head = sgfx::shapes::box({0.6f, 0.3f, 0.12f});
    head->setStateSet(material(glm::vec3(0.1f), glm::vec3(1.0f, 0.82f, 0.55f)));
    auto headPlace =
        sgfx::Transform::create(glm::translate(glm::mat4(1.0f), {kArm, 0.0f, kLampHeight + 0.06f}));
    headPlace->addChild(head);
    lamp->addChild(headPlace);
    auto light = sgfx::Light::create(sgfx::LightType::Spot);
    light->name = "street_lamp_light";
    light->position = {kArm, 0.0f, kLampHeight};
    light->direction = {0.0f, 0.0f, -1.0f};
    light->color = glm::vec3(1.0f, 0.8f, 0.55f); // warm white
    light->intensity = kLampCandela / glm::pi<float>();
    light->falloff = sgfx::LightFalloff::InverseSquare;
    light->range = kLampRange;
    light->innerConeAngle = glm::radians(35.0f);
    light->outerConeAngle = glm::radians(65.0f);
    lamp->addChild(light);
    return lamp;
}

// The point at arc length s along the roads (the ring, then the X and Y cross roads) and the unit
// direction across the road towards its left side.
void roadPoint(const PolygonScene& scene, float s, glm::vec2& at, glm::vec2& left) {
    const float ring = glm::two_pi<float>() * scene.ringRadius, half = 0.5f * scene.extent;
    if (s < ring) {
        const float a = s / scene.ringRadius;
        at = glm::vec2(std::cos(a), std::sin(a)) * scene.ringRadius;
        left = -glm::vec2(std::cos(a), std::sin(a));
        return;
    }
    s -= ring;
    const bool alongX = s < scene.extent;
    const float t = -half + (alongX ? s : s - scene.extent);
    at = alongX ? glm::vec2(t, 0.0f) : glm::vec2(0.0f, t);
    left = alongX ? glm::vec2(0.0f, 1.0f) : glm::vec2(-1.0f, 0.0f);
}

} // namespace

std::shared_ptr<sgfx::Group> addDuskAndStreetLamps(PolygonScene& scene, int count, std::uint64_t seed) {
    if (count < 0 || count > 100000)
        throw std::invalid_argument("polygon: street lamps: " + std::to_string(count) +
                                    " is outside 0..100000");
    for (const auto& child : scene.root->children()) {
        auto* light = dynamic_cast<sgfx::Light*>(child.get());
        if (light && light->name == "sun") {
            const float az = glm::radians(-35.0f), el = glm::radians(4.0f);
            light->direction =
                -glm::vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
            light->color = glm::vec3(1.0f, 0.55f, 0.3f);
            light->intensity = 0.12f;
        } else if (light && light->name == "sky_ambient") {
            light->color = glm::vec3(0.035f, 0.04f, 0.06f);
        }
    }
    const Terrain terrain(seed);
    auto prototype = lampPrototype();
    auto lamps = sgfx::Group::create();
    lamps->name = "street_lamps";
    const float total = glm::two_pi<float>() * scene.ringRadius + 2.0f * scene.extent;
    for (int i = 0; i < count; ++i) {
        glm::vec2 at, left;
        roadPoint(scene, (float(i) + 0.5f) * total / float(count), at, left);
        const glm::vec2 side = (i % 2 ? 1.0f : -1.0f) * left; // from the road's centre to the pole
        const glm::vec2 foot = at + side * (kRoadHalfWidth + 0.7f);
        // The arm (+X of the prototype) points back over the road.
        const float heading = std::atan2(-side.y, -side.x);
        glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(foot, terrain.height(foot.x, foot.y)));
        m = glm::rotate(m, heading, glm::vec3(0, 0, 1));
        auto place = sgfx::Transform::create(m);
        place->name = "street_lamp_" + std::to_string(i);
        place->addChild(prototype);
        lamps->addChild(place);
    }
    scene.root->addChild(lamps);
    return lamps;
}

} // namespace polygon

#include "ViewScene.h"

#include <sgfx/nodes/sky/SkyMath.h>

#include <sgfx/Geometry.h>
#include <sgfx/Material.h>
#include <sgfx/Shapes.h>
#include <sgfx/Visitors.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cxxabi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <typeinfo>

namespace view {

namespace {
const glm::vec3 kSunDirection = glm::normalize(glm::vec3(-0.4f, 0.3f, -0.85f)); // travel direction
constexpr std::uint32_t kWeatherCount = 20000;

// "Transform" for an sgfx::Transform, "FogNode" for an sgfx::FogNode.
std::string typeName(const sgfx::Node& node) {
    const char* mangled = typeid(node).name();
    int status = 0;
    const std::unique_ptr<char, void (*)(void*)> plain(
        abi::__cxa_demangle(mangled, nullptr, nullptr, &status), std::free);
    std::string name = status == 0 && plain ? plain.get() : mangled;
    if (name.starts_with("sgfx::")) name.erase(0, 6);
    return name;
}

// Three numbers as "(x, y, z)", with -0.0000 printed as 0.0000.
std::string triple(const glm::dvec3& v) {
    auto tidy = [](double c) { return std::abs(c) < 5e-5 ? 0.0 : c; };
    char text[96];
    std::snprintf(text, sizeof text, "(%.4f, %.4f, %.4f)", tidy(v.x), tidy(v.y), tidy(v.z));
    return text;
}
} // namespace

ViewScene::ViewScene()
    : world_(sgfx::Group::create())
    , modelSlot_(sgfx::Group::create())
    , ground_(sgfx::Transform::create())
    , weatherPlace_(sgfx::Transform::create())
    , fog_(sgfx::FogNode::create())
    , ao_(sgfx::AmbientOcclusionNode::create())
    , sky_(sgfx::SkyNode::create())
    , env_(sgfx::EnvironmentLightNode::create(sky_))
    , ambient_(sgfx::Light::create(sgfx::LightType::Ambient))
    , sun_(sgfx::Light::create(sgfx::LightType::Directional))
    , shadow_(sgfx::ShadowNode::create(sun_)) {
    auto quad = sgfx::shapes::quad(1.0f, 1.0f);
    auto m = sgfx::Material::create();
    m->diffuse = {0.55f, 0.55f, 0.52f, 1.0f};
    m->ambient = glm::vec3(0.55f);
    quad->getOrCreateStateSet().material.set(m);
    quad->name = "ground plane";
    ground_->name = "ground";
    ground_->addChild(quad);
    world_->addChild(modelSlot_);
    world_->addChild(ground_);
    world_->addChild(weatherPlace_);
    env_->name = "environment light";
    shadow_->name = "shadows";
    shadow_->addChild(world_);
    env_->addChild(shadow_);
    ao_->addChild(env_);
    fog_->addChild(ao_);
    sky_->attachFog(fog_);
    sun_->name = "sun";
    sun_->color = glm::vec3(0.9f);
    auto root = sgfx::Group::create();
    root->addChild(sun_);
    root->addChild(ambient_);
    root->addChild(fog_);
    root->addChild(sky_);
    root_ = root;
}

void ViewScene::setModel(sgfx::NodePtr model) {
    sgfx::ComputeBoundsVisitor bounds;
    model->accept(bounds);
    if (!bounds.valid()) throw std::runtime_error("the files hold no geometry");
    min_ = bounds.min;
    max_ = bounds.max;
    radius_ = std::max(0.5f * glm::length(max_ - min_), 1e-3f);
    const glm::vec3 centre = 0.5f * (min_ + max_);
    modelSlot_->removeChildren();
    modelSlot_->addChild(model);
    model_ = std::move(model);
    ground_->setMatrix(
        glm::scale(glm::translate(glm::mat4(1.0f), {centre.x, centre.y, min_.z - 1e-3f * radius_}),
                   glm::vec3(60.0f * radius_, 60.0f * radius_, 1.0f)));
    // Weather over four model sizes around it, falling from two sizes above its top to its base.
    const glm::vec2 area(8.0f * radius_);
    rain_ = sgfx::ParticleSystemNode::rain(area, kWeatherCount);
    snow_ = sgfx::ParticleSystemNode::snow(area, kWeatherCount);
    const float height = max_.z + 2.0f * radius_;
    for (const auto& p : {rain_, snow_}) {
        sgfx::particles::Emitter e = p->settings().emitter;
        e.lifetime = std::max(0.5f, (height - min_.z) / std::max(-e.velocity.z, 0.1f));
        p->setEmitter(e);
    }
    weatherPlace_->removeChildren();
    weatherPlace_->addChild(rain_);
    weatherPlace_->addChild(snow_);
    weatherPlace_->setMatrix(glm::translate(glm::mat4(1.0f), {centre.x, centre.y, height}));
}

sgfx::FogParameters ViewScene::fogParameters(const Settings& s) const {
    sgfx::FogParameters p;
    switch (s.fogPreset) {
    case FogPreset::Solid:
        p = sgfx::FogParameters::solid();
        break;
    case FogPreset::Ground:
        p = sgfx::FogParameters::ground();
        break;
    case FogPreset::Model: {
        // Half the light from the model's centre reaches the eye at the home distance (40° view).
        const float distance = radius_ / std::sin(glm::radians(20.0f));
        p.density = std::log(2.0f) / distance;
        p.falloff = std::min(1.0f / radius_, 1e3f);
        p.color = {0.72f, 0.76f, 0.82f};
        break;
    }
    }
    p.referenceHeight = s.fogPreset == FogPreset::Model ? min_.z : p.referenceHeight;
    if (s.fogDensity > 0.0f) p.density = s.fogDensity;
    if (s.fogFalloff > 0.0f) p.falloff = s.fogFalloff;
    return p;
}

sgfx::AmbientOcclusionParameters ViewScene::aoParameters(const Settings& s) const {
    sgfx::AmbientOcclusionParameters p;
    p.samples = s.aoSamples;
    p.radius = s.aoRadius > 0.0f ? s.aoRadius : 0.1f * radius_;
    p.bias = 0.05f * p.radius;
    return p;
}

void ViewScene::apply(const Settings& s, sgfx::Camera& camera) {
    fog_->enabled = s.fog;
    if (s.fog) {
        fog_->setParameters(fogParameters(s));
        fog_->setMode(s.fogMode);
    }
    ao_->enabled = s.ao;
    if (s.ao) ao_->setParameters(aoParameters(s));
    camera.setAntiAliasing(s.antiAliasing);
    ground_->nodeMask = s.ground ? ~sgfx::NodeMask{0} : 0;
    if (rain_) {
        rain_->nodeMask = s.weather == Weather::Rain ? ~sgfx::NodeMask{0} : 0;
        snow_->nodeMask = s.weather == Weather::Snow ? ~sgfx::NodeMask{0} : 0;
    }
    applyShadows(s);
    sky_->nodeMask = s.sky ? ~sgfx::NodeMask{0} : 0;
    // The sky's sun is the sun light's, drawn or not: the sky environment follows it.
    sgfx::SkyParameters sky = sgfx::SkyParameters::atTime(s.skyHours);
    if (!s.sky) sky.sunDirection = -kSunDirection;
    sky_->setParameters(sky);
    sun_->direction = -sky.sunDirection;
    applyEnvironment(s);
    camera.clearColor = {0.72f, 0.76f, 0.82f, 1.0f};
}

void ViewScene::applyShadows(const Settings& s) {
    shadow_->enabled = s.shadows;
    if (!s.shadows) return;
    sgfx::ShadowOptions o = shadow_->options();
    const auto debug = s.shadowCascades ? sgfx::ShadowDebugView::Cascades : sgfx::ShadowDebugView::Off;
    const float distance = std::min(20.0f * radius_, 1e6f);
    if (o.filter == s.shadowFilter && o.debugView == debug && o.maxDistance == distance) return;
    o.filter = s.shadowFilter;
    o.debugView = debug;
    o.maxDistance = distance;
    shadow_->setOptions(o); // rebuilds the shader snippet: only on a change
}

void ViewScene::applyEnvironment(const Settings& s) {
    env_->enabled = s.env != EnvSource::None;
    // The environment replaces the flat ambient light (which would light everything twice).
    ambient_->color = glm::vec3(env_->enabled ? 0.0f : 0.35f);
    if (s.env == EnvSource::File && envLoaded_ != s.envFile) {
        env_->setEnvironment(sgfx::Environment::load(s.envFile)); // throws naming the file
        envLoaded_ = s.envFile;
    } else if (s.env == EnvSource::Sky) {
        env_->followSky(sky_);
        envLoaded_.clear();
    }
    env_->setIntensity(s.envIntensity);
}

std::string ViewScene::describeEffects(const Settings& s) const {
    std::ostringstream o;
    const char* sep = "";
    auto add = [&](const std::string& what) {
        o << sep << what;
        sep = ", ";
    };
    if (s.fog) add("fog");
    if (s.ao) add("AO");
    if (s.antiAliasing.mode != sgfx::AntiAliasing::Mode::None) add("AA");
    if (s.weather == Weather::Rain) add("rain");
    if (s.weather == Weather::Snow) add("snow");
    if (s.sky) add("sky");
    if (s.env == EnvSource::Sky) add("sky light");
    if (s.env == EnvSource::File) add("environment " + s.envFile);
    if (s.shadows) add(s.shadowFilter == sgfx::ShadowFilter::Hard2x2 ? "hard shadows" : "shadows");
    return o.str().empty() ? "no effects" : o.str();
}

std::string ViewScene::describePick(const std::optional<sgfx::PickResult>& pick, double x, double y) const {
    char head[64];
    std::snprintf(head, sizeof head, "pick %g,%g: ", x, y);
    if (!pick) return std::string(head) + "nothing";
    const sgfx::Intersection& hit = pick->hit;
    // The path starts below the viewer's effect nodes and the model's slot: the files' own nodes.
    const auto& path = hit.nodePath;
    auto first = path.begin();
    for (auto it = path.begin(); it != path.end(); ++it)
        if (*it == world_.get() || *it == modelSlot_.get()) first = it + 1;
    std::string text = head;
    for (auto it = first; it != path.end(); ++it)
        text += (it == first ? "" : " > ") + ((*it)->name.empty() ? "(" + typeName(**it) + ")" : (*it)->name);
    const glm::dvec3 eye(glm::inverse(glm::dmat4(pick->camera->viewMatrix))[3]);
    char tail[64];
    std::snprintf(tail, sizeof tail, ", %.3f m from the eye", glm::length(hit.point - eye));
    return text + "\n  point " + triple(hit.point) + tail + "\n  normal " + triple(hit.normal);
}

} // namespace view

#pragma once
// sgfx-view's scene: the user's model on a ground plane, under every effect the viewer can
// toggle. All effect nodes stay in the graph; switching one off clears its `enabled` flag or
// node mask, so toggling costs no rebuild and keeps the nodes' GPU targets.
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/environment/EnvironmentLightNode.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>
#include <sgfx/nodes/shadow/ShadowNode.h>
#include <sgfx/nodes/sky/SkyNode.h>

#include <sgfx/Camera.h>
#include <sgfx/Group.h>
#include <sgfx/Queries.h>

#include <optional>
#include <string>

namespace view {

enum class FogPreset : unsigned char { Model, Solid, Ground }; // Model: scaled to the model
enum class Weather : unsigned char { None, Rain, Snow };
// Image-based light: none, the sky's (whether or not the sky is drawn), or a panorama file.
enum class EnvSource : unsigned char { None, Sky, File };

struct Settings {
    bool fog = false;
    sgfx::FogMode fogMode = sgfx::FogMode::Forward;
    FogPreset fogPreset = FogPreset::Model;
    float fogDensity = 0.0f, fogFalloff = 0.0f; // ρ0 (1/m), b (1/m); 0: the preset's
    bool ao = false;
    int aoSamples = 32;
    float aoRadius = 0.0f; // metres; 0: a tenth of the model's size
    sgfx::AntiAliasing antiAliasing = sgfx::AntiAliasing::none();
    Weather weather = Weather::None;
    bool sky = false;
    float skyHours = 10.0f; // local solar time
    bool ground = true;
    EnvSource env = EnvSource::Sky; // metals need something to reflect
    std::string envFile;            // EnvSource::File: .hdr, .png or .jpg panorama (2:1)
    float envIntensity = 1.0f;
    bool shadows = false; // the sun's cascaded shadow maps, 20 model radii deep
    sgfx::ShadowFilter shadowFilter = sgfx::ShadowFilter::Pcf;
    bool shadowCascades = false; // tint each pixel by the cascade that shades it
};

class ViewScene {
public:
    ViewScene();
    // Replaces the model; the ground, the particle area and the model-scaled presets follow its
    // bounds. Throws std::runtime_error when it holds no geometry.
    void setModel(sgfx::NodePtr model);
    // Applies the settings (validated by the nodes: std::invalid_argument names the field; the
    // previous values stay).
    void apply(const Settings& s, sgfx::Camera& camera);

    const sgfx::NodePtr& root() const { return root_; }
    const sgfx::NodePtr& model() const { return model_; }
    glm::vec3 boundsMin() const { return min_; }
    glm::vec3 boundsMax() const { return max_; }
    float radius() const { return radius_; }
    // The fog and AO parameters the settings give for this model (the panel shows them).
    sgfx::FogParameters fogParameters(const Settings& s) const;
    sgfx::AmbientOcclusionParameters aoParameters(const Settings& s) const;
    std::string describeEffects(const Settings& s) const;
    // The image-based light of the settings (a file is loaded once; std::runtime_error names it).
    void applyEnvironment(const Settings& s);
    // The sun's shadows of the settings, 20 model radii of view depth deep.
    void applyShadows(const Settings& s);
    // What pixel (x, y) shows, for the panel and --pick: the node path below the viewer's own
    // nodes (each node's name, or its type when unnamed), then the world point and normal.
    std::string describePick(const std::optional<sgfx::PickResult>& pick, double x, double y) const;

private:
    sgfx::NodePtr root_, model_;
    std::shared_ptr<sgfx::Group> world_, modelSlot_;
    std::shared_ptr<sgfx::Transform> ground_, weatherPlace_;
    std::shared_ptr<sgfx::FogNode> fog_;
    std::shared_ptr<sgfx::AmbientOcclusionNode> ao_;
    std::shared_ptr<sgfx::SkyNode> sky_;
    std::shared_ptr<sgfx::EnvironmentLightNode> env_;
    std::string envLoaded_; // the file env_ holds, loaded once
    std::shared_ptr<sgfx::Light> ambient_;
    std::shared_ptr<sgfx::ParticleSystemNode> rain_, snow_;
    std::shared_ptr<sgfx::Light> sun_;
    std::shared_ptr<sgfx::ShadowNode> shadow_; // sun_'s, around world_
    glm::vec3 min_{-0.5f}, max_{0.5f};
    float radius_ = 1.0f;
};

} // namespace view

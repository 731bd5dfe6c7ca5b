#include "GltfLights.h"

#include <sgfx/GltfLoader.h>

#include <nlohmann/json.hpp>

#include <glm/gtc/constants.hpp>

#include <cmath>
#include <cstring>
#include <string_view>

namespace sgfx::gltf {

namespace {

using Json = nlohmann::json;

struct Checks {
    const std::string& path;
    [[noreturn]] void fail(const std::string& element, const std::string& why) const {
        throw LoadError("sgfx: glTF '" + path + "': " + element + ": " + why);
    }
    std::string shown(const Json& v) const {
        std::string text = v.dump(-1, ' ', true, Json::error_handler_t::replace);
        return text.size() > 40 ? text.substr(0, 37) + "..." : text;
    }
    // A finite number, `fallback` when absent.
    double number(const Json& object, const char* key, double fallback, const std::string& element) const {
        const auto it = object.find(key);
        if (it == object.end()) return fallback;
        if (!it->is_number() || !std::isfinite(it->get<double>()))
            fail(element + "." + key, shown(*it) + " is not a finite number");
        return it->get<double>();
    }
};

std::shared_ptr<Light> lightOf(const Checks& c, const Json& l, const std::string& element,
                               std::size_t index) {
    if (!l.is_object()) c.fail(element, "is not an object");
    const auto type = l.find("type");
    if (type == l.end()) c.fail(element + ".type", "is missing (directional, point or spot)");
    const std::string t = type->is_string() ? type->get<std::string>() : std::string();
    if (t != "directional" && t != "point" && t != "spot")
        c.fail(element + ".type", c.shown(*type) + " is not \"directional\", \"point\" or \"spot\"");
    auto light = Light::create(t == "directional" ? LightType::Directional
                               : t == "spot"      ? LightType::Spot
                                                  : LightType::Point);
    const auto name = l.find("name");
    light->name = name != l.end() && name->is_string()
                      ? name->get<std::string>()
                      : "KHR_lights_punctual.lights[" + std::to_string(index) + "]";
    if (const auto color = l.find("color"); color != l.end()) {
        if (!color->is_array() || color->size() != 3)
            c.fail(element + ".color", "must be an array of 3 numbers");
        for (std::size_t k = 0; k < 3; ++k) {
            const Json& v = (*color)[k];
            if (!v.is_number() || !(v.get<double>() >= 0.0 && v.get<double>() <= 1.0))
                c.fail(element + ".color[" + std::to_string(k) + "]", c.shown(v) + " is outside [0, 1]");
            light->color[int(k)] = v.get<float>();
        }
    }
    const double intensity = c.number(l, "intensity", 1.0, element);
    if (intensity < 0.0) c.fail(element + ".intensity", c.shown(l.at("intensity")) + " is negative");
    // Lux and candela to sgfx's irradiance over π (see Light).
    light->intensity = float(intensity / glm::pi<double>());
    if (light->type == LightType::Directional) return light; // range: not for directional lights
    light->falloff = LightFalloff::InverseSquare;
    if (l.contains("range")) {
        const double range = c.number(l, "range", 0.0, element);
        if (!(range > 0.0))
            c.fail(element + ".range", c.shown(l.at("range")) + " must be > 0 (omit it: unlimited)");
        light->range = float(range);
    }
    if (light->type != LightType::Spot) return light;
    const auto spot = l.find("spot");
    if (spot == l.end() || !spot->is_object())
        c.fail(element + ".spot", "a spot light needs a `spot` object");
    const double inner = c.number(*spot, "innerConeAngle", 0.0, element + ".spot");
    const double outer = c.number(*spot, "outerConeAngle", glm::quarter_pi<double>(), element + ".spot");
    if (!(inner >= 0.0 && inner < outer))
        c.fail(element + ".spot.innerConeAngle",
               std::to_string(inner) + " must be >= 0 and < outerConeAngle (" + std::to_string(outer) + ")");
    if (!(outer <= glm::half_pi<double>()))
        c.fail(element + ".spot.outerConeAngle", std::to_string(outer) + " must be <= pi/2");
    light->innerConeAngle = float(inner);
    light->outerConeAngle = float(outer);
    return light;
}

} // namespace

PunctualLights readPunctualLights(const unsigned char* text, std::size_t size, const std::string& path) {
    PunctualLights out;
    static constexpr std::string_view key = "KHR_lights_punctual";
    if (std::string_view(reinterpret_cast<const char*>(text), size).find(key) == std::string_view::npos)
        return out;
    const auto keep = [](int depth, Json::parse_event_t event, Json& parsed) {
        if (event != Json::parse_event_t::key || depth != 1) return true;
        const auto& k = parsed.get_ref<const std::string&>();
        return k == "extensions" || k == "nodes";
    };
    const Json doc = Json::parse(text, text + size, keep, false);
    if (!doc.is_object()) return out;
    const Checks c{path};
    const std::string root = "extensions.KHR_lights_punctual";
    if (const auto ext = doc.find("extensions"); ext != doc.end() && ext->is_object() && ext->contains(key)) {
        const Json& e = (*ext)[std::string(key)];
        if (!e.is_object()) c.fail(root, "is not an object");
        const auto lights = e.find("lights");
        if (lights == e.end() || !lights->is_array()) c.fail(root + ".lights", "is missing or not an array");
        for (std::size_t i = 0; i < lights->size(); ++i)
            out.lights.push_back(lightOf(c, (*lights)[i], root + ".lights[" + std::to_string(i) + "]", i));
    }
    const auto nodes = doc.find("nodes");
    if (nodes == doc.end() || !nodes->is_array()) return out;
    for (std::size_t i = 0; i < nodes->size(); ++i) {
        const Json& n = (*nodes)[i];
        if (!n.is_object() || !n.contains("extensions") || !n["extensions"].is_object() ||
            !n["extensions"].contains(key))
            continue;
        const std::string element = "nodes[" + std::to_string(i) + "].extensions.KHR_lights_punctual";
        const Json& e = n["extensions"][std::string(key)];
        if (!e.is_object() || !e.contains("light")) c.fail(element, "needs a `light` index");
        const Json& index = e["light"];
        if (!index.is_number_unsigned()) c.fail(element + ".light", c.shown(index) + " is not a light index");
        if (index.get<std::uint64_t>() >= out.lights.size())
            c.fail(element + ".light", "light " + c.shown(index) + " does not exist (" +
                                           std::to_string(out.lights.size()) + " lights in " + root + ")");
        out.nodeLight[i] = std::size_t(index.get<std::uint64_t>());
    }
    return out;
}

} // namespace sgfx::gltf

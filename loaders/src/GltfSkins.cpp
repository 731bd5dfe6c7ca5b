#include "GltfSkins.h"

#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtc/type_ptr.hpp>
#include <glm/gtx/matrix_decompose.hpp>

#include <cmath>
#include <map>
#include <stdexcept>

namespace sgfx::gltf {

namespace {

// The number of morph targets of node `index`'s mesh (0 without a mesh).
std::size_t morphTargetCount(const tinygltf::Model& model, int index) {
    const tinygltf::Node& n = model.nodes[std::size_t(index)];
    if (n.mesh < 0 || std::size_t(n.mesh) >= model.meshes.size()) return 0;
    std::size_t targets = 0;
    for (const auto& p : model.meshes[std::size_t(n.mesh)].primitives)
        targets = std::max(targets, p.targets.size());
    return targets;
}

Interpolation interpolationOf(const Context& c, const std::string& text, const std::string& element) {
    if (text == "LINEAR" || text.empty()) return Interpolation::Linear;
    if (text == "STEP") return Interpolation::Step;
    if (text == "CUBICSPLINE") return Interpolation::CubicSpline;
    c.fail(element + ".interpolation", "'" + text + "' is not LINEAR, STEP or CUBICSPLINE");
}

AnimationPath pathOf(const Context& c, const std::string& text, const std::string& element) {
    if (text == "translation") return AnimationPath::Translation;
    if (text == "rotation") return AnimationPath::Rotation;
    if (text == "scale") return AnimationPath::Scale;
    if (text == "weights") return AnimationPath::Weights;
    c.fail(element, "'" + text + "' is not translation, rotation, scale or weights");
}

// One sampler: key times from `input`, values from `output`, `components` floats per value.
AnimationSampler readSampler(const Context& c, const tinygltf::AnimationSampler& s,
                             const std::string& element, AnimationPath path, std::size_t components) {
    AnimationSampler out;
    out.interpolation = interpolationOf(c, s.interpolation, element);
    out.components = components;
    out.times = readAccessor(c, s.input, element + ".input", {TINYGLTF_TYPE_SCALAR});
    // Weights are SCALAR however many targets there are (glTF 2.0, Animations).
    const int type = path == AnimationPath::Rotation  ? TINYGLTF_TYPE_VEC4
                     : path == AnimationPath::Weights ? TINYGLTF_TYPE_SCALAR
                                                      : TINYGLTF_TYPE_VEC3;
    out.values = readAccessor(c, s.output, element + ".output", {type});
    try {
        out.validate();
    } catch (const std::invalid_argument& e) {
        // Times and counts name the input; values the output.
        const std::string what = e.what();
        c.fail(element + (what.find("value") != std::string::npos ? ".output" : ".input"), what);
    }
    return out;
}

} // namespace

void readSkinAttributes(const Context& c, const tinygltf::Primitive& p, const std::string& element,
                        std::size_t n, Geometry& g, std::size_t& unweighted) {
    auto read = [&](const char* key, std::vector<glm::u16vec4>* joints, std::vector<glm::vec4>* weights) {
        const auto it = p.attributes.find(key);
        if (it == p.attributes.end()) return false;
        std::size_t count = 0;
        const auto v =
            readAccessor(c, it->second, element + ".attributes." + key, {TINYGLTF_TYPE_VEC4}, &count);
        if (count != n)
            c.fail(element + ".attributes." + key,
                   std::to_string(count) + " values for " + std::to_string(n) + " positions");
        for (std::size_t i = 0; i < n; ++i) {
            const glm::vec4 x = glm::make_vec4(v.data() + 4 * i);
            if (joints) {
                for (int k = 0; k < 4; ++k)
                    if (!(x[k] >= 0.0f && x[k] < 65536.0f))
                        c.fail(element + ".attributes." + key, "joint index " + std::to_string(x[k]) +
                                                                   " at vertex " + std::to_string(i) +
                                                                   " is invalid");
                joints->push_back(glm::u16vec4(x));
            } else {
                if (!(glm::all(glm::greaterThanEqual(x, glm::vec4(0.0f))) &&
                      std::isfinite(x.x + x.y + x.z + x.w)))
                    c.fail(element + ".attributes." + key,
                           "weights at vertex " + std::to_string(i) + " are negative, NaN or infinite");
                weights->push_back(x);
            }
        }
        return true;
    };
    const bool set0 = read("JOINTS_0", &g.joints0, nullptr) + read("WEIGHTS_0", nullptr, &g.weights0) == 2;
    if (!set0 && (!g.joints0.empty() || !g.weights0.empty()))
        c.fail(element + ".attributes", "has one of JOINTS_0 and WEIGHTS_0 without the other");
    const bool set1 = read("JOINTS_1", &g.joints1, nullptr) + read("WEIGHTS_1", nullptr, &g.weights1) == 2;
    if (!set1 && (!g.joints1.empty() || !g.weights1.empty()))
        c.fail(element + ".attributes", "has one of JOINTS_1 and WEIGHTS_1 without the other");
    if (set1 && !set0) c.fail(element + ".attributes", "has JOINTS_1 without JOINTS_0");
    // glTF 2.0, Skins: the weights of a vertex sum to 1; exporters round, so they are normalised.
    for (std::size_t i = 0; i < g.weights0.size(); ++i) {
        glm::vec4& w0 = g.weights0[i];
        const float sum =
            w0.x + w0.y + w0.z + w0.w +
            (set1 ? g.weights1[i].x + g.weights1[i].y + g.weights1[i].z + g.weights1[i].w : 0.0f);
        if (!(sum > 0.0f)) {
            w0 = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
            ++unweighted;
            continue;
        }
        w0 /= sum;
        if (set1) g.weights1[i] /= sum;
    }
}

void readMorphTargets(const Context& c, const tinygltf::Primitive& p, const std::string& element,
                      std::size_t n, Geometry& g) {
    for (std::size_t t = 0; t < p.targets.size(); ++t) {
        MorphTarget target;
        for (const auto& [key, index] : p.targets[t]) {
            const std::string name = element + "." + at("targets", t) + "." + key;
            std::vector<glm::vec3>* into = key == "POSITION"  ? &target.positions
                                           : key == "NORMAL"  ? &target.normals
                                           : key == "TANGENT" ? &target.tangents
                                                              : nullptr;
            if (!into) continue; // TEXCOORD_n and COLOR_n targets: not applied (documented)
            std::size_t count = 0;
            const auto v = readAccessor(c, index, name, {TINYGLTF_TYPE_VEC3}, &count);
            if (count != n)
                c.fail(name,
                       std::to_string(count) + " displacements for " + std::to_string(n) + " positions");
            c.charge(n, sizeof(glm::vec3), name);
            for (std::size_t i = 0; i < n; ++i) {
                if (!std::isfinite(v[3 * i] + v[3 * i + 1] + v[3 * i + 2]))
                    c.fail(name, "displacement " + std::to_string(i) + " is NaN or infinite");
                into->emplace_back(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
            }
        }
        g.morphTargets.push_back(std::move(target));
    }
}

std::vector<std::shared_ptr<Skin>> readSkins(const Context& c, const NodeInstances& nodes,
                                             const std::shared_ptr<Node>& root) {
    std::vector<std::shared_ptr<Skin>> skins;
    for (std::size_t i = 0; i < c.model.skins.size(); ++i) {
        const tinygltf::Skin& s = c.model.skins[i];
        const std::string element = at("skins", i);
        auto skin = std::make_shared<Skin>();
        skin->name = s.name.empty() ? element : s.name;
        skin->root = root;
        if (s.joints.empty()) c.fail(element + ".joints", "is empty");
        for (std::size_t j = 0; j < s.joints.size(); ++j) {
            const int node = s.joints[j];
            if (node < 0 || std::size_t(node) >= c.model.nodes.size())
                c.fail(element + ".joints[" + std::to_string(j) + "]",
                       "node " + std::to_string(node) + " does not exist");
            const auto& made = nodes.transforms[std::size_t(node)];
            skin->joints.push_back(made.empty() ? std::weak_ptr<Transform>{} : made.front());
        }
        if (s.inverseBindMatrices >= 0) {
            std::size_t count = 0;
            const auto m = readAccessor(c, s.inverseBindMatrices, element + ".inverseBindMatrices",
                                        {TINYGLTF_TYPE_MAT4}, &count);
            if (count != s.joints.size())
                c.fail(element + ".inverseBindMatrices", std::to_string(count) + " matrices for " +
                                                             std::to_string(s.joints.size()) + " joints");
            for (std::size_t j = 0; j < count; ++j) {
                for (std::size_t k = 0; k < 16; ++k)
                    if (!std::isfinite(m[16 * j + k]))
                        c.fail(element + ".inverseBindMatrices",
                               "matrix " + std::to_string(j) + " has a NaN");
                skin->inverseBindMatrices.push_back(glm::make_mat4(m.data() + 16 * j));
            }
        } else {
            skin->inverseBindMatrices.assign(s.joints.size(), glm::mat4(1.0f));
        }
        skins.push_back(std::move(skin));
    }
    return skins;
}

void readAnimations(const Context& c, const NodeInstances& nodes, AnimationPlayer& player) {
    std::map<int, std::vector<std::size_t>> targetsOf; // node → its targets (one per use)
    auto targets = [&](int node) -> const std::vector<std::size_t>& {
        auto [it, added] = targetsOf.try_emplace(node);
        if (!added) return it->second;
        const tinygltf::Node& n = c.model.nodes[std::size_t(node)];
        const auto& uses = nodes.transforms[std::size_t(node)];
        c.charge(uses.size(), sizeof(AnimationTarget) + 64, at("nodes", std::size_t(node)));
        for (std::size_t u = 0; u < uses.size(); ++u) {
            AnimationTarget t;
            t.transform = uses[u];
            t.name = n.name.empty() ? at("nodes", std::size_t(node)) : n.name;
            if (n.matrix.size() == 16) { // a matrix node: its rest pose as T·R·S (no shear in glTF)
                glm::vec3 skew;
                glm::vec4 perspective;
                const bool ok = glm::decompose(glm::mat4(glm::make_mat4(n.matrix.data())), t.scale,
                                               t.rotation, t.translation, skew, perspective);
                const glm::vec4 q(t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w);
                if (!ok || !std::isfinite(glm::dot(q, q) + glm::dot(t.scale, t.translation)))
                    c.fail(
                        at("nodes", std::size_t(node)) + ".matrix",
                        "is animated but is not a translation, rotation and scale (glTF 2.0 asks for TRS)");
            }
            if (n.translation.size() == 3)
                t.translation = glm::vec3(n.translation[0], n.translation[1], n.translation[2]);
            if (n.rotation.size() == 4)
                t.rotation = glm::quat(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]),
                                       float(n.rotation[2]));
            if (n.scale.size() == 3) t.scale = glm::vec3(n.scale[0], n.scale[1], n.scale[2]);
            for (const auto& g : nodes.geometry[std::size_t(node)][u]) {
                t.morphs.push_back(g);
                if (t.weights.empty()) t.weights = g->morphWeights();
            }
            it->second.push_back(player.targets.size());
            player.targets.push_back(std::move(t));
        }
        return it->second;
    };
    for (std::size_t a = 0; a < c.model.animations.size(); ++a) {
        const tinygltf::Animation& anim = c.model.animations[a];
        const std::string element = at("animations", a);
        Animation out;
        out.name = anim.name.empty() ? element : anim.name;
        // Each sampler is read for the path of the first channel that uses it (its value type).
        std::vector<int> samplerPath(anim.samplers.size(), -1);
        std::vector<std::size_t> samplerComponents(anim.samplers.size(), 0);
        for (std::size_t k = 0; k < anim.channels.size(); ++k) {
            const tinygltf::AnimationChannel& ch = anim.channels[k];
            const std::string name = element + "." + at("channels", k);
            if (ch.sampler < 0 || std::size_t(ch.sampler) >= anim.samplers.size())
                c.fail(name + ".sampler", "sampler " + std::to_string(ch.sampler) + " does not exist (" +
                                              std::to_string(anim.samplers.size()) + " samplers)");
            if (ch.target_node < 0) continue; // glTF: a channel without a node is ignored
            if (std::size_t(ch.target_node) >= c.model.nodes.size())
                c.fail(name + ".target.node", "node " + std::to_string(ch.target_node) + " does not exist (" +
                                                  std::to_string(c.model.nodes.size()) + " nodes)");
            const AnimationPath path = pathOf(c, ch.target_path, name + ".target.path");
            const std::size_t components = path == AnimationPath::Rotation ? 4
                                           : path == AnimationPath::Weights
                                               ? morphTargetCount(c.model, ch.target_node)
                                               : 3;
            if (components == 0)
                c.fail(name + ".target", "animates the weights of node " + std::to_string(ch.target_node) +
                                             ", whose mesh has no morph targets");
            const std::size_t s = std::size_t(ch.sampler);
            // Translation and scale share vec3 values; rotation and weights have their own.
            const auto kind = [](int pth) {
                return pth == int(AnimationPath::Scale) ? int(AnimationPath::Translation) : pth;
            };
            if (samplerPath[s] >= 0 &&
                (kind(samplerPath[s]) != kind(int(path)) || samplerComponents[s] != components))
                c.fail(name + ".sampler",
                       "sampler " + std::to_string(s) + " is shared by channels of different value types");
            samplerPath[s] = int(path);
            samplerComponents[s] = components;
            const auto& uses = targets(ch.target_node);
            c.charge(uses.size(), sizeof(AnimationChannel), name);
            for (std::size_t target : uses)
                out.channels.push_back({s, target, path});
        }
        for (std::size_t s = 0; s < anim.samplers.size(); ++s) {
            const std::string name = element + "." + at("samplers", s);
            // A sampler no channel uses is not read (its value type is unknown).
            out.samplers.push_back(samplerComponents[s]
                                       ? readSampler(c, anim.samplers[s], name, AnimationPath(samplerPath[s]),
                                                     samplerComponents[s])
                                       : AnimationSampler{});
        }
        player.animations.push_back(std::move(out));
    }
}

} // namespace sgfx::gltf

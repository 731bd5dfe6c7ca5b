#pragma once
// A small valid glTF document with a skin, a morph target and an animation (translation, rotation
// and weights channels), its data in one base64 data: URI; and edits that break one element each,
// with the element the loader's error must name. Shared by gltf_animation_test.cpp and the
// bad-input sweep of reliability_test.cpp.
#include "TestUtil.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace sgfx::test {

/// One accessor's data: raw little-endian bytes, component type, count and type as glTF spells them.
struct AnimBlob {
    std::vector<unsigned char> bytes;
    int componentType = 5126;
    std::size_t count = 0;
    const char* type = "SCALAR";
};

inline AnimBlob animFloats(const std::vector<float>& v, std::size_t count, const char* type) {
    AnimBlob b{std::vector<unsigned char>(v.size() * sizeof(float)), 5126, count, type};
    std::memcpy(b.bytes.data(), v.data(), b.bytes.size());
    return b;
}

inline AnimBlob animJoints(const std::vector<std::uint16_t>& v) {
    AnimBlob b{std::vector<unsigned char>(v.size() * 2), 5123, v.size() / 4, "VEC4"};
    std::memcpy(b.bytes.data(), v.data(), b.bytes.size());
    return b;
}

/// The document's accessors; the comment gives each index.
inline std::vector<AnimBlob> animBlobs() {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<float> identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    std::vector<float> ibm = identity;
    ibm.insert(ibm.end(), identity.begin(), identity.end());
    return {
        animFloats({0, 0, 0, 1, 0, 0, 0, 1, 0}, 3, "VEC3"),                      // 0 POSITION
        animFloats({0, 1}, 2, "SCALAR"),                                         // 1 key times
        animFloats({0, 0, 0, 1, 2, 3}, 2, "VEC3"),                               // 2 translations
        animFloats({0, 0, 0, 1, 0, 0, 0.70710678f, 0.70710678f}, 2, "VEC4"),     // 3 rotations
        animFloats({0, 1}, 2, "SCALAR"),                                         // 4 morph weights
        animJoints({0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0}),                        // 5 JOINTS_0
        animFloats({.5f, .5f, 0, 0, .5f, .5f, 0, 0, .5f, .5f, 0, 0}, 3, "VEC4"), // 6 WEIGHTS_0
        animFloats(ibm, 2, "MAT4"),                                              // 7 inverse bind matrices
        animFloats({0, 0, 1, 0, 0, 1, 0, 0, 1}, 3, "VEC3"),                      // 8 morph target POSITION
        animFloats({1, 0.5f}, 2, "SCALAR"),                                      // 9 times decreasing
        animFloats({0, nan}, 2, "SCALAR"),                                       // 10 a NaN time
        animFloats({0, 0, 0, nan, 0, 0}, 2, "VEC3"),                             // 11 a NaN translation
        animJoints({0, 5, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0}),                        // 12 joint 5 of 2
        animFloats({0, 0, 1, 0, 0, 1}, 2, "VEC3"),                               // 13 2 displacements
        animFloats({0, 0, 0, 1, 0.5f, 0.25f}, 6, "SCALAR"),                      // 14 weights of 3 targets
    };
}

/// The valid document, with `from` replaced by `to` (once; `from` must occur).
inline std::string animDocument(const std::string& from = {}, const std::string& to = {}) {
    std::vector<unsigned char> data;
    std::string views, accessors;
    const std::vector<AnimBlob> blobs = animBlobs();
    for (std::size_t index = 0; index < blobs.size(); ++index) {
        const AnimBlob& b = blobs[index];
        const std::size_t offset = data.size();
        data.insert(data.end(), b.bytes.begin(), b.bytes.end());
        while (data.size() % 4)
            data.push_back(0);
        views += std::string(views.empty() ? "" : ",") + R"({"buffer":0,"byteOffset":)" +
                 std::to_string(offset) + R"(,"byteLength":)" + std::to_string(b.bytes.size()) + "}";
        accessors += std::string(accessors.empty() ? "" : ",") + R"({"bufferView":)" + std::to_string(index) +
                     R"(,"componentType":)" + std::to_string(b.componentType) + R"(,"count":)" +
                     std::to_string(b.count) + R"(,"type":")" + b.type + "\"}";
    }
    std::string json =
        R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1,3,4]}],)"
        R"("nodes":[{"name":"skinned","mesh":0,"skin":0},{"name":"joint0","children":[2],"translation":[0,1,0]},)"
        R"({"name":"joint1","translation":[0,1,0]},{"name":"morphed","mesh":1},{"name":"plain","mesh":2}],)"
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"JOINTS_0":5,"WEIGHTS_0":6}}]},)"
        R"({"weights":[0.25],"primitives":[{"attributes":{"POSITION":0},"targets":[{"POSITION":8}]}]},)"
        R"({"primitives":[{"attributes":{"POSITION":0}}]}],)"
        R"("skins":[{"joints":[1,2],"inverseBindMatrices":7}],)"
        R"("animations":[{"channels":[{"sampler":0,"target":{"node":1,"path":"translation"}},)"
        R"({"sampler":1,"target":{"node":2,"path":"rotation"}},{"sampler":2,"target":{"node":3,"path":"weights"}}],)"
        R"("samplers":[{"input":1,"output":2,"interpolation":"LINEAR"},{"input":1,"output":3},{"input":1,"output":4}]}],)"
        R"("buffers":[{"byteLength":)" +
        std::to_string(data.size()) + R"(,"uri":"data:application/octet-stream;base64,)" + base64(data) +
        R"("}],"bufferViews":[)" + views + R"(],"accessors":[)" + accessors + "]}";
    if (!from.empty()) {
        const auto at = json.find(from);
        if (at == std::string::npos)
            ADD_FAILURE() << "the document has no '" << from << "'";
        else
            json.replace(at, from.size(), to);
    }
    return json;
}

/// One broken element: the edit, and what the error must contain (the element and the reason).
struct AnimBreak {
    const char* label;
    const char* from;
    const char* to;
    const char* element;
    const char* reason;
};

inline const std::vector<AnimBreak>& animBreaks() {
    static const std::vector<AnimBreak> breaks{
        {"times_not_increasing", R"("input":1,"output":2,)", R"("input":9,"output":2,)",
         "animations[0].samplers[0].input", "not increasing"},
        {"nan_time", R"("input":1,"output":2,)", R"("input":10,"output":2,)",
         "animations[0].samplers[0].input", "NaN"},
        {"linear_count", R"("input":1,"output":2,)", R"("input":1,"output":0,)",
         "animations[0].samplers[0].output", "9 values for 2 keys of 3 components (6 expected)"},
        {"cubic_count", R"("LINEAR")", R"("CUBICSPLINE")", "animations[0].samplers[0].output",
         "6 values for 2 keys of 3 components (18 expected"},
        {"nan_value", R"("input":1,"output":2,)", R"("input":1,"output":11,)",
         "animations[0].samplers[0].output", "NaN"},
        {"missing_node", R"("target":{"node":1,)", R"("target":{"node":42,)",
         "animations[0].channels[0].target.node", "does not exist"},
        {"missing_sampler", R"({"sampler":0,)", R"({"sampler":7,)", "animations[0].channels[0].sampler",
         "does not exist"},
        {"bad_path", R"("path":"translation")", R"("path":"position")",
         "animations[0].channels[0].target.path", "'position' is not"},
        {"bad_interpolation", R"("LINEAR")", R"("SMOOTH")", "animations[0].samplers[0].interpolation",
         "'SMOOTH' is not"},
        {"weights_without_targets", R"({"node":3,"path":"weights"})", R"({"node":4,"path":"weights"})",
         "animations[0].channels[2].target", "no morph targets"},
        {"ibm_count", R"("joints":[1,2])", R"("joints":[1,2,4])", "skins[0].inverseBindMatrices",
         "2 matrices for 3 joints"},
        {"missing_joint", R"("joints":[1,2])", R"("joints":[1,42])", "skins[0].joints[1]", "does not exist"},
        {"skin_without_joints", R"({"name":"skinned","mesh":0,)", R"({"name":"skinned","mesh":2,)",
         "nodes[0].skin", "no JOINTS_0"},
        {"joints_without_weights", R"(,"WEIGHTS_0":6)", "", "meshes[0].primitives[0].attributes",
         "JOINTS_0 and WEIGHTS_0 without the other"},
        {"joint_beyond_skin", R"("JOINTS_0":5)", R"("JOINTS_0":12)", "joints0[0]",
         "names joint 5 of a skin with 2"},
        {"mesh_weights_count", R"("weights":[0.25])", R"("weights":[0.25,0.5])", "meshes[1].weights",
         "2 weights for 1 targets"},
        {"morph_target_count", R"("targets":[{"POSITION":8}])", R"("targets":[{"POSITION":13}])",
         "meshes[1].primitives[0].targets[0].POSITION", "2 displacements for 3 positions"},
    };
    return breaks;
}

} // namespace sgfx::test

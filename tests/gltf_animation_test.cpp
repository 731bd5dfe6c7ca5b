// glTF animations, skins and morph targets through the loader (issue 26): each broken element of a
// small document is refused naming it; the shared set A2 (../shared/assets/gltf/README.md) loads
// with the README's counts; animated transforms and morph weights match the file's keyframes
// sampled here by an independent linear scan; a skinned geometry's bound holds its posed vertices.
#include "GltfAnimDoc.h"
#include "TestUtil.h"

#include <sgfx/Animation.h>
#include <sgfx/FindNode.h>
#include <sgfx/Geometry.h>
#include <sgfx/GltfLoader.h>
#include <sgfx/Group.h>
#include <sgfx/Visitors.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <span>

using namespace sgfx;
using namespace sgfx::test;

namespace {

const std::filesystem::path kAssets =
    std::filesystem::path(SGFX_SOURCE_DIR) / ".." / "shared" / "assets" / "gltf";

std::shared_ptr<Group> loadText(const std::string& json, const std::string& name,
                                GltfStats* stats = nullptr) {
    return loadGltfFromMemory(std::as_bytes(std::span(json.data(), json.size())), name, {}, stats);
}

// ------------------------------------------------------------ the file read here, not by sgfx

tinygltf::Model readModel(const std::filesystem::path& file) {
    tinygltf::TinyGLTF reader;
    tinygltf::Model model;
    std::string err, warn;
    if (!reader.LoadASCIIFromFile(&model, &err, &warn, file.string()))
        ADD_FAILURE() << "tinygltf cannot read " << file << ": " << err;
    return model;
}

// A float accessor's values (count × components), honouring the view's stride.
std::vector<double> floatsOf(const tinygltf::Model& m, int index) {
    const tinygltf::Accessor& a = m.accessors.at(std::size_t(index));
    const tinygltf::BufferView& v = m.bufferViews.at(std::size_t(a.bufferView));
    const std::vector<unsigned char>& data = m.buffers.at(std::size_t(v.buffer)).data;
    EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT) << "accessor " << index;
    const std::size_t n = std::size_t(tinygltf::GetNumComponentsInType(std::uint32_t(a.type)));
    const std::size_t stride = v.byteStride ? v.byteStride : n * 4;
    std::vector<double> out;
    for (std::size_t i = 0; i < a.count; ++i)
        for (std::size_t c = 0; c < n; ++c) {
            float f = 0.0f;
            std::memcpy(&f, data.data() + v.byteOffset + a.byteOffset + i * stride + c * 4, 4);
            out.push_back(f);
        }
    return out;
}

struct RefSampler {
    std::vector<double> times, values;
    std::size_t n = 0; // components
    std::string interpolation;
};

RefSampler refSampler(const tinygltf::Model& m, const tinygltf::AnimationSampler& s) {
    RefSampler r{floatsOf(m, s.input), floatsOf(m, s.output), 0, s.interpolation};
    r.n = r.values.size() / r.times.size();
    return r;
}

// The spec's slerp (glTF 2.0 Appendix C), shortest path, written out.
std::vector<double> slerp(const double* a, const double* b, double s) {
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    const double sign = d < 0 ? -1.0 : 1.0;
    d *= sign;
    double wa = 1.0 - s, wb = s;
    if (d < 0.9999) {
        const double theta = std::acos(d);
        wa = std::sin((1.0 - s) * theta) / std::sin(theta);
        wb = std::sin(s * theta) / std::sin(theta);
    }
    std::vector<double> q(4);
    double len = 0;
    for (int i = 0; i < 4; ++i) {
        q[std::size_t(i)] = wa * a[i] + wb * sign * b[i];
        len += q[std::size_t(i)] * q[std::size_t(i)];
    }
    for (double& x : q)
        x /= std::sqrt(len);
    return q;
}

// The sampler's value at t: a linear scan for the key interval, lerp or slerp; clamped outside.
std::vector<double> sampleAt(const RefSampler& r, double t, bool rotation) {
    EXPECT_TRUE(r.interpolation == "LINEAR" || r.interpolation.empty()) << r.interpolation;
    const double* v = r.values.data();
    const std::size_t keys = r.times.size();
    if (t <= r.times.front()) return {v, v + r.n};
    if (t >= r.times.back()) return {v + (keys - 1) * r.n, v + keys * r.n};
    std::size_t k = 0;
    while (!(r.times[k] <= t && t < r.times[k + 1]))
        ++k;
    const double s = (t - r.times[k]) / (r.times[k + 1] - r.times[k]);
    if (rotation) return slerp(v + k * 4, v + (k + 1) * 4, s);
    std::vector<double> out(r.n);
    for (std::size_t i = 0; i < r.n; ++i)
        out[i] = v[k * r.n + i] * (1.0 - s) + v[(k + 1) * r.n + i] * s;
    return out;
}

// The last key time over every sampler of animation 0 (what the animation's time wraps at).
double durationOf(const tinygltf::Model& m) {
    double d = 0;
    for (const auto& s : m.animations.at(0).samplers)
        d = std::max(d, floatsOf(m, s.input).back());
    return d;
}

// Node `index`'s T·R·S at animation time t (its rest values where no channel of animation 0 drives).
glm::dmat4 nodeMatrixAt(const tinygltf::Model& m, int index, double t) {
    const tinygltf::Node& n = m.nodes.at(std::size_t(index));
    std::vector<double> tr = n.translation.size() == 3 ? n.translation : std::vector<double>{0, 0, 0};
    std::vector<double> rot = n.rotation.size() == 4 ? n.rotation : std::vector<double>{0, 0, 0, 1};
    std::vector<double> sc = n.scale.size() == 3 ? n.scale : std::vector<double>{1, 1, 1};
    const auto& anim = m.animations.at(0);
    for (const auto& ch : anim.channels) {
        if (ch.target_node != index) continue;
        const RefSampler r = refSampler(m, anim.samplers.at(std::size_t(ch.sampler)));
        const std::vector<double> value = sampleAt(r, t, ch.target_path == "rotation");
        (ch.target_path == "translation" ? tr : ch.target_path == "rotation" ? rot : sc) = value;
    }
    const glm::dquat q(rot[3], rot[0], rot[1], rot[2]);
    return glm::translate(glm::dmat4(1.0), glm::dvec3(tr[0], tr[1], tr[2])) * glm::mat4_cast(q) *
           glm::scale(glm::dmat4(1.0), glm::dvec3(sc[0], sc[1], sc[2]));
}

// Runs the update traversal at simulation time t, as Viewer::update does.
void updateAt(Node& root, double t) {
    UpdateVisitor visitor;
    visitor.simulationTime = t;
    root.accept(visitor);
    visitor.updatePoses();
}

std::string nodeName(const tinygltf::Model& m, int index) {
    const std::string& n = m.nodes.at(std::size_t(index)).name;
    return n.empty() ? "nodes[" + std::to_string(index) + "]" : n;
}

std::vector<std::shared_ptr<Geometry>> geometriesOf(Node& root) {
    std::vector<std::shared_ptr<Geometry>> out;
    for (const auto& n : findNodesIf(root, [](Node& x) { return dynamic_cast<Geometry*>(&x) != nullptr; }))
        out.push_back(std::static_pointer_cast<Geometry>(n));
    return out;
}

// World matrix of a node: its own matrix (a Transform's) times every ancestor's, up the first parents.
glm::dmat4 worldOf(const Node& node) {
    glm::dmat4 m(1.0);
    for (const Node* n = &node; n; n = n->parents().empty() ? nullptr : n->parents().front()) {
        if (const auto* t = dynamic_cast<const Transform*>(n)) m = glm::dmat4(t->matrix()) * m;
    }
    return m;
}

} // namespace

// ------------------------------------------------------------------------ broken elements

TEST(GltfAnimation, TheValidDocumentLoadsAnimatedSkinnedAndMorphed) {
    GltfStats st;
    const auto root = loadText(animDocument(), "anim.gltf", &st);
    EXPECT_EQ(st.animations, 1u);
    EXPECT_EQ(st.skins, 1u);
    ASSERT_NE(animationPlayer(*root), nullptr);
    const auto morphed = findNode<Transform>(*root, "morphed");
    ASSERT_TRUE(morphed);
    // The weights channel drives 0 → 1 over a second: at 0.5 the weight is 0.5.
    updateAt(*root, 0.5);
    const auto g = std::dynamic_pointer_cast<Geometry>(morphed->child(0));
    ASSERT_TRUE(g);
    ASSERT_EQ(g->morphWeights().size(), 1u);
    EXPECT_NEAR(g->morphWeights()[0], 0.5f, 1e-6f);
}

// glTF weights outputs are SCALAR whatever the number of targets: three targets read six values.
TEST(GltfAnimation, WeightsOfThreeTargetsAreScalarOutputs) {
    std::string doc = animDocument(R"("targets":[{"POSITION":8}])",
                                   R"("targets":[{"POSITION":8},{"POSITION":8},{"POSITION":8}])");
    for (const auto& [from, to] :
         {std::pair<std::string, std::string>{R"("weights":[0.25])", R"("weights":[0.25,0,0])"},
          {R"({"input":1,"output":4})", R"({"input":1,"output":14})"}}) {
        const auto at = doc.find(from);
        ASSERT_NE(at, std::string::npos) << from;
        doc.replace(at, from.size(), to);
    }
    const auto root = loadText(doc, "three-targets.gltf", nullptr);
    updateAt(*root, 0.5); // halfway from (0, 0, 0) to (1, 0.5, 0.25)
    const auto g = std::dynamic_pointer_cast<Geometry>(findNode<Transform>(*root, "morphed")->child(0));
    ASSERT_TRUE(g);
    ASSERT_EQ(g->morphWeights().size(), 3u);
    EXPECT_NEAR(g->morphWeights()[0], 0.5f, 1e-6f);
    EXPECT_NEAR(g->morphWeights()[1], 0.25f, 1e-6f);
    EXPECT_NEAR(g->morphWeights()[2], 0.125f, 1e-6f);
}

// A mesh used by a skinned node and by a plain node (listed after it): only the skinned use is posed.
TEST(GltfAnimation, AnUnskinnedUseOfASkinnedMeshStaysUnposed) {
    const auto root = loadText(animDocument(R"({"name":"plain","mesh":2})", R"({"name":"plain","mesh":0})"),
                               "shared-mesh.gltf", nullptr);
    const auto skinned = std::dynamic_pointer_cast<Geometry>(findNode<Transform>(*root, "skinned")->child(0));
    const auto plain = std::dynamic_pointer_cast<Geometry>(findNode<Transform>(*root, "plain")->child(0));
    ASSERT_TRUE(skinned && plain);
    EXPECT_TRUE(skinned->skin);
    EXPECT_FALSE(plain->skin);
    EXPECT_NE(skinned.get(), plain.get());
}

TEST(GltfAnimation, EachBrokenElementIsRefusedNamingIt) {
    for (const AnimBreak& b : animBreaks()) {
        SCOPED_TRACE(b.label);
        const std::string json = animDocument(b.from, b.to);
        std::ofstream(std::filesystem::temp_directory_path() /
                      (std::string("sgfx_anim_") + b.label + ".gltf"))
            << json;
        try {
            (void)loadText(json, std::string("broken_") + b.label + ".gltf");
            ADD_FAILURE() << "loaded";
        } catch (const LoadError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(b.element), std::string::npos)
                << "does not name " << b.element << ": " << what;
            EXPECT_NE(what.find(b.reason), std::string::npos)
                << "does not say '" << b.reason << "': " << what;
            EXPECT_NE(what.find(std::string("broken_") + b.label), std::string::npos) << what;
        }
    }
}

// ------------------------------------------------------------------------ the shared set A2

TEST(GltfAnimation, SharedSetA2LoadsWithTheReadmesCounts) {
    // Copied from the set A2 table of ../shared/assets/gltf/README.md (triangles, animations,
    // skins, morph targets). "Morph targets" there is the sum over a mesh's primitives
    // (MorphPrimitivesTest: two primitives of one target each; SimpleMorph: one of two).
    struct Row {
        const char* model;
        std::size_t triangles, animations, skins, morphTargets;
    };
    const Row rows[] = {
        {"AnimatedCube", 12, 1, 0, 0},        {"BoxAnimated", 254, 1, 0, 0},
        {"RiggedSimple", 188, 1, 1, 0},       {"RiggedFigure", 256, 1, 1, 0},
        {"SimpleSkin", 8, 1, 1, 0},           {"AnimatedMorphCube", 12, 1, 0, 2},
        {"SimpleMorph", 1, 1, 0, 2},          {"AnimatedTriangle", 1, 1, 0, 0},
        {"MorphPrimitivesTest", 32, 0, 0, 2},
    };
    for (const Row& r : rows) {
        SCOPED_TRACE(r.model);
        const auto file = kAssets / r.model / "glTF" / (std::string(r.model) + ".gltf");
        SGFX_REQUIRE(std::filesystem::exists(file), "the shared asset " << file);
        GltfStats st;
        const auto root = loadGltf(file, {}, &st);
        EXPECT_EQ(st.triangles, r.triangles);
        EXPECT_EQ(st.animations, r.animations);
        EXPECT_EQ(st.skins, r.skins);
        std::size_t targets = 0;
        for (const auto& g : geometriesOf(*root))
            targets += g->morphTargets.size();
        EXPECT_EQ(targets, r.morphTargets);
        // A file with animations plays its first one.
        AnimationPlayer* player = animationPlayer(*root);
        EXPECT_EQ(player != nullptr, r.animations > 0);
        if (player) {
            EXPECT_EQ(player->current(), 0);
        }
    }
}

// ------------------------------------------------------------------------ poses against the file

namespace {

// Every node animation 0 moves: its Transform's matrix after updating to t equals the file's T·R·S
// at the animation time t maps to (looped, or clamped into [0, duration]).
void expectNodesFollowTheFile(const char* model) {
    SCOPED_TRACE(model);
    const auto file = kAssets / model / "glTF" / (std::string(model) + ".gltf");
    SGFX_REQUIRE(std::filesystem::exists(file), "the shared asset " << file);
    const tinygltf::Model m = readModel(file);
    ASSERT_FALSE(m.animations.empty());
    const auto root = loadGltf(file);
    AnimationPlayer* player = animationPlayer(*root);
    ASSERT_NE(player, nullptr);
    const double d = durationOf(m);
    std::set<int> animated;
    for (const auto& ch : m.animations[0].channels)
        animated.insert(ch.target_node);
    for (const bool loop : {true, false}) {
        // Each pass from simulation time 0: the animation's time is the simulation time.
        updateAt(*root, 0.0);
        player->play(0);
        player->setWrap(loop ? AnimationPlayer::Wrap::Loop : AnimationPlayer::Wrap::Clamp);
        // 20 times from before the start to past the end.
        for (int i = 0; i < 20; ++i) {
            const double t = -0.2 * d + 1.5 * d * i / 19.0;
            double at = std::clamp(t, 0.0, d);
            if (loop) at = t - d * std::floor(t / d);
            updateAt(*root, t);
            for (int node : animated) {
                SCOPED_TRACE(nodeName(m, node) + " at t=" + std::to_string(t) +
                             (loop ? " (loop)" : " (clamp)"));
                const auto xf = findNode<Transform>(*root, nodeName(m, node));
                ASSERT_TRUE(xf);
                const glm::dmat4 expected = nodeMatrixAt(m, node, at);
                const glm::dmat4 got(xf->matrix());
                for (int c = 0; c < 4; ++c)
                    for (int r = 0; r < 4; ++r)
                        EXPECT_NEAR(got[c][r], expected[c][r], 1e-4 * std::max(1.0, std::abs(expected[c][r])))
                            << "column " << c << " row " << r;
            }
        }
    }
}

} // namespace

TEST(GltfAnimation, AnimatedTriangleRotationFollowsTheFile) {
    expectNodesFollowTheFile("AnimatedTriangle");
}

TEST(GltfAnimation, BoxAnimatedTranslationAndRotationFollowTheFile) {
    // Its rotation keys run 1.25..2.5 s of a 3.71 s animation: times before the first key and after
    // the last come up within the loop.
    expectNodesFollowTheFile("BoxAnimated");
}

TEST(GltfAnimation, MorphWeightsFollowTheFile) {
    for (const char* model : {"AnimatedMorphCube", "SimpleMorph"}) {
        SCOPED_TRACE(model);
        const auto file = kAssets / model / "glTF" / (std::string(model) + ".gltf");
        SGFX_REQUIRE(std::filesystem::exists(file), "the shared asset " << file);
        const tinygltf::Model m = readModel(file);
        const auto root = loadGltf(file);
        const auto& ch = m.animations.at(0).channels.at(0);
        ASSERT_EQ(ch.target_path, "weights");
        const RefSampler r = refSampler(m, m.animations[0].samplers.at(std::size_t(ch.sampler)));
        const std::size_t targets = m.meshes.at(std::size_t(m.nodes.at(std::size_t(ch.target_node)).mesh))
                                        .primitives.at(0)
                                        .targets.size();
        ASSERT_EQ(r.values.size(), r.times.size() * targets) << "one weight per target per key";
        const auto node = findNode<Transform>(*root, nodeName(m, ch.target_node));
        ASSERT_TRUE(node);
        const auto geometries = geometriesOf(*node);
        ASSERT_FALSE(geometries.empty());
        const double d = durationOf(m);
        for (int i = 0; i < 20; ++i) {
            const double t = d * i / 20.0 + 0.013; // within [0, d): no wrap
            updateAt(*root, t);
            const std::vector<double> expected = sampleAt(r, t, false);
            for (const auto& g : geometries) {
                SCOPED_TRACE(g->name + " at t=" + std::to_string(t));
                ASSERT_EQ(g->morphWeights().size(), targets);
                for (std::size_t k = 0; k < targets; ++k)
                    EXPECT_NEAR(g->morphWeights()[k], expected[k], 1e-5) << "weight " << k;
            }
        }
    }
}

TEST(GltfAnimation, MeshDefaultWeightsReachEveryPrimitive) {
    const auto file = kAssets / "MorphPrimitivesTest/glTF/MorphPrimitivesTest.gltf";
    SGFX_REQUIRE(std::filesystem::exists(file), "the shared asset " << file);
    const tinygltf::Model m = readModel(file);
    ASSERT_EQ(m.meshes.size(), 1u);
    const std::vector<double>& weights = m.meshes[0].weights;
    ASSERT_FALSE(weights.empty());
    const auto root = loadGltf(file);
    const auto geometries = geometriesOf(*root);
    ASSERT_EQ(geometries.size(), m.meshes[0].primitives.size());
    for (const auto& g : geometries) {
        SCOPED_TRACE(g->name);
        ASSERT_EQ(g->morphWeights().size(), weights.size());
        for (std::size_t k = 0; k < weights.size(); ++k)
            EXPECT_NEAR(g->morphWeights()[k], weights[k], 1e-6);
    }
}

// ------------------------------------------------------------------------ bounds follow the pose

namespace {

struct Outside {
    std::size_t bindSphere = 0, bindBox = 0; // posed vertices outside the bind pose's sphere, box
};

// At 11 times over animation 0, the skinned geometry's bound holds every vertex skinned here on
// the CPU, with joint matrices from the joints' world matrices and the file's inverse bind matrices.
Outside expectBoundHoldsSkinnedVertices(const tinygltf::Model& m, Node& root) {
    Outside out;
    if (m.skins.size() != 1) {
        ADD_FAILURE() << "one skin expected";
        return out;
    }
    const std::vector<double> ibm = floatsOf(m, m.skins[0].inverseBindMatrices);
    std::shared_ptr<Geometry> g;
    for (const auto& x : geometriesOf(root))
        if (x->skin) g = x;
    if (!g || g->parents().size() != 1) {
        ADD_FAILURE() << "no skinned geometry with one parent";
        return out;
    }
    // The bind-pose bound: the same vertices, unposed.
    auto bind = Geometry::create();
    bind->positions = g->positions;
    const BoundingSphere bindSphere = bind->bound();
    BoundingBox bindBox;
    for (const auto& p : g->positions)
        bindBox.expandBy(p);
    auto inside = [](const BoundingSphere& s, const glm::dvec3& p) {
        return glm::length(p - glm::dvec3(s.center)) <= double(s.radius) * (1.0 + 1e-4) + 1e-5;
    };
    const double d = durationOf(m);
    for (int i = 0; i <= 10; ++i) {
        const double t = d * i / 10.0;
        updateAt(root, t);
        // J_k = inverse(world of the mesh's node) · world of joint k · inverse bind matrix k.
        const glm::dmat4 meshInverse = glm::inverse(worldOf(*g->parents().front()));
        std::vector<glm::dmat4> joints;
        for (std::size_t k = 0; k < m.skins[0].joints.size(); ++k) {
            const auto joint = findNode<Transform>(root, nodeName(m, m.skins[0].joints[k]));
            if (!joint) {
                ADD_FAILURE() << "no joint " << nodeName(m, m.skins[0].joints[k]);
                return out;
            }
            joints.push_back(meshInverse * worldOf(*joint) * glm::dmat4(glm::make_mat4(ibm.data() + 16 * k)));
        }
        const BoundingSphere posed = g->bound();
        for (std::size_t v = 0; v < g->positions.size(); ++v) {
            glm::dvec4 p(0.0);
            for (int k = 0; k < 4; ++k)
                p += double(g->weights0[v][k]) *
                     (joints.at(g->joints0[v][k]) * glm::dvec4(g->positions[v], 1.0));
            const glm::dvec3 skinned(p);
            EXPECT_TRUE(inside(posed, skinned)) << "vertex " << v << " at t=" << t << " is outside the bound";
            out.bindSphere += !inside(bindSphere, skinned);
            const double e = 1e-4;
            out.bindBox += glm::any(glm::lessThan(skinned, glm::dvec3(bindBox.min) - e)) ||
                           glm::any(glm::greaterThan(skinned, glm::dvec3(bindBox.max) + e));
        }
    }
    return out;
}

} // namespace

TEST(GltfAnimation, SkinnedBoundHoldsTheCpuSkinnedVertices) {
    const auto file = kAssets / "RiggedSimple/glTF/RiggedSimple.gltf";
    SGFX_REQUIRE(std::filesystem::exists(file), "the shared asset " << file);
    const tinygltf::Model m = readModel(file);
    const auto root = loadGltf(file);
    const Outside outside = expectBoundHoldsSkinnedVertices(m, *root);
    // The arm swings out of the bind pose's box (its bending stays within the loose bind sphere).
    EXPECT_GT(outside.bindBox, 0u);
}

TEST(GltfAnimation, SkinnedBoundFollowsAPoseFarFromTheBindPose) {
    // The hand-made document: its joints move the triangle about 4 m away at t = 1 s, well out of
    // the bind pose's sphere, so a bound that did not follow the pose fails here.
    const std::string json = animDocument();
    tinygltf::TinyGLTF reader;
    tinygltf::Model m;
    std::string err, warn;
    ASSERT_TRUE(reader.LoadASCIIFromString(&m, &err, &warn, json.data(), unsigned(json.size()), "")) << err;
    const auto root = loadText(json, "anim.gltf");
    const Outside outside = expectBoundHoldsSkinnedVertices(m, *root);
    EXPECT_GT(outside.bindSphere, 0u);
}

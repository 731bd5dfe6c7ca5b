// Skinning and morph targets on the GPU (issue 26) against CPU posing written here, in double,
// from the glTF 2.0 formulas: p' = Σ_k w_k · W_k · IBM_k · (p + Σ_i m_i · d_i), with W_k the joint's
// world matrix walked up the graph by this file's own code. Positions come back from the GPU
// through a capture shader (a foreign program, which the composer also poses), and the built-in
// material's path is checked by pixels where only the posed mesh can be.
#include "TestUtil.h"

#include <sgfx/Animation.h>
#include <sgfx/Geometry.h>
#include <sgfx/GltfLoader.h>
#include <sgfx/Group.h>
#include <sgfx/Material.h>
#include <sgfx/ShaderComposer.h>
#include <sgfx/StateSet.h>
#include <sgfx/Viewer.h>
#include <sgfx/Visitors.h>
#include <sgfx/nodes/fog/FogNode.h>

#include <sgfx_glad/gl.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>

using namespace sgfx;

namespace {

// Writes each vertex's world position and world normal into a storage buffer at binding 3.
const char* const kCaptureVert = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 sgfx_model;
uniform mat3 sgfx_normalMatrix;
layout(std140, binding = 0) uniform SgfxFrame {
    mat4 sgfx_view; mat4 sgfx_projection; mat4 sgfx_viewProjection; mat4 sgfx_invViewProjection;
    vec4 sgfx_eye; vec4 sgfx_viewport; vec4 sgfx_ambientLight; vec4 sgfx_time; ivec4 sgfx_lightCount;
    vec4 sgfx_lightVector[8]; vec4 sgfx_lightColor[8];
};
layout(std430, binding = 3) buffer Capture { vec4 captured[]; };
void main() {
    vec4 world = sgfx_model * vec4(a_position, 1.0);
    captured[2 * gl_VertexID] = world;
    captured[2 * gl_VertexID + 1] = vec4(normalize(sgfx_normalMatrix * a_normal), 0.0);
    gl_Position = sgfx_viewProjection * world;
}
)";

std::shared_ptr<ShaderProgram> captureProgram() {
    auto p = std::make_shared<ShaderProgram>();
    p->name = "capture";
    p->vertexSource = kCaptureVert;
    p->fragmentSource = test::kForeignFrag;
    return p;
}

// The world matrix of `node` (its own transform included), walked up the first parents in double.
glm::dmat4 worldOf(const Node* node) {
    glm::dmat4 m(1.0);
    for (; node; node = node->parents().empty() ? nullptr : node->parents().front())
        if (const auto* t = dynamic_cast<const Transform*>(node)) m = glm::dmat4(t->matrix()) * m;
    return m;
}

glm::dmat3 cofactor(const glm::dmat3& m) {
    return glm::dmat3(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1]));
}

struct Posed {
    std::vector<glm::dvec3> positions, normals;
};

// The CPU pose of every vertex of g, in world space.
Posed cpuPose(const Geometry& g) {
    Posed out;
    const glm::dmat4 meshWorld = worldOf(g.parents().front());
    for (std::size_t v = 0; v < g.positions.size(); ++v) {
        glm::dvec3 p(g.positions[v]);
        glm::dvec3 n = g.normals.empty() ? glm::dvec3(0, 0, 1) : glm::dvec3(g.normals[v]);
        for (std::size_t t = 0; t < g.morphTargets.size() && t < g.morphWeights().size(); ++t) {
            const double w = g.morphWeights()[t];
            if (!g.morphTargets[t].positions.empty()) p += w * glm::dvec3(g.morphTargets[t].positions[v]);
            if (!g.morphTargets[t].normals.empty()) n += w * glm::dvec3(g.morphTargets[t].normals[v]);
        }
        glm::dmat4 m = meshWorld;
        if (g.skin) {
            m = glm::dmat4(0.0);
            auto add = [&](const std::vector<glm::u16vec4>& js, const std::vector<glm::vec4>& ws) {
                if (js.empty()) return;
                for (int k = 0; k < 4; ++k) {
                    const std::size_t j = js[v][k];
                    m += double(ws[v][k]) * worldOf(g.skin->joints[j].lock().get()) *
                         glm::dmat4(g.skin->inverseBindMatrices[j]);
                }
            };
            add(g.joints0, g.weights0);
            add(g.joints1, g.weights1);
        }
        out.positions.push_back(glm::dvec3(m * glm::dvec4(p, 1.0)));
        out.normals.push_back(glm::normalize(cofactor(glm::dmat3(m)) * n));
    }
    return out;
}

// Renders one frame with `g` drawn by the capture program and returns what the GPU posed.
Posed gpuPose(Viewer& viewer, Geometry& g) {
    auto state = std::make_shared<StateSet>();
    state->program.set(captureProgram());
    g.setStateSet(state);
    g.setCullingActive(false);
    viewer.renderFrame(); // compiles programs and makes the context current
    GLuint buffer = 0;
    glCreateBuffers(1, &buffer);
    std::vector<glm::vec4> data(2 * g.positions.size(), glm::vec4(std::nanf("")));
    glNamedBufferData(buffer, GLsizeiptr(data.size() * sizeof(glm::vec4)), data.data(), GL_DYNAMIC_READ);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, buffer);
    viewer.renderFrame();
    glFinish();
    glGetNamedBufferSubData(buffer, 0, GLsizeiptr(data.size() * sizeof(glm::vec4)), data.data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, 0);
    glDeleteBuffers(1, &buffer);
    Posed out;
    for (std::size_t v = 0; v < g.positions.size(); ++v) {
        out.positions.emplace_back(data[2 * v]);
        out.normals.emplace_back(data[2 * v + 1]);
    }
    return out;
}

// Largest position error relative to the posed mesh's size, and largest normal angle error.
void expectSamePose(const Posed& gpu, const Posed& cpu, double relative, const std::string& what) {
    ASSERT_EQ(gpu.positions.size(), cpu.positions.size());
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& p : cpu.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const double size = glm::length(hi - lo);
    double worst = 0.0, worstNormal = 0.0;
    for (std::size_t v = 0; v < cpu.positions.size(); ++v) {
        worst = std::max(worst, glm::length(gpu.positions[v] - cpu.positions[v]) / size);
        worstNormal = std::max(worstNormal, glm::length(gpu.normals[v] - cpu.normals[v]));
    }
    EXPECT_LT(worst, relative) << what << ": worst position error relative to the size " << size;
    EXPECT_LT(worstNormal, 1e-4) << what << ": worst normal difference";
}

// A cylinder along +x from 0 to 2 (radius 0.2) skinned to a chain of three joints at x = 0, 1,
// 1.6; the tip's vertices share joint 1 (JOINTS_0) with joint 2 (JOINTS_1).
struct Arm {
    std::shared_ptr<Group> root = Group::create();
    std::shared_ptr<Transform> meshNode, j0, j1, j2;
    std::shared_ptr<Geometry> geometry = Geometry::create();
};

Arm makeArm() {
    Arm a;
    a.j0 = Transform::create();
    a.j1 = Transform::create(glm::translate(glm::mat4(1.0f), {1, 0, 0}));
    a.j2 = Transform::create(glm::translate(glm::mat4(1.0f), {0.6f, 0, 0}));
    a.root->addChild(a.j0);
    a.j0->addChild(a.j1);
    a.j1->addChild(a.j2);
    // glTF: the skinned mesh node's own transform does not move the mesh.
    a.meshNode =
        Transform::create(glm::translate(glm::scale(glm::mat4(1.0f), {2, 2, 2}), {0.3f, -0.2f, 0.1f}));
    a.root->addChild(a.meshNode);
    Geometry& g = *a.geometry;
    const int rings = 21, segments = 8;
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const float x = 2.0f * float(r) / float(rings - 1), phi = 6.2831853f * float(s) / float(segments);
            g.positions.emplace_back(x, 0.2f * std::cos(phi), 0.2f * std::sin(phi));
            g.normals.emplace_back(0.0f, std::cos(phi), std::sin(phi));
            const float w1 = glm::smoothstep(0.8f, 1.2f, x), w2 = 0.5f * glm::smoothstep(1.4f, 1.8f, x);
            g.joints0.emplace_back(0, 1, 0, 0);
            g.weights0.emplace_back(1.0f - w1, w1 - w2, 0.0f, 0.0f);
            g.joints1.emplace_back(2, 0, 0, 0);
            g.weights1.emplace_back(w2, 0.0f, 0.0f, 0.0f);
        }
    for (int r = 0; r + 1 < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const auto i = std::uint32_t(r * segments + s),
                       j = std::uint32_t(r * segments + (s + 1) % segments);
            g.indices.insert(g.indices.end(), {i, j, i + segments, j, j + segments, i + segments});
        }
    auto skin = std::make_shared<Skin>();
    skin->name = "arm";
    skin->joints = {a.j0, a.j1, a.j2};
    skin->inverseBindMatrices = {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), {-1, 0, 0}),
                                 glm::translate(glm::mat4(1.0f), {-1.6f, 0, 0})};
    skin->root = a.root;
    g.skin = skin;
    a.meshNode->addChild(a.geometry);
    return a;
}

void poseArm(Arm& a, float bend) {
    a.j0->setMatrix(glm::rotate(glm::mat4(1.0f), 0.35f, glm::vec3(0, 1, 0)));
    a.j1->setMatrix(glm::rotate(glm::translate(glm::mat4(1.0f), {1, 0, 0}), bend, glm::vec3(0, 0, 1)));
    a.j2->setMatrix(
        glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), {0.6f, 0, 0}), -0.5f, glm::vec3(0, 0, 1)),
                   {1.0f, 1.3f, 0.8f})); // uneven scale: the normals need the cofactor
}

std::filesystem::path shared(const std::string& model) {
    return std::filesystem::path(SGFX_SOURCE_DIR) / ".." / "shared" / "assets" / "gltf" / model / "glTF" /
           (model + ".gltf");
}

} // namespace

TEST(Skinning, TwoBoneCylinderOnTheGpuEqualsCpuSkinning) {
    auto viewer = test::orthoTopViewer(32, 4.0f);
    Arm arm = makeArm();
    viewer->setSceneData(arm.root);
    for (const float bend : {0.0f, 0.9f, 1.57f}) {
        poseArm(arm, bend);
        viewer->update(0.0);
        const Posed gpu = gpuPose(*viewer, *arm.geometry);
        const Posed cpu = cpuPose(*arm.geometry);
        expectSamePose(gpu, cpu, 1e-5, "bend " + std::to_string(bend));
    }
    // The pose moved the tip: a test that compared a mesh with itself would pass anyway.
    EXPECT_GT(
        glm::length(cpuPose(*arm.geometry).positions.back() - glm::dvec3(arm.geometry->positions.back())),
        0.5);
}

TEST(Skinning, MorphTargetsThenSkinningEqualCpu) {
    auto viewer = test::orthoTopViewer(32, 4.0f);
    Arm arm = makeArm();
    Geometry& g = *arm.geometry;
    for (int t = 0; t < 3; ++t) {
        MorphTarget m;
        for (std::size_t v = 0; v < g.positions.size(); ++v) {
            const glm::vec3 p = g.positions[v];
            m.positions.emplace_back(0.1f * float(t + 1) * std::sin(3.0f * p.x + float(t)),
                                     0.05f * p.y * float(t), 0.07f * std::cos(p.x * float(t + 2)));
            m.normals.emplace_back(0.2f * float(t), 0.0f, -0.1f);
        }
        g.morphTargets.push_back(std::move(m));
    }
    g.dirty();
    viewer->setSceneData(arm.root);
    const std::vector<float> weights = {0.25f, -0.5f, 1.3f};
    g.setMorphWeights(weights);
    poseArm(arm, 0.7f);
    viewer->update(0.0);
    expectSamePose(gpuPose(*viewer, g), cpuPose(g), 1e-5, "morphed and skinned");
    // Morphs alone (no skin): the same mesh unskinned.
    g.skin = nullptr;
    g.joints0.clear();
    g.weights0.clear();
    g.joints1.clear();
    g.weights1.clear();
    g.dirty();
    viewer->update(0.0);
    expectSamePose(gpuPose(*viewer, g), cpuPose(g), 1e-5, "morphed only");
}

TEST(Skinning, MorphWeightsAreChecked) {
    Arm arm = makeArm();
    Geometry& g = *arm.geometry;
    g.morphTargets.resize(2);
    const std::vector<float> good = {0.5f, 0.25f};
    g.setMorphWeights(good);
    const std::vector<float> tooMany = {1.0f, 2.0f, 3.0f};
    EXPECT_THROW(g.setMorphWeights(tooMany), std::invalid_argument);
    const std::vector<float> nan = {std::nanf(""), 0.0f};
    EXPECT_THROW(g.setMorphWeights(nan), std::invalid_argument);
    EXPECT_EQ(g.morphWeights(), good); // the old weights stay
}

// The shared skinned and morphed models at several times of their first animation: the GPU's
// positions against a CPU pose of the same file.
TEST(Skinning, SharedModelsMatchCpuPosingOfTheFile) {
    const std::vector<std::string> models = {"RiggedSimple", "RiggedFigure", "SimpleSkin",
                                             "AnimatedMorphCube", "SimpleMorph"};
    for (const auto& model : models) {
        const auto file = shared(model);
        if (!test::optionalPrerequisite(std::filesystem::exists(file), "shared glTF set A2 (" + model + ")"))
            return;
        auto root = loadGltf(file);
        AnimationPlayer* player = animationPlayer(*root);
        ASSERT_NE(player, nullptr) << model;
        // The posed geometry (each of these models has one).
        struct Find : NodeVisitor {
            Geometry* found = nullptr;
            void apply(Geometry& g) override {
                if (g.posed()) found = &g;
            }
        } find;
        root->accept(find);
        ASSERT_NE(find.found, nullptr) << model;
        auto viewer = test::orthoTopViewer(32, 4.0f);
        viewer->setSceneData(root);
        const float duration = player->animations[0].duration();
        double moved = 0.0;
        for (const double fraction : {0.13, 0.5, 0.81}) {
            const double t = fraction * duration;
            player->play(0);
            player->seek(t);
            player->pause();
            viewer->update(0.0);
            const Posed cpu = cpuPose(*find.found);
            expectSamePose(gpuPose(*viewer, *find.found), cpu, 1e-5, model + " at t = " + std::to_string(t));
            for (std::size_t v = 0; v < cpu.positions.size(); ++v)
                moved = std::max(moved, glm::length(cpu.positions[v] -
                                                    glm::dvec3(worldOf(find.found->parents().front()) *
                                                               glm::dvec4(find.found->positions[v], 1.0))));
        }
        EXPECT_GT(moved, 1e-3) << model << ": the animation never moved a vertex from its bind pose";
    }
}

// The arm lies along +x from 0 to 4 with its elbow at x = 1; bent 90°, its forearm points along
// +y, out of the bind-pose bound (centre (2, 0, 0), radius 2.2). `shifted` moves the point (1, 2.8),
// which only the bent forearm covers, to the origin. White, unlit, built-in material.
struct Forearm {
    std::shared_ptr<Transform> shifted, j1;
    std::shared_ptr<Geometry> geometry = Geometry::create();
    void bend() {
        j1->setMatrix(
            glm::rotate(glm::translate(glm::mat4(1.0f), {1, 0, 0}), 1.5707963f, glm::vec3(0, 0, 1)));
    }
};

Forearm makeForearm() {
    Forearm f;
    auto root = Group::create();
    auto j0 = Transform::create();
    f.j1 = Transform::create(glm::translate(glm::mat4(1.0f), {1, 0, 0}));
    root->addChild(j0);
    j0->addChild(f.j1);
    Geometry& g = *f.geometry;
    const int rings = 41;
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < 6; ++s) {
            const float x = 4.0f * float(r) / float(rings - 1), phi = 1.0471976f * float(s);
            g.positions.emplace_back(x, 0.15f * std::cos(phi), 0.15f * std::sin(phi));
            const float w = x > 1.0f ? 1.0f : 0.0f;
            g.joints0.emplace_back(0, 1, 0, 0);
            g.weights0.emplace_back(1.0f - w, w, 0.0f, 0.0f);
        }
    for (int r = 0; r + 1 < rings; ++r)
        for (int s = 0; s < 6; ++s) {
            const auto i = std::uint32_t(r * 6 + s), j = std::uint32_t(r * 6 + (s + 1) % 6);
            g.indices.insert(g.indices.end(), {i, j, i + 6, j, j + 6, i + 6});
        }
    auto skin = std::make_shared<Skin>();
    skin->joints = {j0, f.j1};
    skin->inverseBindMatrices = {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), {-1, 0, 0})};
    skin->root = root;
    g.skin = skin;
    auto material = std::make_shared<Material>();
    material->model = ShadingModel::Unlit;
    material->diffuse = glm::vec4(1.0f);
    g.getOrCreateStateSet().material.set(material);
    auto meshNode = Transform::create();
    meshNode->addChild(f.geometry);
    root->addChild(meshNode);
    f.shifted = Transform::create(glm::translate(glm::mat4(1.0f), {-1.0f, -2.8f, 0.0f}));
    f.shifted->addChild(root);
    return f;
}

// A skinned arm swung out of its bind-pose bound is drawn (the bound follows the pose) by the
// built-in material, where the CPU pose puts it.
TEST(Skinning, ArmSwungOutOfItsBindBoundIsNotCulled) {
    Forearm arm = makeForearm();
    auto viewer = test::orthoTopViewer(16, 0.25f);
    viewer->setSceneData(arm.shifted);
    viewer->frame(0.0);
    EXPECT_EQ(test::pixelAt(viewer->capture(), 8, 8).r, 0) << "the straight arm is outside the view";
    arm.bend();
    viewer->frame(0.0);
    EXPECT_GT(test::pixelAt(viewer->capture(), 8, 8).r, 250) << "the bent forearm passes through the view";
}

// Passes that draw the scene again (the split fog's depth pre-pass) pose it the same way: split
// fog on the bent forearm equals forward fog, which needs no pre-pass; a pre-pass of the unposed
// arm would leave that pixel at sky depth, fogged almost fully.
TEST(Skinning, DepthPrePassSeesThePose) {
    FogParameters fog;
    fog.density = 0.05f;
    fog.falloff = 0.0f;
    int pixel[2] = {0, 0};
    for (const FogMode mode : {FogMode::Forward, FogMode::ForwardSplit}) {
        Forearm arm = makeForearm();
        arm.bend();
        auto node = FogNode::create(fog, mode);
        node->addChild(arm.shifted);
        auto viewer = test::orthoTopViewer(16, 0.25f);
        viewer->setSceneData(node);
        viewer->frame(0.0);
        test::expectNoGlErrors(*viewer);
        pixel[mode == FogMode::Forward ? 0 : 1] = test::pixelAt(viewer->capture(), 8, 8).b;
    }
    // 10 m of fog at 0.05 /m: k = 1 − e^(−0.5); white surface, fog blue 0.80 (linear).
    const double k = 1.0 - std::exp(-0.5);
    EXPECT_NEAR(pixel[0], test::srgbByte((1.0 - k) * 1.0 + k * 0.80), 2);
    EXPECT_NEAR(pixel[1], pixel[0], 2);
}

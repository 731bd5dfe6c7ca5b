// Posed geometry (issue 26): morph weights, skin joint matrices and the bound that follows them.
// The GPU does the per-vertex work (shaders/pose.glsl); this file keeps what the CPU must know.
#include "sgfx/Geometry.h"
#include "sgfx/Group.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace sgfx {

namespace {

std::string labelOf(const Geometry& g) {
    return g.name.empty() ? std::string("(unnamed)") : "'" + g.name + "'";
}

// The matrix from `root` (exclusive) down to `node` (inclusive of its own transform), in double:
// joints of a model far from the origin keep their precision. Memoised per call of updateSkin.
struct WorldMatrices {
    const Node* root = nullptr;
    std::unordered_map<const Node*, glm::dmat4> memo;

    glm::dmat4 of(const Node* node) {
        if (!node || node == root) return glm::dmat4(1.0);
        if (const auto it = memo.find(node); it != memo.end()) return it->second;
        // The first parent: a joint reached by several paths is posed along the first (documented).
        const Node* parent = node->parents().empty() ? nullptr : node->parents().front();
        glm::dmat4 m = of(parent);
        if (const auto* t = dynamic_cast<const Transform*>(node)) m = m * glm::dmat4(t->matrix());
        memo.emplace(node, m);
        return m;
    }
};

} // namespace

void Geometry::setMorphWeights(std::span<const float> weights) {
    if (weights.size() > morphTargets.size())
        throw std::invalid_argument("sgfx: geometry " + labelOf(*this) + ": " +
                                    std::to_string(weights.size()) + " morph weights for " +
                                    std::to_string(morphTargets.size()) + " targets");
    for (std::size_t i = 0; i < weights.size(); ++i)
        if (!std::isfinite(weights[i]))
            throw std::invalid_argument("sgfx: geometry " + labelOf(*this) + ": morph weight " +
                                        std::to_string(i) + " is NaN or infinite");
    if (morphWeights_.size() == weights.size() &&
        std::equal(weights.begin(), weights.end(), morphWeights_.begin()))
        return;
    morphWeights_.assign(weights.begin(), weights.end());
    ++poseRevision_;
    dirtyBound();
}

void Geometry::updateSkin() {
    if (!skin) return;
    const std::size_t n = skin->joints.size();
    if (skin->inverseBindMatrices.size() != n)
        throw std::invalid_argument("sgfx: geometry " + labelOf(*this) + ": skin '" + skin->name + "' has " +
                                    std::to_string(skin->inverseBindMatrices.size()) +
                                    " inverse bind matrices for " + std::to_string(n) + " joints");
    const auto root = skin->root.lock();
    WorldMatrices world{root.get(), {}};
    // glTF 2.0, Skins: the mesh node's own transform is replaced by the joints'; the renderer
    // applies the model matrix after skinning, so it is taken out here.
    const Node* meshNode = parents().empty() ? nullptr : parents().front();
    // A singular mesh node (scale 0: legal, since glTF ignores it) would make every matrix NaN;
    // its model matrix then collapses the mesh anyway, so the joints' own matrices are kept.
    const glm::dmat4 meshWorld = world.of(meshNode);
    const double det = glm::determinant(meshWorld);
    const glm::dmat4 toMesh =
        std::isfinite(det) && std::abs(det) > 1e-300 ? glm::inverse(meshWorld) : glm::dmat4(1.0);
    std::vector<glm::mat4> next(n);
    for (std::size_t j = 0; j < n; ++j) {
        const auto joint = skin->joints[j].lock();
        next[j] = glm::mat4(toMesh * (joint ? world.of(joint.get()) : glm::dmat4(1.0)) *
                            glm::dmat4(skin->inverseBindMatrices[j]));
    }
    if (next == jointMatrices_) return;
    jointMatrices_ = std::move(next);
    ++poseRevision_;
    dirtyBound();
}

// The box of the posed vertices, without visiting them: each joint's bind-pose box (of the
// vertices it weighs, grown by the morph range) moved by its joint matrix. A skinned vertex is a
// convex mix of its joints' moved copies, so it lies in the union's box. The bind-pose boxes are
// made once per revision of the arrays (and skin size), so a new pose costs a few boxes.
void Geometry::updatePoseBoxes() const {
    const std::size_t joints = skin ? skin->joints.size() : 0;
    if (poseBoxesRevision_ == revision_ && jointBoxes_.size() == joints) return;
    baseBox_ = BoundingBox{};
    for (const auto& p : positions)
        baseBox_.expandBy(p);
    morphBoxes_.assign(morphTargets.size(), BoundingBox{});
    for (std::size_t t = 0; t < morphTargets.size(); ++t)
        for (const auto& v : morphTargets[t].positions)
            morphBoxes_[t].expandBy(v);
    jointBoxes_.assign(joints, BoundingBox{});
    auto add = [&](const std::vector<glm::u16vec4>& js, const std::vector<glm::vec4>& ws) {
        for (std::size_t v = 0; v < js.size() && v < ws.size() && v < positions.size(); ++v)
            for (int k = 0; k < 4; ++k)
                if (ws[v][k] > 0.0f && js[v][k] < joints) jointBoxes_[js[v][k]].expandBy(positions[v]);
    };
    add(joints0, weights0);
    add(joints1, weights1);
    poseBoxesRevision_ = revision_;
}

BoundingBox Geometry::posedBox() const {
    updatePoseBoxes();
    if (!baseBox_.valid()) return baseBox_;
    // Morphs: Σ w_i·d_i lies in the box summed over the targets of w_i times each target's box.
    glm::vec3 lo(0.0f), hi(0.0f);
    for (std::size_t t = 0; t < morphBoxes_.size() && t < morphWeights_.size(); ++t) {
        const BoundingBox& d = morphBoxes_[t];
        if (!d.valid()) continue;
        const float w = morphWeights_[t];
        lo += glm::min(d.min * w, d.max * w);
        hi += glm::max(d.min * w, d.max * w);
    }
    if (!skin || jointMatrices_.size() != jointBoxes_.size())
        return BoundingBox{baseBox_.min + lo, baseBox_.max + hi};
    BoundingBox all;
    for (std::size_t j = 0; j < jointBoxes_.size(); ++j) {
        const BoundingBox& b = jointBoxes_[j];
        if (!b.valid()) continue;
        for (int c = 0; c < 8; ++c)
            all.expandBy(
                glm::vec3(jointMatrices_[j] * glm::vec4(c & 1 ? b.max.x + hi.x : b.min.x + lo.x,
                                                        c & 2 ? b.max.y + hi.y : b.min.y + lo.y,
                                                        c & 4 ? b.max.z + hi.z : b.min.z + lo.z, 1.0f)));
    }
    return all;
}

void Geometry::validatePose() const {
    const std::size_t n = positions.size();
    auto fail = [&](const std::string& why) {
        throw std::invalid_argument("sgfx: geometry " + labelOf(*this) + " " + why);
    };
    // Joints without a skin are allowed (a mesh loaded before its skin is known): they are not drawn posed.
    if (joints0.size() != weights0.size() || joints1.size() != weights1.size())
        fail("has joint indices and weights of different counts");
    if (skin && joints0.empty()) fail("has a skin but no joints0/weights0");
    const std::size_t joints = skin ? skin->joints.size() : 0;
    auto checkJoints = [&](const std::vector<glm::u16vec4>& js, const char* what) {
        for (std::size_t v = 0; v < js.size(); ++v)
            for (int k = 0; k < 4; ++k)
                if (js[v][k] >= joints)
                    fail(std::string(what) + "[" + std::to_string(v) + "] names joint " +
                         std::to_string(js[v][k]) + " of a skin with " + std::to_string(joints));
    };
    if (skin) {
        checkJoints(joints0, "joints0");
        checkJoints(joints1, "joints1");
    }
    for (std::size_t t = 0; t < morphTargets.size(); ++t) {
        const MorphTarget& m = morphTargets[t];
        for (const auto* a : {&m.positions, &m.normals, &m.tangents})
            if (!a->empty() && a->size() != n)
                fail("morph target " + std::to_string(t) + " has " + std::to_string(a->size()) +
                     " displacements for " + std::to_string(n) + " positions");
    }
}

} // namespace sgfx

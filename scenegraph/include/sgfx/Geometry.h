#pragma once
#include "sgfx/Export.h"
#include "sgfx/Node.h"

#include <glm/glm.hpp>
#include <glm/gtc/type_precision.hpp>

#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

namespace sgfx {

enum class PrimitiveMode : std::uint8_t { Points, Lines, LineStrip, Triangles, TriangleStrip, TriangleFan };

namespace gl {
struct GeometryBuffers;
}
class TriangleBvh;
class Transform;

/// A glTF skin: the joints that pose a skinned geometry and their inverse bind matrices (glTF 2.0,
/// Skins). Shared by every geometry the skin deforms.
struct SGFX_API Skin {
    std::string name;
    std::vector<std::weak_ptr<Transform>> joints;
    std::vector<glm::mat4> inverseBindMatrices; ///< one per joint (identity when the file has none)
    /// Joint matrices are computed from here down (the loaded model's root): above it every
    /// transform cancels, so a model far from the origin keeps its precision.
    std::weak_ptr<Node> root;
};

/// One morph target: per-vertex displacements (empty, or one per position), glTF 2.0 Morph Targets.
struct SGFX_API MorphTarget {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec3> tangents;
};

/// Vertex arrays plus optional indices: a drawable leaf. Attributes other than positions may be
/// empty; a non-empty attribute must have one entry per position (checked at draw time).
/// After editing the arrays call dirty(): the GPU copy is refreshed at the next draw.
class SGFX_API Geometry : public Node {
public:
    static std::shared_ptr<Geometry> create() { return std::make_shared<Geometry>(); }
    Geometry();
    ~Geometry() override;

    void accept(NodeVisitor& v) override;

    /// A new Geometry with copies of the arrays, the mode, the name and this one's StateSet
    /// (shared); no parents, no GPU copy.
    std::shared_ptr<Geometry> clone() const;

    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec4> tangents; ///< xyz tangent, w handedness
    std::vector<glm::vec2> texcoords;
    std::vector<glm::vec2> texcoords1; ///< a second set (glTF TEXCOORD_1), chosen per material map
    std::vector<glm::vec4> colors;
    std::vector<std::uint32_t> indices;
    /// Instanced drawing: when not empty, the geometry is drawn once per matrix (each applied
    /// before the node's world transform) in one draw call. Foreign shaders read it as
    /// `layout(location = 6) in mat4` (locations 6..9).
    std::vector<glm::mat4> instances;
    PrimitiveMode mode = PrimitiveMode::Triangles;

    /// Skinning (glTF JOINTS_0/WEIGHTS_0 and JOINTS_1/WEIGHTS_1): per vertex up to eight joint
    /// indices into skin->joints and their weights (normalised at load). Skinned on the GPU in the
    /// vertex stage, before the model matrix, for built-in materials and foreign shaders alike.
    std::vector<glm::u16vec4> joints0, joints1;
    std::vector<glm::vec4> weights0, weights1;
    std::shared_ptr<Skin> skin;
    /// Morph targets, applied on the GPU before skinning: position += Σ weight_i · target_i.
    std::vector<MorphTarget> morphTargets;

    /// The morph weights (one per target; missing ones are 0). Throws std::invalid_argument on a
    /// NaN or infinite weight or more weights than targets, keeping the old ones.
    void setMorphWeights(std::span<const float> weights);
    const std::vector<float>& morphWeights() const { return morphWeights_; }
    /// Joint matrices of the present pose (mesh space bind pose → mesh space posed), one per joint:
    /// inverse(world of the geometry's parent) · world of the joint · inverse bind matrix.
    const std::vector<glm::mat4>& jointMatrices() const { return jointMatrices_; }
    /// Recomputes jointMatrices() from the joints' transforms (UpdateVisitor::updatePoses does it
    /// after every update traversal) and dirties the bound when the pose moved.
    void updateSkin();
    /// Counts pose changes (joint matrices, morph weights): the GPU copy follows it.
    std::uint64_t poseRevision() const { return poseRevision_; }
    bool posed() const { return skin != nullptr || !morphTargets.empty(); }

    void dirty();
    std::uint64_t revision() const { return revision_; }

    std::size_t elementCount() const { return indices.empty() ? positions.size() : indices.size(); }
    std::size_t triangleCount() const; ///< of all instances
    std::size_t instanceCount() const { return instances.empty() ? 1 : instances.size(); }

    /// Throws std::invalid_argument naming the attribute and geometry when arrays disagree or
    /// an index is out of range.
    void validate() const;

    /// Its triangles in a BVH for scene queries (Intersection.h), built on first use and again
    /// after dirty(). Safe to call from several threads at once while nothing changes the arrays.
    std::shared_ptr<const TriangleBvh> triangleBvh() const;

    /// Renderer-owned GPU copy (created lazily on the GL thread).
    std::unique_ptr<gl::GeometryBuffers>& gpu() const { return gpu_; }

protected:
    BoundingSphere computeBound() const override;

private:
    BoundingBox posedBox() const;
    void validatePose() const; ///< validate()'s checks of joints, weights and morph targets
    std::uint64_t revision_ = 1;
    std::uint64_t poseRevision_ = 1;
    std::vector<float> morphWeights_;
    std::vector<glm::mat4> jointMatrices_;
    /// Bind-pose boxes the posed bound is made from (updatePoseBoxes): all positions, each morph
    /// target's displacements, and per joint the vertices it moves; with the revision they are for.
    void updatePoseBoxes() const;
    mutable BoundingBox baseBox_;
    mutable std::vector<BoundingBox> morphBoxes_, jointBoxes_;
    mutable std::uint64_t poseBoxesRevision_ = 0;
    mutable std::unique_ptr<gl::GeometryBuffers> gpu_;
    mutable std::mutex queryMutex_; ///< guards bvh_
    mutable std::shared_ptr<const TriangleBvh> bvh_;
};

} // namespace sgfx

#pragma once
#include "sgfx/Export.h"
#include "sgfx/Node.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace sgfx {

enum class PrimitiveMode : std::uint8_t { Points, Lines, LineStrip, Triangles, TriangleStrip, TriangleFan };

namespace gl {
struct GeometryBuffers;
}
class TriangleBvh;

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
    std::uint64_t revision_ = 1;
    mutable std::unique_ptr<gl::GeometryBuffers> gpu_;
    mutable std::mutex queryMutex_; ///< guards bvh_
    mutable std::shared_ptr<const TriangleBvh> bvh_;
};

} // namespace sgfx

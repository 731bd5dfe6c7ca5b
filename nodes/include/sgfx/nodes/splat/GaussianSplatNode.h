#pragma once
/// @file
/// 3D Gaussian splatting (Kerbl et al. 2023) as a scene-graph leaf: each Gaussian is projected
/// with the EWA Jacobian (Zwicker et al. 2001) into a 2D Gaussian drawn on a 3σ quad, sorted by
/// view depth every frame (a GPU radix sort or a CPU sort) and blended back to front,
/// premultiplied, depth-tested against the opaque scene without writing depth. The whole cloud
/// is one item of the transparent stage (ordered with glass by its bound's centre) and takes the
/// effects above it at the colour hook (fog). See docs/gaussian-splatting.md.
#include "sgfx/Export.h"
#include <sgfx/nodes/splat/SplatCloud.h>

#include <sgfx/Drawable.h>
#include <sgfx/ShaderComposer.h>

#include <memory>

namespace sgfx {

class StateSet;

/// How the per-frame depth order is made.
enum class SplatSort : std::uint8_t { Gpu, Cpu };

class SGFX_API GaussianSplatNode : public Drawable {
public:
    /// Throws std::invalid_argument (SplatCloud::validate).
    static std::shared_ptr<GaussianSplatNode> create(SplatCloud cloud);
    /// splat::loadPly, then create; throws LoadError.
    static std::shared_ptr<GaussianSplatNode> load(const std::filesystem::path& file);
    explicit GaussianSplatNode(SplatCloud cloud);
    ~GaussianSplatNode() override;

    const SplatCloud& cloud() const { return cloud_; }
    /// Throws std::invalid_argument and keeps the old cloud.
    void setCloud(SplatCloud cloud);
    void setSort(SplatSort sort) { sort_ = sort; }
    SplatSort sort() const { return sort_; }
    /// Sorts for a view as a draw does (the node must have been compiled: drawn once), without
    /// drawing: benchmarks time the sort alone with it.
    void sortFor(Renderer& renderer, const glm::mat4& modelView) const;
    /// The back-to-front order of the last draw (read back from the GPU for SplatSort::Gpu):
    /// for tests and benchmarks.
    std::vector<std::uint32_t> lastOrder() const;

    /// Premultiplied blending, depth test without depth writes, both faces.
    static std::shared_ptr<StateSet> defaultState();

    const BaseShader& baseShader() const override { return shader_; }
    FeatureMask features(const ResolvedState&) const override { return FeatureWorldPosition; }
    void compile(Renderer& renderer) const override;
    void draw(Renderer& renderer, gl::Program& program, const RenderItem& item) const override;
    void releaseGLObjects() override;
    std::size_t triangleCount() const override { return 2 * cloud_.size(); }

protected:
    BoundingSphere computeBound() const override;

private:
    struct Gpu;
    void sortOnCpu(const glm::mat4& modelView) const;
    void sortOnGpu(Renderer& renderer, const glm::mat4& modelView) const;
    SplatCloud cloud_;
    SplatSort sort_ = SplatSort::Gpu;
    BaseShader shader_;
    mutable std::unique_ptr<Gpu> gpu_;
    mutable bool dirty_ = true;
};

} // namespace sgfx

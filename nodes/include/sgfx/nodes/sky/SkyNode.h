#pragma once
/// @file
/// A physically based sky behind the scene (lecture 12: Rayleigh and Mie single scattering; Earth
/// defaults after Nishita et al. 1993): a spherical atmosphere seen from the eye's altitude, a sun
/// disc, time of day by the sun's direction. Its horizon colour can drive a FogNode's colour, so
/// distant geometry fades into the sky (aerial perspective).
#include "sgfx/Export.h"
#include <sgfx/nodes/environment/EnvironmentMath.h>
#include <sgfx/nodes/sky/SkyMath.h>

#include <sgfx/Drawable.h>
#include <sgfx/ShaderComposer.h>

#include <memory>

namespace sgfx {

class FogNode;
class ShadowNode;

/// The atmosphere, the sun and how the sky is drawn (view table or per pixel).
struct SGFX_API SkyParameters {
    glm::vec3 sunDirection{0.0f, 0.5f, 0.866f}; ///< towards the sun, world (normalised when set)
    float sunIntensity = 20.0f;                 ///< irradiance scale of the scattered light
    float sunDiscRadiance = 2000.0f;            ///< radiance of the disc itself
    float sunAngularRadius = 0.00465f;          ///< rad (the real sun: 0.267°)
    float altitude = 0.0f;                      ///< m above sea level of world z = 0
    sky::Atmosphere atmosphere;                 ///< Earth by default
    int steps = 16;                             ///< view-ray steps
    int lightSteps = 8;                         ///< sun-ray steps
    /// Sample a sky-view table made once per frame (256 × 128 texels) instead of integrating per
    /// pixel; `false` integrates every pixel (exact, several times the cost on a software GPU).
    bool lookupTable = true;

    /// Sun at local solar time `hours`, latitude (degrees) and day of the year.
    static SkyParameters atTime(float hours, float latitudeDegrees = 45.0f, int dayOfYear = 172);
    /// Throws std::invalid_argument naming the field.
    void validate() const;
    bool operator==(const SkyParameters&) const = default;
};

/// The sky behind everything (lecture 12: Rayleigh and Mie single scattering), drawn where
/// nothing else is; attachFog() makes a FogNode take its horizon colour. See
/// docs/effects/volume-sky.md.
class SGFX_API SkyNode : public Drawable {
public:
    static std::shared_ptr<SkyNode> create(const SkyParameters& parameters = {});
    explicit SkyNode(const SkyParameters& parameters);

    /// Throws std::invalid_argument and keeps the old parameters.
    void setParameters(const SkyParameters& parameters);
    const SkyParameters& parameters() const { return parameters_; }

    /// Each frame (update traversal) the fog's colour becomes the sky's horizon colour towards the
    /// sun's azimuth, averaged around the horizon, and the fog stops fogging sky pixels itself
    /// (FogSky::Off): the sky is fogged once, by its own atmosphere. Null detaches.
    void attachFog(std::shared_ptr<FogNode> fog);
    /// Each frame (update traversal) the shadow node's sun light follows the sky's sun: its
    /// direction becomes −sunDirection and its colour the sun's transmittance through the
    /// atmosphere (sky::sunTransmittance; its intensity is left alone). Below the horizon the
    /// colour is 0, and a sun without light draws no shadow map. Null detaches.
    void attachShadow(std::shared_ptr<ShadowNode> shadow);
    /// The linear radiance of the horizon (1° above it), averaged over 8 azimuths.
    glm::vec3 horizonColor() const;
    /// The sky seen from sea level + altitude, without the sun's disc (a directional light stands
    /// for the sun), as a cube map of size² faces: rendered by the sky's own scattering shader
    /// and read back (EnvironmentLightNode::followSky calls it from compile()). GL must be
    /// current; size is a power of two from 8 to 512.
    env::CubeImage renderEnvironment(Renderer& renderer, int size) const;

    const BaseShader& baseShader() const override;
    void setupFrame(FrameSetup& frame) const override;
    FeatureMask features(const ResolvedState&) const override { return 0; }
    bool background() const override { return true; }
    void update(UpdateVisitor& uv) override;
    void draw(Renderer& renderer, gl::Program& program, const RenderItem& item) const override;

protected:
    BoundingSphere computeBound() const override { return {}; }

private:
    std::string tableName() const;
    SkyParameters parameters_;
    std::weak_ptr<FogNode> fog_;
    std::weak_ptr<ShadowNode> shadow_;
};

} // namespace sgfx

#pragma once
/// @file
/// Cascaded and spot shadow-map arithmetic on the CPU, no GL: splits, slice spheres, the light's
/// rotation, texel snapping, cascade selection, bias, PCSS widths. The shadow GLSL repeats the
/// per-fragment parts (selection, bias, PCSS); tests check it against this mirror.
/// Formulas: docs/plans/shadows.md §5. Doubles wherever a value feeds the texel grid.
#include <glm/glm.hpp>

#include <array>
#include <vector>

namespace sgfx::shadow {

inline constexpr int kMaxCascades = 4;

/// Split depths C_0..C_N of the practical split scheme (Zhang et al. 2006, "Parallel-Split Shadow
/// Maps"): C_i = λ·n·(f/n)^(i/N) + (1 − λ)·(n + (f − n)·i/N), so C_0 = n and C_N = f. Throws
/// std::invalid_argument naming the parameter unless 0 < near < far (finite), N in 1..4, λ in [0, 1].
std::vector<double> practicalSplits(double near, double far, int cascades, double lambda);

/// Start of cascade k's slice (k = 0..N−1): C_k − β·(C_k − C_{k−1}), and n for k = 0. It reaches
/// back over the previous cascade's blend band, so band points lie inside both spheres.
double sliceStart(const std::vector<double>& splits, int cascade, double blendBand);

/// A bounding sphere of a view-frustum slice: its centre lies `centreDistance` along the camera's
/// forward axis from the eye (perspective) or from the camera plane (ortho).
struct SliceSphere {
    double centreDistance = 0.0;
    double radius = 0.0;
};

/// Perspective slice [a, b] of a camera with vertical fov `fovy` (radians) and `aspect` = w/h.
/// k² = tan²(fovx/2) + tan²(fovy/2); z* = min(b, (a + b)(1 + k²)/2); r = √((b − z*)² + b²k²): the
/// centre is equidistant from the near and far corners (or at the far plane when that is nearer),
/// and r depends only on (a, b, fovy, aspect), so it is constant while the camera moves or turns.
SliceSphere perspectiveSliceSphere(double fovy, double aspect, double a, double b);

/// Ortho slice [a, b] with half extents (halfWidth, halfHeight): the box's half-diagonal.
SliceSphere orthoSliceSphere(double halfWidth, double halfHeight, double a, double b);

/// World-to-light rotation V_L for `towardsLight` (need not be unit): rows right, up, L, so the
/// light looks along −L (forward −Z in light space, like a camera). Up is +Z, or +X when
/// |L·Z| > 0.99. A rotation only: the texel grid stays fixed in the world for one sun direction.
glm::dmat3 lightRotation(const glm::dvec3& towardsLight);

/// Texels of margin m = ⌈R_k + 1⌉ for a PCF disc of radius R_k texels, ⌈maxPenumbra/2⌉ + 1 for
/// PCSS: every tap stays inside its atlas tile, so the atlas needs no border.
int marginTexels(double kernelRadiusTexels);
int pcssMarginTexels(double maxPenumbraTexels);

/// A cascade fitted to its sphere in light space: ortho box centre.xy ± halfExtent, texel size.
struct CascadeFit {
    glm::dvec2 centre{0.0};  ///< snapped (or not) sphere centre in light space, x and y
    double halfExtent = 0.0; ///< r' = r·S/(S − 2m)
    double texel = 0.0;      ///< t = 2r'/S, metres
};

/// r' = r·S/(S − 2m): the sphere plus m texels each side fills the S-texel tile.
double marginRadius(double radius, int mapSize, int marginTexels);
/// t = 2r'/S.
double texelSize(double halfExtent, int mapSize);
/// c' = t·⌊c/t + ½⌋ per component: the box moves in whole texels, so edges do not shimmer.
glm::dvec2 snapToTexels(const glm::dvec2& c, double texel);
/// The whole fit for a sphere (world centre, radius) under rotation V_L.
CascadeFit fitCascade(const glm::dmat3& lightRotation, const glm::dvec3& worldCentre, double radius,
                      int mapSize, int marginTexels, bool snap = true);

/// The light-space orthographic projection of a fitted cascade: x and y over centre ± halfExtent,
/// light-space z (along L, towards the light) over [zMin, zMax], zMax mapping to depth 0.
glm::dmat4 cascadeProjection(const CascadeFit& fit, double zMin, double zMax);

/// Where each map lies in the shadow atlas: tiles of tileSize² in rows of at most
/// maxSize / tileSize, so the atlas stays within GL_MAX_TEXTURE_SIZE.
struct AtlasLayout {
    glm::ivec2 size{0};            ///< atlas texels
    std::vector<glm::ivec4> tiles; ///< x, y, width, height in texels
};
/// Throws std::invalid_argument when a tile does not fit (tileSize > maxSize) or count < 1.
AtlasLayout atlasLayout(int count, int tileSize, int maxSize);

/// World to atlas: xy the atlas coordinates in [0, 1] of the tile's part, z the depth in [0, 1]
/// (the shadow map's), for a tile under `projection` after `rotation` (V_L).
glm::dmat4 atlasMatrix(const glm::ivec4& tile, const glm::ivec2& atlasSize, const glm::dmat4& projection,
                       const glm::dmat3& rotation);

/// The PCF disc: 16 points in the unit disc. The first 4 are the early-out probes, at radius 0.95
/// on the diagonals; the other 12 are Mitchell's best-candidate points (fixed seed) farthest from
/// those before them, so the set is well spread (tests check the spacing).
inline constexpr int kPoissonTaps = 16;
const std::array<glm::dvec2, kPoissonTaps>& poissonDisc();

/// Hermite smoothstep, as GLSL: 0 below e0, 1 above e1 (a step at e0 when e0 == e1).
double smoothstep(double e0, double e1, double x);

/// Which cascade shades view depth z, and how: v = mix(mix(v_i, v_{i+1}, blend), 1, fade).
/// cascade == N (no map) beyond the far split, with fade 1.
struct CascadeSelection {
    int cascade = 0;
    double blend = 0.0; ///< weight of cascade i + 1, smoothstep over the last β of cascade i
    double fade = 0.0;  ///< weight of "lit", smoothstep over the last φ of the last cascade
};
CascadeSelection selectCascade(const std::vector<double>& splits, double viewDepth, double blendBand,
                               double fadeBand);
/// The same as weights per cascade, plus the "lit" weight last (index N); they sum to 1.
std::array<double, kMaxCascades + 1> cascadeWeights(const std::vector<double>& splits, double viewDepth,
                                                    double blendBand, double fadeBand);

/// Receiver-side depth bias along L (metres): b = t·(c_b + s_b·R·min(tan θ, M)), R = max(R_k, 1),
/// cos θ = N_g·L. Back-facing or grazing receivers (cos θ ≤ 0) take the full slope M.
double receiverBias(double texel, double cosTheta, double constantBias, double slopeBias,
                    double kernelRadiusTexels, double maxSlope);
/// Normal offset distance (Holbert 2011): P' = P + N_g·δ, δ = n_o·t·(R + ½)·sin θ.
double normalOffset(double texel, double cosTheta, double normalOffsetScale, double kernelRadiusTexels);

/// PCSS (Fernando 2005, "Percentage-Closer Soft Shadows"), distances along the light's axis.
/// Sun of angular radius α (w_light/d_b → 2·tan α for a light at infinity):
/// search w_s = min((d_r − d_near)·tan α, maxPenumbra·t); penumbra w_p = 2(d_r − d_b)·tan α.
double sunSearchWidth(double receiverDepth, double nearDepth, double angularRadius, double maxPenumbraTexels,
                      double texel);
double sunPenumbraWidth(double receiverDepth, double blockerDepth, double angularRadius);
/// Filter radius ρ = max(w_p/2, R_k·t): never sharper than the PCF disc.
double pcssFilterRadius(double penumbraWidth, double kernelRadiusTexels, double texel);
/// Spot of source radius w_l, linear depths from the light (similar triangles): search radius
/// w_s = w_l(d_r − n)/d_r; full penumbra width w_p = 2(d_r − d_b)·w_l/d_b, like the sun's. The
/// plan's (d_r − d_b)·w_l/d_b is its half, the filter radius ρ (w_l being a radius, not a width).
double spotSearchWidth(double sourceRadius, double receiverDepth, double nearDepth);
double spotPenumbraWidth(double sourceRadius, double receiverDepth, double blockerDepth);

/// Spot projection: vertical fov 2·outer + margin (radians), aspect 1; view = lookAt(position,
/// position + axis) with the up rule of lightRotation.
double spotFovy(double outerAngle, double marginAngle);
glm::dmat4 spotView(const glm::dvec3& position, const glm::dvec3& axis);
glm::dmat4 spotProjection(double fovy, double near, double far);
/// World size of one spot-map texel at linear depth d: 2d·tan(fovy/2)/S.
double spotTexelSize(double depth, double fovy, int mapSize);

} // namespace sgfx::shadow

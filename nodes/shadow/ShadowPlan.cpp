#include "ShadowPlan.h"

#include <sgfx/Camera.h>
#include <sgfx/Drawable.h>
#include <sgfx/FrameSetup.h>
#include <sgfx/ShaderComposer.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace sgfx::shadow {

namespace {

// Atlases stay within what GL 4.5 guarantees for a texture side (llvmpipe: 16384 too).
constexpr int kMaxAtlasSize = 16384;

// The camera's depth range the cascades cover, and where each slice's sphere lies.
struct CameraSlices {
    double near = 0.1, far = 1.0;
    glm::dmat4 cameraToWorld{1.0};
    bool perspective = true;
    double fovy = 0.8, aspect = 1.0;             // perspective
    glm::dvec2 orthoCentre{0.0}, orthoHalf{1.0}; // orthographic, camera space

    SliceSphere sphere(double a, double b) const {
        return perspective ? perspectiveSliceSphere(fovy, aspect, a, b)
                           : orthoSliceSphere(orthoHalf.x, orthoHalf.y, a, b);
    }
    glm::dvec3 centre(const SliceSphere& s) const {
        const glm::dvec2 xy = perspective ? glm::dvec2(0.0) : orthoCentre;
        return glm::dvec3(cameraToWorld * glm::dvec4(xy, -s.centreDistance, 1.0));
    }
};

// The nominal planes (not the ones fitted to this frame's content), so cascades depend on the
// camera alone.
CameraSlices cameraSlices(const ViewInfo& v, double maxDistance) {
    CameraSlices c;
    c.cameraToWorld = glm::inverse(glm::dmat4(v.view));
    c.perspective = v.perspective;
    if (v.perspective) {
        c.near = v.nominalNear;
        c.far = v.nominalFar;
        c.fovy = glm::radians(double(v.fovy));
        c.aspect = v.aspect;
    } else {
        // glm::ortho: P22 = −2/(f − n), P32 = −(f + n)/(f − n); P00 = 2/(r − l), P30 = −(r + l)/(r − l).
        const glm::dmat4 p(v.projection);
        c.near = (p[3][2] + 1.0) / p[2][2];
        c.far = (p[3][2] - 1.0) / p[2][2];
        c.orthoHalf = {1.0 / p[0][0], 1.0 / p[1][1]};
        c.orthoCentre = {-p[3][0] / p[0][0], -p[3][1] / p[1][1]};
    }
    // The split scheme needs 0 < n < f (an ortho camera may start at or behind its plane).
    c.near = std::max(c.near, 1e-3);
    c.far = std::min(c.far, maxDistance);
    if (!(c.far > c.near)) c.far = c.near * 2.0;
    return c;
}

int sunIndex(const RenderQueue& queue, const Light* sun) {
    for (std::size_t i = 0; sun && i < queue.lights.size(); ++i) {
        const LightInfo& l = queue.lights[i];
        if (l.source == sun && l.vector.w == 0.0f && glm::any(glm::greaterThan(l.color, glm::vec3(0.0f))))
            return int(i);
    }
    return -1;
}

// The tile's atlas rectangle half a texel in, so bilinear taps never read a neighbour.
glm::vec4 tileRect(const glm::ivec4& t, const glm::ivec2& atlas) {
    const glm::vec2 a(atlas);
    return {(float(t.x) + 0.5f) / a.x, (float(t.y) + 0.5f) / a.y, (float(t.x + t.z) - 0.5f) / a.x,
            (float(t.y + t.w) - 0.5f) / a.y};
}

bool casts(const RenderItem& item, const ShadowOptions& o) {
    if (item.drawable) return o.drawablesCast && !item.drawable->background();
    return true;
}

// What a cull from a light found that casts: opaque items (alpha-masked ones as cut-outs),
// transmissive ones when asked, and blended ones when asked, drawn as cut-outs at
// blendedCasterAlpha (FeatureAlphaMask added, PassCommands::blendedCasters).
std::vector<RenderItem> castingItems(const RenderQueue& q, const ShadowOptions& o) {
    std::vector<RenderItem> out;
    for (const RenderItem& item : q.opaque)
        if (casts(item, o)) out.push_back(item);
    if (o.transmissiveCast)
        for (const RenderItem& item : q.transmissive)
            if (casts(item, o)) out.push_back(item);
    if (o.blendedCasterAlpha)
        for (const auto* list : {&q.transparent, &q.claimed})
            for (const RenderItem& item : *list)
                if (casts(item, o) && item.faces != RenderItem::Faces::Back) {
                    out.push_back(item);
                    out.back().features |= FeatureAlphaMask;
                    out.back().faces = RenderItem::Faces::AsState;
                }
    return out;
}

// Each cascade's casters: the items whose bound, in light space, overlaps its square.
void splitCasters(ShadowNode::Plan& plan, const std::vector<CascadeFit>& fits, const glm::dmat3& rotation,
                  const ShadowOptions& o) {
    plan.casters.assign(fits.size(), {});
    for (const RenderItem& item : castingItems(plan.casterQueue, o)) {
        const BoundingSphere b = item.worldBound();
        if (!b.valid()) continue;
        const glm::dvec3 c = rotation * glm::dvec3(b.center);
        for (std::size_t i = 0; i < fits.size(); ++i) {
            const double reach = fits[i].halfExtent + double(b.radius);
            if (std::abs(c.x - fits[i].centre.x) <= reach && std::abs(c.y - fits[i].centre.y) <= reach)
                plan.casters[i].push_back(item);
        }
    }
}

// Plan §5: practical splits, a sphere per slice, texel-snapped fits under V_L, the node's bound
// for the depth range; one cull from the light over the union of the cascades' boxes. The
// cascades' tiles are the atlas's first `cascades` ones.
void fitSun(const FrameSetup& f, const ShadowNode& node, int sun, const BoundingSphere& bound,
            ShadowNode::Plan& plan) {
    const ShadowOptions& o = node.options();
    const glm::dvec3 L = glm::normalize(glm::dvec3(f.queue().lights[std::size_t(sun)].vector));
    const CameraSlices cam = cameraSlices(f.view(), o.maxDistance);
    const int n = o.cascades;
    const std::vector<double> splits = practicalSplits(cam.near, cam.far, n, o.splitLambda);
    const double kernel = o.filter == ShadowFilter::Hard2x2 ? 1.0 : double(o.pcfRadius);
    const int margin =
        o.filter == ShadowFilter::Pcss ? pcssMarginTexels(o.maxPenumbraTexels) : marginTexels(kernel);
    const glm::dmat3 rotation = lightRotation(L);
    const double zc = glm::dot(L, glm::dvec3(bound.center)), zr = double(bound.radius) * 1.001;
    plan.rotation = glm::mat3(rotation);
    plan.lightView = glm::mat4(glm::dmat4(rotation));
    plan.light = glm::vec4(glm::vec3(L), float(1.0 / (2.0 * zr)));
    std::vector<CascadeFit> fits;
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    for (int i = 0; i < n; ++i) {
        const auto k = std::size_t(i);
        const SliceSphere s = cam.sphere(sliceStart(splits, i, o.blendBand), splits[k + 1]);
        const CascadeFit fit =
            fitCascade(rotation, cam.centre(s), s.radius, o.mapSize, margin, o.snapToTexels);
        fits.push_back(fit);
        lo = glm::min(lo, fit.centre - fit.halfExtent);
        hi = glm::max(hi, fit.centre + fit.halfExtent);
        const glm::dmat4 projection = cascadeProjection(fit, zc - zr, zc + zr);
        plan.projections.push_back(glm::mat4(projection));
        // The tile's orthographic map of light space: a scale and an offset per axis.
        const glm::dmat4 toAtlas = atlasMatrix(plan.tiles[k], plan.atlasSize, projection, glm::dmat3(1.0));
        plan.cascadeMaps[k] = glm::vec4(toAtlas[0][0], toAtlas[1][1], toAtlas[3][0], toAtlas[3][1]);
        plan.depthMap = glm::vec2(toAtlas[2][2], toAtlas[3][2]);
        plan.tileRects[k] = tileRect(plan.tiles[k], plan.atlasSize);
        const double end = splits[k + 1], start = splits[k];
        plan.splits[i] = float(end);
        plan.bandStart[i] = float(end - (i + 1 < n ? o.blendBand : o.fadeBand) * (end - start));
        plan.texels[i] = float(fit.texel);
        plan.info.radii.push_back(fit.halfExtent);
        plan.info.texels.push_back(fit.texel);
    }
    // One cull over the union of the cascades' boxes (same V_L), split per cascade after.
    const glm::dmat4 cullBox = glm::ortho(lo.x, hi.x, lo.y, hi.y, -(zc + zr), -(zc - zr));
    f.cullForLight(node, LightCull{plan.lightView, glm::mat4(cullBox), o.castMask}, plan.casterQueue);
    splitCasters(plan, fits, rotation, o);
    plan.info.active = true;
    plan.info.splits = splits;
    for (const auto& c : plan.casters)
        plan.info.casters.push_back(c.size());
}

// A spot's perspective map (plan §5): from its position along its axis, the cone plus the
// filter's margin in texels (cones beyond 80° are cut there), near spotNear, far its range or the
// far side of the node's bound; its casters culled through that frustum.
void fitSpot(const FrameSetup& f, const ShadowNode& node, int light, const BoundingSphere& bound,
             const glm::ivec4& tile, ShadowNode::Plan& plan) {
    const ShadowOptions& o = node.options();
    const LightInfo& info = f.queue().lights[std::size_t(light)];
    ShadowNode::SpotPlan spot;
    spot.light = light;
    const glm::dvec3 pos(info.vector), axis = glm::normalize(glm::dvec3(info.spotAxis));
    const double outer = std::min(double(info.source->outerConeAngle), glm::radians(80.0));
    const int S = tile.z,
              m = o.filter == ShadowFilter::Hard2x2 ? marginTexels(1.0) : marginTexels(o.pcfRadius);
    const double fovy = 2.0 * std::atan(std::tan(outer) * S / double(S - 2 * m));
    const double near = o.spotNear;
    const double far = std::max(
        info.range > 0.0f ? double(info.range) : glm::distance(pos, glm::dvec3(bound.center)) + bound.radius,
        near * 2.0);
    const glm::dmat4 view = spotView(pos, axis), projection = spotProjection(fovy, near, far);
    spot.view = glm::mat4(view);
    spot.projection = glm::mat4(projection);
    spot.matrix = glm::mat4(atlasMatrix(tile, plan.atlasSize, projection * view, glm::dmat3(1.0)));
    spot.tileRect = tileRect(tile, plan.atlasSize);
    spot.position = glm::vec4(glm::vec3(pos), 1.0f);
    spot.axis = glm::vec4(glm::vec3(axis), 0.0f);
    spot.params = glm::vec4(float(near), float(far), float(2.0 * std::tan(fovy / 2.0) / S), 0.0f);
    f.cullForLight(node, LightCull{spot.view, spot.projection, o.castMask}, spot.queue);
    spot.casters = castingItems(spot.queue, o);
    plan.spots.push_back(std::move(spot));
}

int spotIndex(const RenderQueue& queue, const Light* spot) {
    for (std::size_t i = 0; i < queue.lights.size(); ++i) {
        const LightInfo& l = queue.lights[i];
        if (l.source == spot && l.vector.w == 1.0f && glm::any(glm::greaterThan(l.color, glm::vec3(0.0f))))
            return int(i);
    }
    return -1;
}

} // namespace

// The sun's cascades in the atlas's first row, the spots' maps in the second.
std::shared_ptr<ShadowNode::Plan> planShadows(const FrameSetup& f, const ShadowNode& node) {
    auto plan = std::make_shared<ShadowNode::Plan>();
    const ShadowOptions& o = node.options();
    const BoundingSphere bound = f.worldBound(node);
    if (!bound.valid() || !(bound.radius > 0.0f)) return plan;
    const int sun = sunIndex(f.queue(), node.sun().get());
    plan->info.sunLight = sun;
    std::vector<int> spots;
    for (const auto& light : node.spots())
        if (const int i = spotIndex(f.queue(), light.get()); i >= 0) spots.push_back(i);
    const int cascades = sun >= 0 ? o.cascades : 0, spotCount = int(spots.size());
    if (cascades + spotCount == 0) return plan;
    const int rowSun = cascades ? o.mapSize : 0, rowSpots = spotCount ? o.spotMapSize : 0;
    plan->atlasSize =
        glm::ivec2(std::max(cascades * o.mapSize, spotCount * o.spotMapSize), rowSun + rowSpots);
    if (plan->atlasSize.x > kMaxAtlasSize)
        throw std::invalid_argument("sgfx: ShadowNode '" + node.name + "': " + std::to_string(cascades) +
                                    " cascades of " + std::to_string(o.mapSize) + " texels exceed a " +
                                    std::to_string(kMaxAtlasSize) + "-texel atlas");
    plan->tiles.clear();
    for (int i = 0; i < cascades; ++i)
        plan->tiles.emplace_back(i * o.mapSize, 0, o.mapSize, o.mapSize);
    for (int j = 0; j < spotCount; ++j)
        plan->tiles.emplace_back(j * o.spotMapSize, rowSun, o.spotMapSize, o.spotMapSize);
    if (sun >= 0) fitSun(f, node, sun, bound, *plan);
    for (int j = 0; j < spotCount; ++j)
        fitSpot(f, node, spots[std::size_t(j)], bound, plan->tiles[std::size_t(cascades + j)], *plan);
    return plan;
}

} // namespace sgfx::shadow

#include <sgfx/nodes/shadow/ShadowNode.h>

#include "ParameterChecks.h"
#include "ShadowPlan.h"

#include <sgfx/Camera.h>
#include <sgfx/FrameSetup.h>
#include <sgfx/PassCommands.h>
#include <sgfx/RenderQueue.h>
#include <sgfx/Renderer.h>
#include <sgfx/gl/Objects.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {

constexpr std::string_view kOwner = "ShadowOptions";
void checkRange(const char* name, float v, double lo, double hi, bool openLow = false) {
    nodes::checkRange(kOwner, name, v, lo, hi, openLow);
}

// The PCF disc as a GLSL constant, from the one table ShadowMath keeps.
std::string discConstant() {
    std::string s = "const vec2 sgfx_shadowDisc[16] = vec2[16](";
    const auto& disc = shadow::poissonDisc();
    for (std::size_t k = 0; k < disc.size(); ++k) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%svec2(%.9f, %.9f)", k ? ", " : "", disc[k].x, disc[k].y);
        s += buf;
    }
    return s + ");\n";
}

} // namespace

void ShadowOptions::validate() const {
    if (cascades < 1 || cascades > shadow::kMaxCascades)
        nodes::refuse(kOwner, "cascades = " + std::to_string(cascades) + " is outside [1, 4]");
    if (mapSize < 256 || mapSize > 4096 || mapSize % 64 != 0)
        nodes::refuse(kOwner,
                      "mapSize = " + std::to_string(mapSize) + " must be a multiple of 64 in [256, 4096]");
    checkRange("maxDistance", maxDistance, 0.0, 1e6, true);
    checkRange("splitLambda", splitLambda, 0.0, 1.0);
    checkRange("blendBand", blendBand, 0.0, 0.5);
    checkRange("fadeBand", fadeBand, 0.0, 0.5);
    if (std::uint8_t(filter) > std::uint8_t(ShadowFilter::Pcss))
        nodes::refuse(kOwner, "filter has an invalid value " + std::to_string(int(filter)));
    checkRange("pcfRadius", pcfRadius, 0.5, 8.0);
    checkRange("lightAngularRadius", lightAngularRadius, 0.0, 0.2);
    checkRange("maxPenumbraTexels", maxPenumbraTexels, 1.0, 32.0);
    checkRange("constantBias", constantBias, 0.0, 16.0);
    checkRange("slopeBias", slopeBias, 0.0, 16.0);
    checkRange("maxSlope", maxSlope, 0.0, 100.0);
    checkRange("normalOffset", normalOffset, 0.0, 16.0);
    checkRange("density", density, 0.0, 1.0);
    if (blendedCasterAlpha) checkRange("blendedCasterAlpha", *blendedCasterAlpha, 0.0, 1.0, true);
    if (spotMapSize < 128 || spotMapSize > 4096 || spotMapSize % 64 != 0)
        nodes::refuse(kOwner, "spotMapSize = " + std::to_string(spotMapSize) +
                                  " must be a multiple of 64 in [128, 4096]");
    checkRange("spotNear", spotNear, 0.0, 100.0, true);
    if (castMask == 0) nodes::refuse(kOwner, "castMask is 0: nothing could cast");
    if (receiveMask == 0) nodes::refuse(kOwner, "receiveMask is 0: nothing could receive");
    if (std::uint8_t(debugView) > std::uint8_t(ShadowDebugView::Cascades))
        nodes::refuse(kOwner, "debugView has an invalid value " + std::to_string(int(debugView)));
}

// ------------------------------------------------------------------------------ node

std::shared_ptr<ShadowNode> ShadowNode::create(std::shared_ptr<Light> sun, const ShadowOptions& options) {
    auto n = std::make_shared<ShadowNode>();
    n->setOptions(options);
    n->setSun(std::move(sun));
    return n;
}

ShadowNode::ShadowNode()
    : shared_(std::make_shared<Shared>()) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "shadow.atlas@%p", static_cast<const void*>(this));
    atlasName_ = buf;
    rebuildSnippet();
}

ShadowNode::~ShadowNode() = default;

void ShadowNode::setSun(std::shared_ptr<Light> sun) {
    if (sun && sun->type != LightType::Directional)
        throw std::invalid_argument("sgfx: ShadowNode '" + name + "': setSun needs a Directional light; '" +
                                    sun->name + "' is not one");
    sun_ = std::move(sun);
}

void ShadowNode::addSpot(std::shared_ptr<Light> spot) {
    if (!spot || spot->type != LightType::Spot)
        throw std::invalid_argument("sgfx: ShadowNode '" + name + "': addSpot needs a Spot light" +
                                    (spot ? "; '" + spot->name + "' is not one" : ""));
    if (spots_.size() >= 3)
        throw std::invalid_argument("sgfx: ShadowNode '" + name + "': at most 3 spot lights; '" + spot->name +
                                    "' would be the fourth");
    if (std::find(spots_.begin(), spots_.end(), spot) == spots_.end()) spots_.push_back(std::move(spot));
    rebuildSnippet(); // the variant with spots
}

bool ShadowNode::removeSpot(const Light* spot) {
    const bool removed = std::erase_if(spots_, [&](const auto& s) { return s.get() == spot; }) > 0;
    rebuildSnippet();
    return removed;
}

void ShadowNode::setOptions(const ShadowOptions& options) {
    options.validate();
    options_ = options;
    rebuildSnippet();
}

ShadowFrameInfo ShadowNode::lastFrame() const {
    return shared_->current ? shared_->current->info : ShadowFrameInfo{};
}

void ShadowNode::rebuildSnippet() {
    const bool debug = options_.debugView == ShadowDebugView::Cascades;
    static constexpr const char* kFilters[] = {"hard", "pcf", "pcss"};
    const char* filter = kFilters[std::size_t(options_.filter)];
    ShaderSnippet s;
    const bool spots = !spots_.empty();
    s.name = std::string("shadow_") + filter + (spots ? "_spots" : "") + (debug ? "_debug" : "");
    s.defines = "#define SGFX_LIGHT_VISIBILITY 1\n#define SGFX_SHADOW_SUN 1\n#define SGFX_SHADOW_FILTER " +
                std::to_string(int(options_.filter)) + "\n" + (spots ? "#define SGFX_SHADOW_SPOTS 1\n" : "");
    SnippetSampler map;
    map.uniform = "sgfx_shadowMap";
    map.resource = atlasName_;
    map.comparison = true;
    s.samplers = {map};
    if (options_.filter == ShadowFilter::Pcss) s.samplers.push_back({"sgfx_shadowDepth", atlasName_});
    // Hard: its function; PCF: the disc and its function; PCSS: both, and its own.
    s.fragmentDecl =
        nodes::shaderText("shadow_decl.glsl") + nodes::shaderText("shadow_hard.glsl") +
        (options_.filter == ShadowFilter::Hard2x2 ? ""
                                                  : discConstant() + nodes::shaderText("shadow_pcf.glsl")) +
        (options_.filter == ShadowFilter::Pcss ? nodes::shaderText("shadow_pcss.glsl") : "") +
        nodes::shaderText("shadow_visibility.glsl");
    if (debug) s.colorCode = nodes::shaderText("shadow_debug.glsl");
    snippet_ = std::move(s);
}

void ShadowNode::setupFrame(FrameSetup& f) const {
    if (!f.once(atlasName_)) return;
    addPasses(f, shadow::planShadows(f, *this));
}

// A pass per cascade and per spot into its tile of the atlas: the casters' depth seen from the
// light. Without a light the one pass clears a 1×1 atlas that the materials bind and never read.
void ShadowNode::addPasses(FrameSetup& f, const std::shared_ptr<const Plan>& plan) const {
    struct Data {
        ResourceId atlas;
    };
    const TextureDesc desc{.format = format::Depth32F,
                           .size = SizeRule::fixedSize(plan->atlasSize.x, plan->atlasSize.y)};
    const int cascades = int(plan->casters.size());
    const int passes = std::max(1, cascades + int(plan->spots.size()));
    for (int i = 0; i < passes; ++i) {
        const bool spot = i >= cascades && !plan->spots.empty();
        std::string pass =
            spot ? "shadow: spot " + std::to_string(i - cascades) : "shadow: cascade " + std::to_string(i);
        f.addPass<Data>(
            std::move(pass), PassPhase::BeforeMain,
            [i, desc, atlas = atlasName_](PassBuilder& b, Data& d) {
                d.atlas = i == 0 ? b.depth(b.create(atlas, desc), false) : b.depth(b.get(atlas), true);
                b.publish(atlas, d.atlas);
            },
            [i, cascades, spot, plan, shared = shared_, cutoff = options_.blendedCasterAlpha](PassCommands& c,
                                                                                              const Data& d) {
                if (i == 0) shared->current = plan;
                if (cutoff) c.blendedCasters(*cutoff);
                const glm::ivec4 tile = plan->tiles[std::size_t(i)];
                c.target({}, d.atlas);
                // The whole atlas at once: llvmpipe clears whole tiles fast and a scissored
                // rectangle pixel by pixel. The later passes keep it.
                if (i == 0) c.clearDepth();
                c.viewport(tile);
                c.scissor(tile);
                if (spot) {
                    const SpotPlan& s = plan->spots[std::size_t(i - cascades)];
                    c.setView(s.view, s.projection);
                    c.drawQueue(s.casters, DrawMode::DepthOnly);
                } else if (plan->info.active) {
                    c.setView(plan->lightView, plan->projections[std::size_t(i)]);
                    c.drawQueue(plan->casters[std::size_t(i)], DrawMode::DepthOnly);
                }
            });
    }
}

void ShadowNode::applyUniforms(gl::Program& program, const DrawContext&) const {
    static const std::array<std::string, shadow::kMaxCascades> map = {
        "sgfx_shadowCascadeMap[0]", "sgfx_shadowCascadeMap[1]", "sgfx_shadowCascadeMap[2]",
        "sgfx_shadowCascadeMap[3]"};
    static const std::array<std::string, shadow::kMaxCascades> tile = {
        "sgfx_shadowTile[0]", "sgfx_shadowTile[1]", "sgfx_shadowTile[2]", "sgfx_shadowTile[3]"};
    const Plan* plan = shared_->current.get();
    const bool active = plan && plan->info.active;
    const int cascades = active ? int(plan->casters.size()) : 0;
    program.setInt4("sgfx_shadowSun",
                    glm::ivec4(active ? plan->info.sunLight : -1, cascades, options_.pcfEarlyOut ? 1 : 0, 0));
    glm::ivec4 spots(-1);
    if (plan) applySpotUniforms(program, *plan, spots);
    program.setInt4("sgfx_shadowSpots", spots);
    if (plan) applyCommonUniforms(program, *plan);
    if (!active) return;
    for (int i = 0; i < cascades; ++i) {
        program.set(map[std::size_t(i)], plan->cascadeMaps[std::size_t(i)]);
        program.set(tile[std::size_t(i)], plan->tileRects[std::size_t(i)]);
    }
    program.set("sgfx_shadowSplits", plan->splits);
    program.set("sgfx_shadowBandStart", plan->bandStart);
    program.set("sgfx_shadowTexel", plan->texels);
    program.set("sgfx_shadowLight", plan->light);
    program.set("sgfx_shadowDepthMap", plan->depthMap);
}

void ShadowNode::applySpotUniforms(gl::Program& program, const Plan& plan, glm::ivec4& slots) const {
    static const std::array<std::string, 3> matrix = {"sgfx_shadowSpotMatrix[0]", "sgfx_shadowSpotMatrix[1]",
                                                      "sgfx_shadowSpotMatrix[2]"};
    static const std::array<std::string, 3> tile = {"sgfx_shadowSpotTile[0]", "sgfx_shadowSpotTile[1]",
                                                    "sgfx_shadowSpotTile[2]"};
    static const std::array<std::string, 3> pos = {"sgfx_shadowSpotPos[0]", "sgfx_shadowSpotPos[1]",
                                                   "sgfx_shadowSpotPos[2]"};
    static const std::array<std::string, 3> axis = {"sgfx_shadowSpotAxis[0]", "sgfx_shadowSpotAxis[1]",
                                                    "sgfx_shadowSpotAxis[2]"};
    static const std::array<std::string, 3> params = {"sgfx_shadowSpot[0]", "sgfx_shadowSpot[1]",
                                                      "sgfx_shadowSpot[2]"};
    for (std::size_t j = 0; j < plan.spots.size() && j < 3; ++j) {
        const SpotPlan& s = plan.spots[j];
        slots[int(j)] = s.light;
        program.set(matrix[j], s.matrix);
        program.set(tile[j], s.tileRect);
        program.set(pos[j], s.position);
        program.set(axis[j], s.axis);
        program.set(params[j], s.params);
    }
}

// What every light's lookup reads: bias, filter, the disc's rotation frame.
void ShadowNode::applyCommonUniforms(gl::Program& program, const Plan& plan) const {
    program.set("sgfx_shadowRotation", plan.rotation);
    program.set("sgfx_shadowBias", glm::vec4(options_.constantBias, options_.slopeBias, options_.maxSlope,
                                             options_.normalOffset));
    const float radius = options_.filter == ShadowFilter::Hard2x2 ? 1.0f : options_.pcfRadius;
    if (options_.filter == ShadowFilter::Pcss)
        program.set("sgfx_shadowPcssParams", glm::vec4(std::tan(options_.lightAngularRadius),
                                                       options_.maxPenumbraTexels / 2.0f, 0.0f, 0.0f));
    program.set("sgfx_shadowFilter", glm::vec4(radius, 1.0f / float(plan.atlasSize.x),
                                               1.0f / float(plan.atlasSize.y), options_.density));
}

} // namespace sgfx

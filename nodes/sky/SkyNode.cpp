#include <sgfx/nodes/sky/SkyNode.h>

#include "ParameterChecks.h"
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/shadow/ShadowNode.h>

#include <sgfx/Camera.h>

#include <sgfx/FrameSetup.h>
#include <sgfx/PassCommands.h>
#include <sgfx/Renderer.h>
#include <sgfx/StateSet.h>
#include <sgfx/Visitors.h>
#include <sgfx/gl/Objects.h>

#include <sgfx_glad/gl.h>

#include <cmath>
#include <cstdio>

namespace sgfx {

namespace {

void check(const char* name, float v, double lo, double hi, bool openLow = false) {
    nodes::checkRange("SkyParameters", name, v, lo, hi, openLow);
}

constexpr int kLutWidth = 256, kLutHeight = 128;

BaseShader makeSkyShader(bool lut) {
    std::string vertex =
        nodes::afterVersion(std::string(ShaderComposer::fullscreenVertex()), "#define SGFX_FULLSCREEN_FAR\n");
    std::string fragment = nodes::shaderWithIncludes("sky.frag");
    if (lut) fragment = nodes::afterVersion(std::move(fragment), "#define SGFX_SKY_LUT\n");
    return BaseShader{lut ? "sky_lut_view" : "sky", "blit.vert", std::move(vertex), "sky.frag",
                      std::move(fragment)};
}

const BaseShader& skyShader(bool lut) {
    static const BaseShader direct = makeSkyShader(false), table = makeSkyShader(true);
    return lut ? table : direct;
}

void setSkyUniforms(gl::Program& program, const SkyParameters& p, float eyeHeight) {
    const sky::Atmosphere& a = p.atmosphere;
    program.set("u_sunDirection", p.sunDirection);
    program.set("u_sunIntensity", p.sunIntensity);
    program.set("u_altitude", p.altitude + eyeHeight);
    program.set("u_planetRadius", a.planetRadius);
    program.set("u_atmosphereRadius", a.atmosphereRadius);
    program.set("u_rayleigh", a.rayleigh);
    program.set("u_rayleighHeight", a.rayleighHeight);
    program.set("u_mie", a.mie);
    program.set("u_mieHeight", a.mieHeight);
    program.set("u_mieG", a.mieG);
    program.set("u_mieExtinction", a.mieExtinction);
    program.set("u_steps", p.steps);
    program.set("u_lightSteps", p.lightSteps);
}

} // namespace

SkyParameters SkyParameters::atTime(float hours, float latitudeDegrees, int dayOfYear) {
    SkyParameters p;
    p.sunDirection = sky::sunDirection(hours, latitudeDegrees, dayOfYear);
    return p;
}

void SkyParameters::validate() const {
    for (int i = 0; i < 3; ++i)
        check("sunDirection", sunDirection[i], -1e6, 1e6);
    if (!(glm::length(sunDirection) > 0.0f)) nodes::refuse("SkyParameters", "sunDirection must not be zero");
    check("sunIntensity", sunIntensity, 0.0, 1e6);
    check("sunDiscRadiance", sunDiscRadiance, 0.0, 1e9);
    check("sunAngularRadius", sunAngularRadius, 0.0, 0.5);
    check("altitude", altitude, -1e4, 1e5);
    const sky::Atmosphere& a = atmosphere;
    check("atmosphere.planetRadius", a.planetRadius, 1.0, 1e9, true);
    check("atmosphere.atmosphereRadius", a.atmosphereRadius, a.planetRadius, 1e9, true);
    for (int i = 0; i < 3; ++i)
        check("atmosphere.rayleigh", a.rayleigh[i], 0.0, 1.0);
    check("atmosphere.rayleighHeight", a.rayleighHeight, 0.0, 1e6, true);
    check("atmosphere.mie", a.mie, 0.0, 1.0);
    check("atmosphere.mieHeight", a.mieHeight, 0.0, 1e6, true);
    check("atmosphere.mieG", a.mieG, -0.999, 0.999);
    check("atmosphere.mieExtinction", a.mieExtinction, 1.0, 10.0);
    if (steps < 1 || steps > 256)
        nodes::refuse("SkyParameters", "steps = " + std::to_string(steps) + " is outside [1, 256]");
    if (lightSteps < 1 || lightSteps > 64)
        nodes::refuse("SkyParameters", "lightSteps = " + std::to_string(lightSteps) + " is outside [1, 64]");
}

std::shared_ptr<SkyNode> SkyNode::create(const SkyParameters& p) {
    auto n = std::make_shared<SkyNode>(p);
    n->name = "sky";
    auto state = std::make_shared<StateSet>();
    // On the far plane: only where nothing was drawn (the depth buffer still holds 1).
    state->depth.set(DepthState{.test = true, .write = false, .func = CompareFunc::LessEqual});
    state->cullFace.set(CullFace::None);
    n->setStateSet(state);
    return n;
}

SkyNode::SkyNode(const SkyParameters& p) {
    setParameters(p);
}

void SkyNode::setParameters(const SkyParameters& p) {
    p.validate();
    parameters_ = p;
    parameters_.sunDirection = glm::normalize(p.sunDirection);
}

void SkyNode::attachFog(std::shared_ptr<FogNode> fog) {
    fog_ = fog;
}

glm::vec3 SkyNode::horizonColor() const {
    const SkyParameters& p = parameters_;
    glm::vec3 sum(0.0f);
    const float el = glm::radians(1.0f);
    for (int i = 0; i < 8; ++i) {
        const float az = float(i) * glm::radians(45.0f);
        const glm::vec3 dir(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
        sum += sky::skyRadiance(p.atmosphere, dir, p.sunDirection, p.sunIntensity, p.altitude, p.steps,
                                p.lightSteps);
    }
    return sum / 8.0f;
}

void SkyNode::attachShadow(std::shared_ptr<ShadowNode> shadow) {
    shadow_ = shadow;
}

void SkyNode::update(UpdateVisitor&) {
    if (auto shadow = shadow_.lock(); shadow && shadow->sun()) {
        Light& sun = *shadow->sun();
        sun.direction = -parameters_.sunDirection;
        sun.color = sky::sunTransmittance(parameters_.atmosphere, parameters_.sunDirection, parameters_.altitude);
        if (shadow->options().lightAngularRadius != parameters_.sunAngularRadius) { // PCSS's sun size
            ShadowOptions o = shadow->options();
            o.lightAngularRadius = std::min(parameters_.sunAngularRadius, 0.2f);
            shadow->setOptions(o);
        }
    }
    auto fog = fog_.lock();
    if (!fog) return;
    FogParameters fp = fog->parameters();
    fp.color = glm::min(horizonColor(), glm::vec3(1e6f));
    fp.sky = FogSky::Off;
    fog->setParameters(fp);
}

// The blackboard name of this node's sky-view table (several skies may be drawn in one view).
std::string SkyNode::tableName() const {
    char buf[48];
    std::snprintf(buf, sizeof buf, "sky.viewTable@%p", static_cast<const void*>(this));
    return buf;
}

// Fills the sky-view table for the view being drawn (before the main pass); the sky's draw reads it.
void SkyNode::setupFrame(FrameSetup& f) const {
    if (!parameters_.lookupTable || !f.once(tableName())) return;
    struct Data {
        ResourceId table;
    };
    const TextureDesc desc{.format = format::Rgba16F,
                           .size = SizeRule::fixedSize(kLutWidth, kLutHeight),
                           .filter = Filter::Linear,
                           .wrapS = Wrap::Repeat}; // azimuth wraps round
    f.addPass<Data>(
        "sky: view table", PassPhase::BeforeMain,
        [name = tableName(), desc](PassBuilder& b, Data& d) {
            d.table = b.colour(b.create(name, desc), 0, false);
            b.publish(name, d.table);
        },
        [p = parameters_](PassCommands& c, const Data& d) {
            static const BaseShader lutShader{"sky_lut", "blit.vert",
                                              std::string(ShaderComposer::fullscreenVertex()), "sky_lut.frag",
                                              nodes::shaderWithIncludes("sky_lut.frag")};
            gl::Program& program = c.program(lutShader);
            c.target({d.table});
            setSkyUniforms(program, p, c.frame().eye.z);
            c.fullscreen(program);
        });
    f.sampleInMainPass(tableName());
}

const BaseShader& SkyNode::baseShader() const {
    return skyShader(parameters_.lookupTable);
}

env::CubeImage SkyNode::renderEnvironment(Renderer& r, int size) const {
    if (size < 8 || size > 512 || (size & (size - 1)))
        throw std::invalid_argument("sgfx: SkyNode::renderEnvironment: size " + std::to_string(size) +
                                    " is not a power of two from 8 to 512");
    // A float strip of the six faces, read back for the CPU prefilter.
    gl::TextureObject strip = gl::createTexture2D(GL_RGBA32F, 6 * size, size);
    gl::FramebufferObject fbo = gl::createFramebuffer(strip);
    r.runCommands("sky: environment cube", [&](PassCommands& c) {
        static const BaseShader cubeShader{"sky_cube", "blit.vert",
                                           std::string(ShaderComposer::fullscreenVertex()), "sky_cube.frag",
                                           nodes::shaderWithIncludes("sky_cube.frag")};
        gl::Program& program = c.program(cubeShader);
        setSkyUniforms(program, parameters_, 0.0f);
        program.set("u_faceSize", size);
        r.beginOffscreen(fbo.get(), {6 * size, size});
        c.fullscreen(program);
        r.endOffscreen();
    });
    std::vector<float> texels(std::size_t(6) * size * size * 4);
    gl::readTexture(strip, 0, GL_RGBA, GL_FLOAT, texels.size() * sizeof(float), texels.data());
    env::CubeImage cube = env::CubeImage::filled(size, glm::vec3(0.0f));
    for (int f = 0; f < 6; ++f)
        for (int t = 0; t < size; ++t)
            for (int s = 0; s < size; ++s) {
                const float* p = &texels[(std::size_t(t) * 6 * size + std::size_t(f) * size + s) * 4];
                cube.texel(f, s, t) = glm::max(glm::vec3(p[0], p[1], p[2]), glm::vec3(0.0f));
            }
    return cube;
}

void SkyNode::draw(Renderer& r, gl::Program& program, const RenderItem&) const {
    const SkyParameters& p = parameters_;
    setSkyUniforms(program, p, r.frame().eye.z);
    if (p.lookupTable && r.bindFrameResource(program, "u_skyLut", tableName())) {
        program.set("u_sunTransmittance", sky::sunTransmittance(p.atmosphere, p.sunDirection,
                                                                p.altitude + r.frame().eye.z, p.steps));
    }
    program.set("u_sunCosRadius", std::cos(p.sunAngularRadius));
    program.set("u_sunDiscRadiance", p.sunDiscRadiance);
    r.drawFullscreen(program, DepthState{.test = true, .write = false, .func = CompareFunc::LessEqual});
}

} // namespace sgfx

#include <sgfx/nodes/environment/EnvironmentLightNode.h>

#include "EmbeddedShaders.h"

#include <sgfx/nodes/sky/SkyNode.h>

#include <sgfx/gl/Objects.h>

#include <optional>

#include <sgfx_glad/gl.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {
constexpr std::string_view kSpecular = "environment.specular";
constexpr std::string_view kBrdf = "environment.brdf";
constexpr int kBrdfSize = 32;

void checkCube(const env::CubeImage& c) {
    if (c.size < 8 || (c.size & (c.size - 1)))
        throw std::invalid_argument("sgfx: Environment: the cube's size " + std::to_string(c.size) +
                                    " is not a power of two of at least 8");
    for (std::size_t f = 0; f < 6; ++f) {
        if (c.faces[f].size() != std::size_t(c.size) * std::size_t(c.size))
            throw std::invalid_argument("sgfx: Environment: face " + std::to_string(f) + " holds " +
                                        std::to_string(c.faces[f].size()) + " texels, not " +
                                        std::to_string(c.size) + " x " + std::to_string(c.size));
        for (std::size_t i = 0; i < c.faces[f].size(); ++i) {
            const glm::vec3 v = c.faces[f][i];
            if (!std::isfinite(v.x + v.y + v.z) || glm::any(glm::lessThan(v, glm::vec3(0.0f))))
                throw std::invalid_argument("sgfx: Environment: face " + std::to_string(f) + " texel (" +
                                            std::to_string(i % std::size_t(c.size)) + ", " +
                                            std::to_string(i / std::size_t(c.size)) +
                                            ") is not a finite, non-negative radiance");
        }
    }
}

std::vector<glm::vec3> rgbOf(const FloatImage& image, int x0, int width) {
    std::vector<glm::vec3> out;
    out.reserve(std::size_t(width) * std::size_t(image.height));
    for (int y = 0; y < image.height; ++y)
        for (int x = x0; x < x0 + width; ++x) {
            const float* p = &image.rgba[(std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 4];
            out.emplace_back(p[0], p[1], p[2]);
        }
    return out;
}
} // namespace

// ------------------------------------------------------------------------------ environment

Environment::Environment(env::CubeImage radiance) {
    checkCube(radiance);
    irradiance_ = env::irradianceSh(radiance);
    specular_ = env::prefilterSpecular(radiance);
}

std::shared_ptr<const Environment> Environment::uniform(glm::vec3 radiance, int size) {
    return std::make_shared<const Environment>(env::CubeImage::filled(size, radiance));
}

std::shared_ptr<const Environment> Environment::fromCube(env::CubeImage radiance) {
    return std::make_shared<const Environment>(std::move(radiance));
}

std::shared_ptr<const Environment> Environment::fromEquirect(const FloatImage& panorama, int size) {
    if (panorama.width <= 0 || panorama.height <= 0 ||
        panorama.rgba.size() != std::size_t(panorama.width) * std::size_t(panorama.height) * 4)
        throw std::invalid_argument("sgfx: Environment::fromEquirect: the panorama is empty or inconsistent");
    return fromCube(
        env::cubeFromEquirect(rgbOf(panorama, 0, panorama.width), panorama.width, panorama.height, size));
}

std::shared_ptr<const Environment> Environment::load(const std::filesystem::path& file, int size) {
    const FloatImage image = readImageLinear(file);
    try {
        if (image.width == 2 * image.height) return fromEquirect(image, size);
        if (image.width == 6 * image.height) {
            env::CubeImage cube;
            cube.size = image.height;
            for (int f = 0; f < 6; ++f)
                cube.faces[std::size_t(f)] = rgbOf(image, f * image.height, image.height);
            return fromCube(std::move(cube));
        }
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error("sgfx: environment " + file.string() + ": " + e.what());
    }
    throw std::runtime_error("sgfx: environment " + file.string() + ": " + std::to_string(image.width) +
                             " x " + std::to_string(image.height) +
                             " is neither a 2:1 panorama nor a 6:1 strip of cube faces");
}

// ------------------------------------------------------------------------------ node

// The GL copies of one environment, remade when the node's environment changes.
struct EnvironmentLightNode::Gpu {
    std::shared_ptr<const Environment> uploaded; // kept alive: compared by address
    std::shared_ptr<const Environment> fromSky;  // the followed sky's, when rendered
    std::optional<SkyParameters> skyParameters;  // what fromSky was rendered from
    gl::TextureObject specular;
    gl::TextureObject brdf;
    int levels = 0;
};

std::shared_ptr<EnvironmentLightNode>
EnvironmentLightNode::create(std::shared_ptr<const Environment> environment, float intensity) {
    auto n = std::make_shared<EnvironmentLightNode>();
    n->setEnvironment(std::move(environment));
    n->setIntensity(intensity);
    return n;
}

EnvironmentLightNode::EnvironmentLightNode()
    : gpu_(std::make_unique<Gpu>()) {}

EnvironmentLightNode::~EnvironmentLightNode() = default;

std::shared_ptr<EnvironmentLightNode> EnvironmentLightNode::create(std::shared_ptr<const SkyNode> sky,
                                                                   float intensity) {
    if (!sky) throw std::invalid_argument("sgfx: EnvironmentLightNode: the sky is null");
    auto n = std::make_shared<EnvironmentLightNode>();
    n->followSky(std::move(sky));
    n->setIntensity(intensity);
    return n;
}

std::shared_ptr<const Environment> EnvironmentLightNode::environment() const {
    return sky_ && gpu_->fromSky ? gpu_->fromSky : environment_;
}

void EnvironmentLightNode::followSky(std::shared_ptr<const SkyNode> sky, int size) {
    if (size < 8 || size > 512 || (size & (size - 1)))
        throw std::invalid_argument("sgfx: EnvironmentLightNode::followSky: size " + std::to_string(size) +
                                    " is not a power of two from 8 to 512");
    if (sky == sky_ && size == skySize_) return;                     // already: nothing to render again
    if (!sky && sky_ && gpu_->fromSky) environment_ = gpu_->fromSky; // keep the last
    sky_ = std::move(sky);
    skySize_ = size;
    gpu_->skyParameters.reset();
}

void EnvironmentLightNode::setEnvironment(std::shared_ptr<const Environment> environment) {
    if (!environment) throw std::invalid_argument("sgfx: EnvironmentLightNode: the environment is null");
    environment_ = std::move(environment);
    sky_.reset(); // a given environment replaces a followed sky
}

void EnvironmentLightNode::setIntensity(float intensity) {
    if (!(intensity >= 0.0f) || !std::isfinite(intensity))
        throw std::invalid_argument("sgfx: EnvironmentLightNode: intensity " + std::to_string(intensity) +
                                    " is not a finite, non-negative number");
    intensity_ = intensity;
}

const ShaderSnippet& EnvironmentLightNode::snippet() const {
    static const ShaderSnippet s = [] {
        ShaderSnippet sn;
        sn.name = "environment";
        sn.defines = "#define SGFX_ENVIRONMENT 1";
        sn.samplers = {{"sgfx_envSpecular", std::string(kSpecular), true},
                       {"sgfx_envBrdf", std::string(kBrdf), true}};
        sn.fragmentDecl = std::string(nodes::shaders::embedded("env_light.glsl"));
        return sn;
    }();
    return s;
}

void EnvironmentLightNode::compile(Renderer& r) const {
    Gpu& g = *gpu_;
    if (!g.brdf) {
        // The split-sum table, computed once by env::brdfTable.
        const std::vector<glm::vec2> table = env::brdfTable(kBrdfSize);
        g.brdf = gl::createTexture2D(GL_RG32F, kBrdfSize, kBrdfSize, GL_LINEAR);
        gl::writeTexture(g.brdf, 0, -1, kBrdfSize, kBrdfSize, GL_RG, GL_FLOAT, table.data());
    }
    if (sky_ && g.skyParameters != sky_->parameters()) {
        // The sun moved (or the first frame): the sky again, prefiltered on the CPU.
        g.fromSky = Environment::fromCube(sky_->renderEnvironment(r, skySize_));
        g.skyParameters = sky_->parameters();
    }
    const std::shared_ptr<const Environment> current = environment();
    if (!current || (g.uploaded == current && g.specular)) return;
    // The prefiltered cube's levels.
    const std::vector<env::CubeImage>& levels = current->specular();
    g.specular = gl::createTextureCube(GL_RGB16F, levels[0].size, int(levels.size()));
    for (std::size_t l = 0; l < levels.size(); ++l)
        for (int f = 0; f < 6; ++f)
            gl::writeTexture(g.specular, int(l), f, levels[l].size, levels[l].size, GL_RGB, GL_FLOAT,
                             levels[l].faces[std::size_t(f)].data());
    g.levels = int(levels.size());
    g.uploaded = current;
}

void EnvironmentLightNode::applyUniforms(gl::Program& program, const DrawContext&) const {
    if (!gpu_->uploaded) return; // nothing compiled yet: the samplers read texture 0 (black)
    const env::Sh9& sh = gpu_->uploaded->irradiance();
    for (std::size_t i = 0; i < sh.size(); ++i)
        program.set("sgfx_envSh[" + std::to_string(i) + "]", sh[i] * intensity_);
    program.set("sgfx_envParams", glm::vec2(intensity_, float(std::max(gpu_->levels - 1, 0))));
}

unsigned EnvironmentLightNode::texture(std::string_view resource) const {
    if (resource == kSpecular) return gpu_->specular.get();
    if (resource == kBrdf) return gpu_->brdf.get();
    return 0;
}

void EnvironmentLightNode::releaseGLObjects() {
    // The CPU copy of the sky's environment stays: only GL objects go.
    gpu_->uploaded.reset();
    gpu_->specular = {};
    gpu_->brdf = {};
}

} // namespace sgfx

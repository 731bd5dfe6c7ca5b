// Soak run: the proving ground with every effect that exists, many frames at a small size under
// a fixed time step. Every frame is read back as linear floats and checked for NaN/Inf, and for
// GL errors. Prints frames/s and resident memory after warm-up and at the end.
#include "CameraPath.h"
#include "CliParse.h"
#include "PolygonScene.h"
#include "ProcessMemory.h"

#include <sgfx/Viewer.h>
#include <sgfx/gl/Objects.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/debugtint/DebugTintNode.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>
#include <sgfx/nodes/sky/SkyNode.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>
#include <sgfx/nodes/volume/VolumeNode.h>

#include <glm/gtc/matrix_transform.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

namespace {

struct Args {
    long frames = 100000;
    int width = 64, height = 64;
    float scale = 0.05f;
};

// Returns -1 when the run goes on, else the exit status (0 after --help, 2 for bad options).
int parse(int argc, char** argv, Args& a) {
    CLI::App cli{
        "soak: runs the proving ground for many frames and checks each one (NaN/Inf pixels, GL errors)",
        "soak"};
    demo::lastValueWins(cli);
    cli.add_option("--frames", a.frames, "frames to run (default 100000)")
        ->check(CLI::Range(1L, std::numeric_limits<long>::max()))
        ->type_name("N");
    demo::addSize(cli, a.width, a.height, 1, 4096, "image size (default 64x64)");
    cli.add_option_function<std::string>(
           "--scale",
           [&a](const std::string& v) {
               a.scale = float(demo::number("--scale", v, 0, 16));
               if (a.scale <= 0.0f)
                   throw CLI::ValidationError("--scale", "'" + v + "': S must be in (0, 16]");
           },
           "proving ground scale, as polygon --scale (default 0.05)")
        ->type_name("S");
    return demo::parse(cli, argc, argv);
}

} // namespace

int main(int argc, char** argv) {
    Args args;
    if (const int status = parse(argc, argv, args); status >= 0) return status;
    try {
        polygon::SceneOptions so;
        so.scale = args.scale;
        const polygon::PolygonScene scene = polygon::buildPolygonScene(so);
        // Every effect node that exists, around parts of the scene.
        auto tint = sgfx::DebugTintNode::create({1.0f, 0.2f, 0.1f, 0.3f});
        tint->addChild(scene.vehicle);
        // Ground fog whose mode changes every 500 frames and whose density breathes.
        auto fog = sgfx::FogNode::create(sgfx::FogParameters::ground());
        // Ambient occlusion, switched between full and half resolution, on and off.
        auto ao = sgfx::AmbientOcclusionNode::create();
        ao->addChild(scene.root);
        fog->addChild(ao);
        fog->addChild(tint);
        auto root = sgfx::Group::create();
        root->addChild(fog);
        // Particles in the fog: smoke (soft) beside the road and rain over the scene, whose
        // capacity and draw path change as the run goes on.
        auto smoke = sgfx::ParticleSystemNode::smoke(2.0f, 300);
        auto smokeAt =
            sgfx::Transform::create(glm::translate(glm::mat4(1.0f), glm::vec3(20.0f, 10.0f, 0.0f)));
        smokeAt->addChild(smoke);
        auto rain = sgfx::ParticleSystemNode::rain({200.0f, 200.0f}, 2000);
        auto rainAt = sgfx::Transform::create(glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 60.0f)));
        rainAt->addChild(rain);
        ao->addChild(smokeAt);
        fog->addChild(rainAt);
        // A volume cloud (its method and resolution change) and the sky, driving the fog.
        sgfx::VolumeParameters cloudParameters;
        cloudParameters.size = {30.0f, 30.0f, 15.0f};
        cloudParameters.absorption = 0.05f;
        cloudParameters.scattering = 0.2f;
        auto cloud = sgfx::VolumeNode::create(cloudParameters, sgfx::VolumeGrid::noise(24, 5, 3, 0.4f));
        auto cloudAt =
            sgfx::Transform::create(glm::translate(glm::mat4(1.0f), glm::vec3(-20.0f, 30.0f, 10.0f)));
        cloudAt->addChild(cloud);
        fog->addChild(cloudAt);
        auto sky = sgfx::SkyNode::create(sgfx::SkyParameters::atTime(16.0f));
        sky->attachFog(fog);
        root->addChild(sky);
        // The glass: sorted and order-independent in turn, the cabin's triangles sorted per view.
        sgfx::TransparencyDetails perTriangle;
        perTriangle.sortTriangles = true;
        scene.glassBin->setDetails(perTriangle);

        auto viewer = sgfx::Viewer::createHeadless(args.width, args.height);
        viewer->renderer().options().colorTarget = sgfx::RendererOptions::ColorTarget::Rgba32F;
        viewer->setSceneData(root);
        auto& cam = *viewer->camera();
        cam.setPerspective(polygon::kPathFovyDegrees, polygon::kPathNear, polygon::kPathFar);

        constexpr double dt = 1.0 / 60.0;  // fixed time step
        constexpr long kPathFrames = 3600; // one lap of the camera path a minute of simulated time
        // llvmpipe grows its pools over the first ~1000 frames, then levels off.
        const long warmup = std::min<long>(1000, args.frames / 2);
        long rssStart = 0;
        std::size_t programsStart = 0;
        auto t0 = std::chrono::steady_clock::now();
        for (long f = 0; f < args.frames; ++f) {
            if (f == warmup) {
                rssStart = sgfxdemo::residentKb();
                programsStart = viewer->renderer().composer().size();
                t0 = std::chrono::steady_clock::now();
            }
            const polygon::CameraPose pose =
                polygon::cameraPose(float(f % kPathFrames) / kPathFrames, so.extent);
            cam.setLookAt(pose.eye, pose.target, pose.up);
            tint->setTint({1.0f, 0.2f, 0.1f, float(0.5 + 0.5 * std::sin(f * dt))});
            fog->setMode(sgfx::FogMode(f / 500 % 3));
            scene.glassBin->setMode(sgfx::TransparencyMode(f / 250 % 2));
            if (f % 400 == 0) { // anti-aliasing modes in turn
                static const sgfx::AntiAliasing modes[] = {
                    sgfx::AntiAliasing::none(), sgfx::AntiAliasing::msaa(4), sgfx::AntiAliasing::fxaa(),
                    sgfx::AntiAliasing::taa(), sgfx::AntiAliasing::ssaa(2)};
                cam.setAntiAliasing(modes[f / 400 % 5]);
            }
            if (f % 450 == 0) {
                sgfx::VolumeParameters vp = cloudParameters;
                static const sgfx::VolumeMethod methods[] = {
                    sgfx::VolumeMethod::Raymarch, sgfx::VolumeMethod::Raymarch, sgfx::VolumeMethod::Slicing,
                    sgfx::VolumeMethod::Splatting};
                vp.halfResolution = f / 450 % 4 == 1;
                vp.method = methods[f / 450 % 4];
                vp.slices = 48;
                vp.splatSpacing = 1.0f; // 30 × 30 × 15 kernels
                cloud->setParameters(vp);
                sky->setParameters(sgfx::SkyParameters::atTime(float(6 + f / 450 % 14)));
            }
            if (f % 350 == 0) {
                sgfx::ParticleSettings ps = rain->settings();
                ps.capacity = f / 350 % 2 ? 3000 : 2000;
                ps.path = sgfx::ParticlePath(f / 350 % 5);
                ps.emitter.lifetime = 9.0f;
                rain->setSettings(ps);
                smoke->paused = f / 700 % 3 == 2;
            }
            if (f % 300 == 0) {
                sgfx::AmbientOcclusionParameters ap;
                ap.halfResolution = f / 300 % 2 == 1;
                ap.samples = f / 600 % 2 ? 16 : 32;
                ao->setParameters(ap);
                ao->enabled = f / 900 % 3 != 2;
            }
            sgfx::FogParameters fp = sgfx::FogParameters::ground();
            fp.density = float(1e-3 * (1.0 + std::sin(f * dt * 0.3)) / std::max(args.scale, 1e-3f));
            fog->setParameters(fp);
            viewer->frame(dt);
            const sgfx::FloatImage img = viewer->renderer().readPixelsLinear();
            for (std::size_t i = 0; i < img.rgba.size(); ++i)
                if (!std::isfinite(img.rgba[i])) {
                    std::fprintf(stderr, "soak: frame %ld: non-finite value %f at pixel %zu channel %zu\n", f,
                                 double(img.rgba[i]), i / 4, i % 4);
                    return 1;
                }
            for (const std::string& e : viewer->renderer().takeGlErrors()) {
                std::fprintf(stderr, "soak: frame %ld: GL: %s\n", f, e.c_str());
                return 1;
            }
        }
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const long measured = args.frames - warmup;
        const long rssEnd = sgfxdemo::residentKb();
        std::printf(
            "SOAK ok frames=%ld size=%dx%d fps=%.1f rss_start_kb=%ld rss_end_kb=%ld rss_growth_kb=%ld "
            "programs_start=%zu programs_end=%zu gl_objects=%ld\n",
            args.frames, args.width, args.height, measured > 0 ? double(measured) / seconds : 0.0, rssStart,
            rssEnd, rssEnd - rssStart, programsStart, viewer->renderer().composer().size(),
            sgfx::gl::liveObjects().total());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "soak: %s\n", e.what());
        return 1;
    }
}

// Peer benchmark: OpenSceneGraph 3.6's osgParticle (CPU simulation) on Mesa's llvmpipe through
// OSMesa, with the scene of `particles --bench` (demos/particles/main.cpp): a 40 × 40 m emitter
// shooting sprites of 0.1 m upwards at 5 ± 1 m/s under a = (0, 0, −2), one second of life, N live
// particles, seen from (0, −60, 20) towards (0, 0, 8) with a 50° field of view. Alpha-blended,
// unlit, untextured (osgParticle's default attributes without texture).
//
//   osg_particles N [--size WxH] [--frames F] [--no-draw] [--shape quad|point]
//
// --shape: quad (default) draws each particle as a camera-facing quad of 0.1 m, like sgfx's
// instanced and pulled paths; point draws GL_POINTS (osgParticle::Particle::POINT) like sgfx's
// points path, of osg::Point's size in pixels: the 0.1 m projected at the look distance (61.2 m)
// for the image height, at least 1 (bench/particles_table.sh pairs each with its sgfx peer).
//
// --no-draw: the particle system's Geode is not drawn (node mask 0), so the frame is osgParticle's
// simulation alone (the emitter and program nodes still run).
//
// Prints: OSG_PARTICLES count=... live=... frame_ms=... update_ms=... draw_ms=...
// (update: the update traversal, where osgParticle emits, moves and kills particles; draw: the
// cull and draw traversals plus glFinish). The OSMesa/libGL linking notes of osg_polygon.cpp apply.
#include "osg_osmesa.h"

#include <osg/BlendFunc>
#include <osg/Geode>
#include <osg/Point>
#include <osgParticle/AccelOperator>
#include <osgParticle/BoxPlacer>
#include <osgParticle/ModularEmitter>
#include <osgParticle/ModularProgram>
#include <osgParticle/ParticleSystem>
#include <osgParticle/ParticleSystemUpdater>
#include <osgParticle/RadialShooter>
#include <osgParticle/RandomRateCounter>
#include <osgViewer/Viewer>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr,
                     "usage: osg_particles N [--size WxH] [--frames F] [--no-draw] [--shape quad|point]\n");
        return 2;
    }
    const long n = std::strtol(argv[1], nullptr, 10);
    int width = 1280, height = 720, frames = 10;
    bool draw = true;
    bool points = false;
    for (int i = 2; i < argc; i += 2) {
        if (!std::strcmp(argv[i], "--no-draw")) {
            draw = false;
            --i;
            continue;
        }
        if (i + 1 >= argc) break;
        if (!std::strcmp(argv[i], "--size") && std::sscanf(argv[i + 1], "%dx%d", &width, &height) == 2)
            continue;
        if (!std::strcmp(argv[i], "--shape") &&
            (!std::strcmp(argv[i + 1], "point") || !std::strcmp(argv[i + 1], "quad"))) {
            points = !std::strcmp(argv[i + 1], "point");
            continue;
        }
        if (!std::strcmp(argv[i], "--frames")) {
            frames = std::atoi(argv[i + 1]);
            continue;
        }
        std::fprintf(stderr, "osg_particles: bad option %s\n", argv[i]);
        return 2;
    }
    if (n < 1 || frames < 1 || width < 1 || height < 1) {
        std::fprintf(stderr, "osg_particles: N, frames and size must be positive\n");
        return 2;
    }
    const auto gl = OsgOsmesaContext::open("osg_particles", width, height);
    if (!gl) return 1;
    std::printf("GL_RENDERER: %s\n", gl->renderer());

    constexpr double kLife = 1.0, kDt = 1.0 / 30.0;
    osg::ref_ptr<osgParticle::ParticleSystem> ps = new osgParticle::ParticleSystem;
    ps->setDefaultAttributes("", false, false);
    osgParticle::Particle& tpl = ps->getDefaultParticleTemplate();
    tpl.setLifeTime(kLife);
    tpl.setShape(points ? osgParticle::Particle::POINT : osgParticle::Particle::QUAD);
    tpl.setSizeRange(osgParticle::rangef(0.1f, 0.1f));
    tpl.setAlphaRange(osgParticle::rangef(0.8f, 0.8f));
    tpl.setColorRange(osgParticle::rangev4(osg::Vec4(1, 0.9f, 0.7f, 0.8f), osg::Vec4(1, 0.9f, 0.7f, 0.8f)));
    ps->getOrCreateStateSet()->setAttributeAndModes(new osg::BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA));
    if (points) { // 0.1 m at 61.2 m under a 50 degree vertical field of view, in pixels
        const double px = 0.1 / (2.0 * 61.2 * std::tan(osg::DegreesToRadians(25.0))) * height;
        ps->getOrCreateStateSet()->setAttributeAndModes(new osg::Point(float(std::max(1.0, px))));
    }

    osg::ref_ptr<osgParticle::ModularEmitter> emitter = new osgParticle::ModularEmitter;
    emitter->setParticleSystem(ps.get());
    auto* counter = new osgParticle::RandomRateCounter;
    counter->setRateRange(double(n) / kLife, double(n) / kLife); // n live in steady state
    emitter->setCounter(counter);
    auto* placer = new osgParticle::BoxPlacer;
    placer->setXRange(-20.0f, 20.0f);
    placer->setYRange(-20.0f, 20.0f);
    placer->setZRange(0.0f, 0.0f);
    emitter->setPlacer(placer);
    auto* shooter = new osgParticle::RadialShooter;
    shooter->setThetaRange(0.0f, 0.2f); // about the ±1 m/s spread around 5 m/s upwards
    shooter->setInitialSpeedRange(4.0f, 6.0f);
    emitter->setShooter(shooter);
    osg::ref_ptr<osgParticle::ModularProgram> program = new osgParticle::ModularProgram;
    program->setParticleSystem(ps.get());
    auto* accel = new osgParticle::AccelOperator;
    accel->setAcceleration(osg::Vec3(0, 0, -2));
    program->addOperator(accel);
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->addDrawable(ps.get());
    if (!draw) geode->setNodeMask(0);
    osg::ref_ptr<osgParticle::ParticleSystemUpdater> updater = new osgParticle::ParticleSystemUpdater;
    updater->addParticleSystem(ps.get());
    osg::ref_ptr<osg::Group> root = new osg::Group;
    root->addChild(emitter.get());
    root->addChild(program.get());
    root->addChild(geode.get());
    root->addChild(updater.get());

    osgViewer::Viewer viewer;
    viewer.setThreadingModel(osgViewer::Viewer::SingleThreaded);
    viewer.setUpViewerAsEmbeddedInWindow(0, 0, width, height);
    viewer.setSceneData(root.get());
    osg::Camera* camera = viewer.getCamera();
    camera->setClearColor(osg::Vec4(0.42f, 0.60f, 0.85f, 1.0f));
    camera->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
    camera->setProjectionMatrixAsPerspective(50.0, double(width) / height, 0.5, 500.0);
    camera->setViewMatrixAsLookAt(osg::Vec3d(0, -60, 20), osg::Vec3d(0, 0, 8), osg::Vec3d(0, 0, 1));
    viewer.realize();

    using clock = std::chrono::steady_clock;
    double t = 0.0;
    auto frame = [&](double* updateMs, double* drawMs) {
        t += kDt;
        viewer.advance(t);
        viewer.eventTraversal();
        const auto t0 = clock::now();
        viewer.updateTraversal();
        const auto t1 = clock::now();
        viewer.renderingTraversals();
        glFinish();
        const auto t2 = clock::now();
        if (updateMs) *updateMs = std::chrono::duration<double, std::milli>(t1 - t0).count();
        if (drawMs) *drawMs = std::chrono::duration<double, std::milli>(t2 - t1).count();
    };
    // Warm-up: one lifetime fills the system to its steady count.
    for (int i = 0; i < int(kLife / kDt) + 3; ++i)
        frame(nullptr, nullptr);
    std::vector<double> total, update, drawMs;
    for (int i = 0; i < frames; ++i) {
        double u = 0, d = 0;
        frame(&u, &d);
        update.push_back(u);
        drawMs.push_back(d);
        total.push_back(u + d);
    }
    auto med = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
    };
    std::printf("OSG_PARTICLES count=%ld live=%d size=%dx%d drawn=%d shape=%s frame_ms=%.2f update_ms=%.2f "
                "draw_ms=%.2f\n",
                n, ps->numParticles() - ps->numDeadParticles(), width, height, int(draw),
                points ? "point" : "quad", med(total), med(update), med(drawMs));
    return 0;
}

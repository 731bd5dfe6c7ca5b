// OpenSceneGraph 3.6 peer of sgfx_cull: the same scene (bench/cull_scene.h) built from osg::Group,
// osg::MatrixTransform and one shared osg::Geode + osg::Geometry box (with an osg::Material
// StateSet), culled by osgUtil::CullVisitor set up as osgUtil::SceneView::cullStage does it:
// reset, StateGraph::clean, RenderStage::reset, push viewport / projection / model-view
// (ABSOLUTE_RF), traverse the camera, pop; then RenderStage::sort (timed apart, as sort_ms) and
// StateGraph::prune (counted with the cull). CullSettings are OSG's defaults (DEFAULT_CULLING,
// COMPUTE_NEAR_FAR_USING_BOUNDING_VOLUMES). No GL context: culling never touches GL.
//
//   osg_cull [--n N] [--frames F] [--no-memory] [--no-geode] [--mixed]
//     --no-geode  put the Geometry straight under each MatrixTransform (OSG >= 3.4 allows it) and
//                 switch small-feature culling off (sgfx has none): OSG's leanest setup
//     --mixed     cull_scene.h's mixed-state scene: rotated, non-uniformly scaled leaves over 8
//                 boxes with their own osg::Material each; small-feature culling off as well
#include "alloc_count.h"
#include "cull_scene.h"

#include <osg/Camera>
#include <osg/FrameStamp>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Material>
#include <osg/MatrixTransform>
#include <osg/State>
#include <osgUtil/CullVisitor>
#include <osgUtil/RenderStage>
#include <osgUtil/StateGraph>

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

namespace {

double peakRssMb() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_maxrss) / 1024.0;
}

osg::ref_ptr<osg::Geometry> makeBox(int state) {
    const float h = cullscene::kBoxSize * 0.5f;
    osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
    for (int c = 0; c < 8; ++c)
        v->push_back(osg::Vec3(c & 1 ? h : -h, c & 2 ? h : -h, c & 4 ? h : -h));
    osg::ref_ptr<osg::Vec3Array> nrm = new osg::Vec3Array;
    for (const osg::Vec3& p : *v) {
        osg::Vec3 q = p;
        q.normalize();
        nrm->push_back(q);
    }
    static const unsigned short idx[36] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                           2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
    g->setVertexArray(v.get());
    g->setNormalArray(nrm.get(), osg::Array::BIND_PER_VERTEX);
    g->addPrimitiveSet(new osg::DrawElementsUShort(GL_TRIANGLES, 36, idx));
    osg::ref_ptr<osg::Material> material = new osg::Material;
    float rgb[3];
    cullscene::stateColour(state, rgb);
    material->setDiffuse(osg::Material::FRONT_AND_BACK, osg::Vec4(rgb[0], rgb[1], rgb[2], 1.0f));
    g->getOrCreateStateSet()->setAttributeAndModes(material.get());
    return g;
}

// Same accounting as sgfx_cull: the node, its children vector and its children's back-pointers.
struct NodeBytes {
    double group = 0, transform = 0;
};

NodeBytes measureNodes(osg::Node* leafChild) {
    constexpr int kCount = 10000;
    std::vector<osg::ref_ptr<osg::Node>> kids;
    for (int i = 0; i < kCount * 8; ++i)
        kids.push_back(new osg::Group);
    std::vector<osg::ref_ptr<osg::Node>> keep;
    keep.reserve(2 * kCount);
    NodeBytes out;
    alloccount::enabled = true;
    long long before = alloccount::live;
    for (int i = 0; i < kCount; ++i) {
        osg::ref_ptr<osg::Group> g = new osg::Group;
        for (int c = 0; c < 8; ++c)
            g->addChild(kids[std::size_t(i * 8 + c)].get());
        keep.push_back(g);
    }
    out.group = double(alloccount::live - before) / kCount;
    before = alloccount::live;
    for (int i = 0; i < kCount; ++i) {
        osg::ref_ptr<osg::MatrixTransform> t =
            new osg::MatrixTransform(osg::Matrix::translate(double(i), 0.0, 0.0));
        t->addChild(leafChild);
        keep.push_back(t);
    }
    out.transform = double(alloccount::live - before) / kCount;
    alloccount::enabled = false;
    return out;
}

// Render leaves the cull produced (what sgfx calls queued items).
std::size_t countLeaves(const osgUtil::StateGraph& sg) {
    std::size_t n = sg._leaves.size();
    for (const auto& c : sg._children)
        n += countLeaves(*c.second);
    return n;
}

} // namespace

int main(int argc, char** argv) {
    cullscene::Args args;
    if (!cullscene::parseArgs(argc, argv, "osg_cull", true, args)) return 2;
    const long n = args.n;
    const int frames = args.frames;
    const bool memory = args.memory;
    const bool geode = args.geode;

    std::vector<osg::ref_ptr<osg::Node>> leaves; // one, or kStates with --mixed
    for (int b = 0; b < (args.mixed ? cullscene::kStates : 1); ++b) {
        osg::ref_ptr<osg::Geometry> box = makeBox(b);
        osg::ref_ptr<osg::Node> leaf = box;
        if (geode) {
            osg::ref_ptr<osg::Geode> gd = new osg::Geode;
            gd->addDrawable(box.get());
            leaf = gd;
        }
        leaves.push_back(leaf);
    }
    NodeBytes nodeBytes;
    if (memory) nodeBytes = measureNodes(leaves.front().get());

    const cullscene::Dims d = cullscene::dims(n);
    long groups = 0;
    alloccount::enabled = memory;
    const long long sceneBefore = alloccount::live;
    osg::ref_ptr<osg::Node> root = cullscene::build<osg::ref_ptr<osg::Node>>(
        d,
        [&](std::vector<osg::ref_ptr<osg::Node>>&& children) -> osg::ref_ptr<osg::Node> {
            ++groups;
            osg::ref_ptr<osg::Group> g = new osg::Group;
            for (auto& c : children)
                g->addChild(c.get());
            return g;
        },
        [&](int i, int j, int k) -> osg::ref_ptr<osg::Node> {
            float m[16];
            cullscene::leafMatrix(i, j, k, args.mixed, m);
            osg::ref_ptr<osg::MatrixTransform> t = new osg::MatrixTransform(osg::Matrixf(m));
            t->addChild(leaves[args.mixed ? std::size_t(cullscene::stateOf(i, j, k)) : 0].get());
            return t;
        });
    const double sceneBytes = double(alloccount::live - sceneBefore);
    alloccount::enabled = false;

    const cullscene::View v = cullscene::view(d);
    osg::ref_ptr<osg::Camera> camera = new osg::Camera;
    osg::ref_ptr<osg::Viewport> viewport = new osg::Viewport(0, 0, v.width, v.height);
    camera->setViewport(viewport.get());
    camera->setProjectionMatrixAsPerspective(v.fovyDegrees, v.aspect, v.zNear, v.zFar);
    camera->setViewMatrixAsLookAt(osg::Vec3d(v.eye[0], v.eye[1], v.eye[2]),
                                  osg::Vec3d(v.center[0], v.center[1], v.center[2]),
                                  osg::Vec3d(v.up[0], v.up[1], v.up[2]));
    if (!geode || args.mixed) // sgfx culls no small features: compare frustum culling alone
        camera->setCullingMode(camera->getCullingMode() & ~osg::CullSettings::SMALL_FEATURE_CULLING);
    camera->addChild(root.get());
    root->getBound(); // bounds are lazy: computed once, outside the timed frames

    osg::ref_ptr<osgUtil::CullVisitor> cv = osgUtil::CullVisitor::create();
    osg::ref_ptr<osgUtil::StateGraph> rendergraph = new osgUtil::StateGraph;
    osg::ref_ptr<osgUtil::RenderStage> renderStage = new osgUtil::RenderStage;
    osg::ref_ptr<osg::FrameStamp> frameStamp = new osg::FrameStamp;
    osg::ref_ptr<osg::State> state = new osg::State;
    osg::RenderInfo renderInfo(state.get(), nullptr);
    osg::ref_ptr<osg::RefMatrix> proj = new osg::RefMatrix(camera->getProjectionMatrix());
    osg::ref_ptr<osg::RefMatrix> mv = new osg::RefMatrix(camera->getViewMatrix());

    // CPU time of this thread as well: robust to other load on the machine (preemption).
    auto cpuMs = [] {
        timespec ts{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
        return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
    };
    std::vector<double> cullMs, sortMs, cullCpuMs;
    std::size_t queued = 0;
    double nearPlane = 0, farPlane = 0;
    using clock = std::chrono::steady_clock;
    for (int f = -3; f < frames; ++f) { // 3 warm-up frames
        const double c0 = cpuMs();
        const auto t0 = clock::now();
        // osgUtil::SceneView::cullStage, less what this scene does not use (occluders, the
        // global/secondary/local StateSets, stereo).
        cv->reset();
        frameStamp->setFrameNumber(f + 3);
        cv->setFrameStamp(frameStamp.get());
        cv->setTraversalNumber(frameStamp->getFrameNumber());
        cv->inheritCullSettings(*camera);
        cv->setStateGraph(rendergraph.get());
        cv->setRenderStage(renderStage.get());
        cv->setRenderInfo(renderInfo);
        renderStage->reset();
        rendergraph->clean();
        renderStage->setInitialViewMatrix(mv.get());
        renderStage->setViewport(viewport.get());
        cv->pushViewport(viewport.get());
        cv->pushProjectionMatrix(proj.get());
        cv->pushModelViewMatrix(mv.get(), osg::Transform::ABSOLUTE_RF);
        cv->traverse(*camera);
        cv->popModelViewMatrix();
        cv->popProjectionMatrix();
        cv->popViewport();
        const auto t1 = clock::now();
        const double c1 = cpuMs();
        queued = countLeaves(*rendergraph);
        const auto t2 = clock::now();
        renderStage->sort();
        const auto t3 = clock::now();
        const double c3 = cpuMs();
        rendergraph->prune();
        const auto t4 = clock::now();
        const double c4 = cpuMs();
        nearPlane = cv->getCalculatedNearPlane();
        farPlane = cv->getCalculatedFarPlane();
        if (f < 0) continue;
        cullMs.push_back(std::chrono::duration<double, std::milli>((t1 - t0) + (t4 - t3)).count());
        cullCpuMs.push_back((c1 - c0) + (c4 - c3));
        sortMs.push_back(std::chrono::duration<double, std::milli>(t3 - t2).count());
    }
    const double ms = cullscene::median(cullMs);
    const long nodes = groups + d.count();
    std::printf("CULL side=osg n=%ld groups=%ld frames=%d ms_median=%.4f ms_min=%.4f cpu_ms_median=%.4f "
                "nodes_per_s=%.4g "
                "queued=%zu fraction=%.4f sort_ms=%.4f near=%.3f far=%.3f peak_rss_mb=%.1f "
                "scene_bytes_per_leaf=%.1f group_bytes=%.1f transform_bytes=%.1f sizeof_group=%zu "
                "sizeof_transform=%zu geode=%d mixed=%d\n",
                d.count(), groups, frames, ms, cullMs.front(), cullscene::median(cullCpuMs),
                double(nodes) / (ms * 1e-3), queued, double(queued) / double(d.count()),
                cullscene::median(sortMs), nearPlane, farPlane, peakRssMb(),
                memory ? sceneBytes / double(d.count()) : 0.0, nodeBytes.group, nodeBytes.transform,
                sizeof(osg::Group), sizeof(osg::MatrixTransform), geode ? 1 : 0, int(args.mixed));
    return 0;
}

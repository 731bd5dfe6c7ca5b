#pragma once
// sgfx side of bench/cull_scene.h, shared by sgfx_cull and cull_bench. Needs alloc_count.h
// included first (once per program) for the memory figures.
#include "alloc_count.h"
#include "cull_scene.h"

#include <sgfx/Camera.h>
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Material.h>
#include <sgfx/Shapes.h>
#include <sgfx/StateSet.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <sys/resource.h>

#include <memory>
#include <vector>

namespace cullscene {

inline double peakRssMb() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_maxrss) / 1024.0; // ru_maxrss is in KiB on Linux
}

// One box Geometry with a Material, shared by every leaf (--mixed: box `state` of kStates, each
// with its own material colour).
inline std::shared_ptr<sgfx::Geometry> makeBox(int state = 0) {
    std::shared_ptr<sgfx::Geometry> box = sgfx::shapes::box(glm::vec3(kBoxSize));
    auto material = sgfx::Material::create();
    float rgb[3];
    stateColour(state, rgb);
    material->diffuse = glm::vec4(rgb[0], rgb[1], rgb[2], 1.0f);
    box->getOrCreateStateSet().material.set(material);
    return box;
}

struct SgfxScene {
    Dims dims{};
    long groups = 0;
    double heapBytes = 0; // live heap the build added (when counting)
    std::vector<std::shared_ptr<sgfx::Geometry>> boxes; // one, or kStates with --mixed
    std::shared_ptr<sgfx::Camera> camera; // the scene is its child

    long nodes() const { return groups + dims.count(); } // Groups and Transforms
};

inline SgfxScene buildSgfxScene(long n, bool countHeap, bool mixed = false) {
    SgfxScene s;
    s.dims = dims(n);
    for (int b = 0; b < (mixed ? kStates : 1); ++b)
        s.boxes.push_back(makeBox(b));
    alloccount::enabled = countHeap;
    const long long before = alloccount::live;
    sgfx::NodePtr root = build<sgfx::NodePtr>(
        s.dims,
        [&](std::vector<sgfx::NodePtr>&& children) -> sgfx::NodePtr {
            ++s.groups;
            auto g = sgfx::Group::create();
            for (auto& c : children)
                g->addChild(std::move(c));
            return g;
        },
        [&](int i, int j, int k) -> sgfx::NodePtr {
            float m[16];
            leafMatrix(i, j, k, mixed, m);
            auto t = sgfx::Transform::create(glm::make_mat4(m));
            t->addChild(s.boxes[mixed ? std::size_t(stateOf(i, j, k)) : 0]);
            return t;
        });
    s.heapBytes = double(alloccount::live - before);
    alloccount::enabled = false;

    const View v = view(s.dims);
    s.camera = sgfx::Camera::create();
    s.camera->setViewport(0, 0, v.width, v.height);
    s.camera->setPerspective(v.fovyDegrees, v.zNear, v.zFar);
    s.camera->setLookAt({v.eye[0], v.eye[1], v.eye[2]}, {v.center[0], v.center[1], v.center[2]},
                        {v.up[0], v.up[1], v.up[2]});
    s.camera->addChild(root);
    s.camera->bound(); // bounds are lazy: computed once, outside any timed frame
    return s;
}

// Live heap per node, counted the same way as osg_cull: the node (with its control block), its
// children vector and the back-pointers its children keep (Group: 8 fresh children; Transform:
// the one shared box).
struct NodeBytes {
    double group = 0, transform = 0;
};

inline NodeBytes measureSgfxNodes() {
    constexpr int kCount = 10000;
    const sgfx::NodePtr box = makeBox();
    std::vector<sgfx::NodePtr> kids;
    for (int i = 0; i < kCount * 8; ++i)
        kids.push_back(sgfx::Group::create());
    std::vector<sgfx::NodePtr> keep;
    keep.reserve(2 * kCount);
    NodeBytes out;
    alloccount::enabled = true;
    long long before = alloccount::live;
    for (int i = 0; i < kCount; ++i) {
        auto g = sgfx::Group::create();
        for (int c = 0; c < 8; ++c)
            g->addChild(kids[std::size_t(i * 8 + c)]);
        keep.push_back(std::move(g));
    }
    out.group = double(alloccount::live - before) / kCount;
    before = alloccount::live;
    for (int i = 0; i < kCount; ++i) {
        auto t = sgfx::Transform::create(glm::translate(glm::mat4(1.0f), glm::vec3(float(i), 0, 0)));
        t->addChild(box);
        keep.push_back(std::move(t));
    }
    out.transform = double(alloccount::live - before) / kCount;
    alloccount::enabled = false;
    return out;
}

} // namespace cullscene

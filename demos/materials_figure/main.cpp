// The "before and after" figures of docs/materials.md, headless, each a pair of PNGs:
//   mirror_before/after   the proving ground's robot vehicle beside its mirror image (scale −1 in
//                         x). "Before" is what sgfx drew before mirrored transforms were handled:
//                         emulated by reversing every triangle's winding under the fix, which
//                         culls and lights the same faces the old renderer did.
//   transmission_before/after  a glTF model with KHR_materials_transmission (argument), drawn
//                         with its transmission dropped (the loader used to warn and draw it
//                         opaque) and as loaded.
//   materials_figure [--out-dir DIR] [--size WxH] [--transmission-model FILE]
#include "CliParse.h"

#include <PolygonScene.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/NodeVisitor.h>
#include <sgfx/Shapes.h>
#include <sgfx/Viewer.h>
#include <sgfx/nodes/environment/EnvironmentLightNode.h>
#include <sgfx/nodes/sky/SkyNode.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <set>
#include <string>
#include <utility>

namespace {

// Reverses each triangle's winding (indexed triangle lists, the vehicle's parts).
class ReverseWinding : public sgfx::NodeVisitor {
public:
    ReverseWinding()
        : NodeVisitor(Mode::AllChildren) {}
    void apply(sgfx::Geometry& g) override {
        if (g.mode != sgfx::PrimitiveMode::Triangles) return;
        for (std::size_t i = 0; i + 2 < g.indices.size(); i += 3)
            std::swap(g.indices[i + 1], g.indices[i + 2]);
        g.dirty();
    }
};

// Drops every material's transmission (what the loader did before it read the extension).
class DropTransmission : public sgfx::NodeVisitor {
public:
    DropTransmission()
        : NodeVisitor(Mode::AllChildren) {}
    void apply(sgfx::Geometry& g) override {
        if (g.stateSet() && g.stateSet()->material.value && *g.stateSet()->material.value)
            (*g.stateSet()->material.value)->transmission = 0.0f;
    }
};

// A sun, its sky's light on the materials, a grey ground at z = 0 (none when `groundSize` is 0);
// `content` on top.
std::shared_ptr<sgfx::Group> lit(const std::shared_ptr<sgfx::Node>& content, float groundSize) {
    auto root = sgfx::Group::create();
    auto sun = sgfx::Light::create(sgfx::LightType::Directional);
    sun->direction = glm::normalize(glm::vec3(-0.4f, 0.6f, -0.7f));
    sun->color = glm::vec3(2.0f);
    root->addChild(sun);
    auto sky = sgfx::SkyNode::create();
    auto env = sgfx::EnvironmentLightNode::create(sky);
    if (groundSize > 0.0f) {
        auto ground = sgfx::shapes::quad(groundSize, groundSize);
        auto grey = sgfx::Material::create();
        grey->diffuse = glm::vec4(0.35f, 0.35f, 0.33f, 1.0f);
        grey->ambient = glm::vec3(0.35f, 0.35f, 0.33f);
        ground->getOrCreateStateSet().material.set(grey);
        env->addChild(ground);
    }
    env->addChild(content);
    root->addChild(env);
    return root;
}

void shoot(const std::shared_ptr<sgfx::Node>& scene, glm::vec3 eye, glm::vec3 at, int w, int h,
           const std::filesystem::path& file) {
    auto v = sgfx::Viewer::createHeadless(w, h);
    v->camera()->setPerspective(40.0f, 0.05f, 500.0f);
    v->camera()->setLookAt(eye, at, {0, 0, 1});
    v->camera()->clearColor = {0.55f, 0.65f, 0.8f, 1.0f};
    v->setSceneData(scene);
    v->frame();
    v->writeScreenshot(file);
    std::printf("wrote %s\n", file.string().c_str());
}

// The vehicle and its mirror image side by side, their winding reversed for the "before".
std::shared_ptr<sgfx::Node> vehiclePair(bool before) {
    auto pair = sgfx::Group::create();
    for (const float sx : {1.0f, -1.0f}) {
        auto vehicle = polygon::buildVehicle();
        const float apart = vehicle->bound().radius * 0.9f; // side by side, not overlapping
        if (before && sx < 0.0f) {
            ReverseWinding reverse;
            vehicle->accept(reverse);
        }
        auto t = sgfx::Transform::create(
            glm::scale(glm::translate(glm::mat4(1.0f), {sx * apart, 0.0f, 0.0f}), glm::vec3(sx, 1.0f, 1.0f)));
        t->addChild(vehicle);
        pair->addChild(t);
    }
    return pair;
}

} // namespace

int main(int argc, char** argv) {
    std::filesystem::path dir = ".";
    std::filesystem::path transmissionModel;
    int width = 480, height = 320;
    CLI::App cli{"materials_figure: docs/materials.md's before/after figures (a mirrored vehicle, a "
                 "transmissive glTF model)",
                 "materials_figure"};
    demo::lastValueWins(cli);
    demo::addFigureOptions(cli, dir, width, height);
    cli.add_option("--transmission-model", transmissionModel,
                   "a glTF model with KHR_materials_transmission for the transmission pair (none by default)")
        ->type_name("FILE");
    if (const int status = demo::parse(cli, argc, argv); status >= 0) return status;
    try {
        for (const bool before : {true, false}) {
            const auto pair = vehiclePair(before);
            const sgfx::BoundingSphere b = pair->bound();
            shoot(lit(pair, 8.0f * b.radius), b.center + glm::vec3(0.35f, -1.25f, 0.6f) * b.radius, b.center,
                  width, height, dir / (before ? "mirror_before.png" : "mirror_after.png"));
        }
        if (!transmissionModel.empty()) {
            for (const bool before : {true, false}) {
                auto model = sgfx::loadModel(transmissionModel);
                if (before) {
                    DropTransmission drop;
                    model->accept(drop);
                }
                // Its own backdrop and floor: no ground; straight on, the tiles filling the width.
                const sgfx::BoundingSphere b = model->bound();
                shoot(lit(model, 0.0f), b.center + glm::vec3(0.0f, -1.9f, 0.15f) * b.radius, b.center, width,
                      height, dir / (before ? "transmission_before.png" : "transmission_after.png"));
            }
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "materials_figure: %s\n", e.what());
        return 1;
    }
    return 0;
}

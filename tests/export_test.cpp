// The demo's scene written as OBJ and glTF loads back through loadModel with every triangle and
// the same extent, so other tools and peer benchmarks see exactly what sgfx renders.
#include "PolygonScene.h"

#include <sgfx/Geometry.h>
#include <sgfx/GltfWriter.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/ObjWriter.h>
#include <sgfx/Visitors.h>

#include <gtest/gtest.h>
#include <sgfx/Image.h>
#include <sgfx/Material.h>
#include <sgfx/StateSet.h>
#include <sgfx/Texture.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <functional>

using namespace sgfx;

TEST(Export, ProvingGroundRoundTripsThroughObjAndGltf) {
    polygon::SceneOptions so;
    so.scale = 0.05f;
    so.lod = false; // writers keep only the finest level of a LOD (GltfWriter test): compare all
    const polygon::PolygonScene scene = polygon::buildPolygonScene(so);
    StatsVisitor stats;
    scene.root->accept(stats);
    ComputeBoundsVisitor bounds;
    scene.root->accept(bounds);
    ASSERT_GT(stats.triangles, 1000u);

    const auto dir = std::filesystem::temp_directory_path();
    const ObjWriteResult obj = writeObj(*scene.root, dir / "sgfx_export.obj");
    const GltfWriteResult glb = writeGltf(*scene.root, dir / "sgfx_export.glb");
    const GltfWriteResult gltf = writeGltf(*scene.root, dir / "sgfx_export.gltf");
    EXPECT_EQ(obj.triangles, stats.triangles);
    EXPECT_EQ(obj.textures, 1u); // the leaf cards' mask, as an RGBA map_Kd
    EXPECT_EQ(glb.triangles, stats.triangles);
    EXPECT_EQ(gltf.triangles, stats.triangles);
    for (const char* name : {"sgfx_export.obj", "sgfx_export.glb", "sgfx_export.gltf"}) {
        SCOPED_TRACE(name);
        const auto model = loadModel(dir / name);
        StatsVisitor back;
        model->accept(back);
        EXPECT_EQ(back.triangles, stats.triangles);
        if (std::string(name) == "sgfx_export.obj") {
            // The mask came back as the base colour map's alpha: leaf and gap texels both there.
            std::size_t cut = 0, kept = 0;
            std::function<void(const Node&)> walk = [&](const Node& n) {
                const StateSet* ss = n.stateSet().get();
                const Material* m = ss && ss->material.value ? ss->material.value->get() : nullptr;
                if (m && m->baseColorTexture && m->baseColorTexture->image &&
                    m->baseColorTexture->image->channels == 4)
                    for (std::size_t i = 3; i < m->baseColorTexture->image->pixels.size(); i += 4)
                        (m->baseColorTexture->image->pixels[i] < 128 ? cut : kept) += 1;
                if (auto g = dynamic_cast<const Group*>(&n))
                    for (const auto& c : g->children())
                        walk(*c);
            };
            walk(*model);
            EXPECT_GT(cut, 0u);
            EXPECT_GT(kept, 0u);
        }
        ComputeBoundsVisitor b;
        model->accept(b);
        // OBJ keeps 6 significant digits: 1 mm on an 800 m ground.
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(b.min[c], bounds.min[c], 1e-3f);
            EXPECT_NEAR(b.max[c], bounds.max[c], 1e-3f);
        }
    }
}

namespace {

// The colours of a material as the OBJ writer keeps them: Ka, Kd with d, Ks, Ns, Ke.
using Colours = std::array<float, 14>;
Colours coloursOf(const Material& m) {
    return {m.ambient.r,  m.ambient.g,  m.ambient.b,  m.diffuse.r, m.diffuse.g,  m.diffuse.b,  m.diffuse.a,
            m.specular.r, m.specular.g, m.specular.b, m.shininess, m.emissive.r, m.emissive.g, m.emissive.b};
}

// The distinct colours of the materials that triangle geometry below `node` is drawn with (the
// nearest material above it; the default one where there is none: the scene uses no Override).
void usedColours(const Node& node, const Material& inherited, std::vector<Colours>& out) {
    const StateSet* ss = node.stateSet().get();
    const Material& m = ss && ss->material.value && *ss->material.value ? **ss->material.value : inherited;
    if (auto g = dynamic_cast<const Geometry*>(&node); g && g->mode == PrimitiveMode::Triangles)
        if (std::find(out.begin(), out.end(), coloursOf(m)) == out.end()) out.push_back(coloursOf(m));
    if (auto g = dynamic_cast<const Group*>(&node))
        for (const auto& c : g->children())
            usedColours(*c, m, out);
}

bool near(const Colours& a, const Colours& b) {
    for (std::size_t i = 0; i < a.size(); ++i)
        if (std::abs(a[i] - b[i]) > 1e-6f * std::max(1.0f, std::abs(b[i]))) return false;
    return true;
}

} // namespace

TEST(Export, ObjExportReloadsWithTheSceneColours) {
    // The proving ground's colours are its materials' (it has no vertex colours): every one that
    // is drawn comes back from `polygon --export-obj`'s MTL, to the 6 digits it is written with.
    polygon::SceneOptions so;
    so.scale = 0.05f;
    so.lod = false;
    const polygon::PolygonScene scene = polygon::buildPolygonScene(so);
    const Material defaults;
    std::vector<Colours> drawn, back;
    usedColours(*scene.root, defaults, drawn);
    ASSERT_GT(drawn.size(), 10u);
    const auto file = std::filesystem::temp_directory_path() / "sgfx_export_colours.obj";
    writeObj(*scene.root, file);
    usedColours(*loadModel(file), defaults, back);
    EXPECT_EQ(back.size(), drawn.size());
    for (const Colours& c : drawn)
        EXPECT_TRUE(std::any_of(back.begin(), back.end(), [&](const Colours& b) { return near(b, c); }))
            << "Kd " << c[3] << " " << c[4] << " " << c[5] << " did not come back";
}

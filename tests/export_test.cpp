// The demo's scene written as OBJ and glTF loads back through loadModel with every triangle and
// the same extent, so other tools and peer benchmarks see exactly what sgfx renders.
#include "PolygonScene.h"

#include <sgfx/GltfWriter.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/ObjWriter.h>
#include <sgfx/Visitors.h>

#include <gtest/gtest.h>

#include <filesystem>

using namespace sgfx;

TEST(Export, ProvingGroundRoundTripsThroughObjAndGltf) {
    polygon::SceneOptions so;
    so.scale = 0.05f;
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
    EXPECT_EQ(glb.triangles, stats.triangles);
    EXPECT_EQ(gltf.triangles, stats.triangles);
    for (const char* name : {"sgfx_export.obj", "sgfx_export.glb", "sgfx_export.gltf"}) {
        SCOPED_TRACE(name);
        const auto model = loadModel(dir / name);
        StatsVisitor back;
        model->accept(back);
        EXPECT_EQ(back.triangles, stats.triangles);
        ComputeBoundsVisitor b;
        model->accept(b);
        // OBJ keeps 6 significant digits: 1 mm on an 800 m ground.
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(b.min[c], bounds.min[c], 1e-3f);
            EXPECT_NEAR(b.max[c], bounds.max[c], 1e-3f);
        }
    }
}

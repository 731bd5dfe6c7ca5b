// OBJ/OFF/PLY/STL through OpenMesh: round trips through the writer keep the vertex positions and
// the triangle count; normals are made when a file has none; bad files say why.
#include <sgfx/MeshLoader.h>
#include <sgfx/Shapes.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace sgfx;

namespace {
bool contains(const std::vector<glm::vec3>& set, glm::vec3 p) {
    return std::any_of(set.begin(), set.end(),
                       [&](const glm::vec3& q) { return glm::length(q - p) < 1e-5f; });
}
} // namespace

TEST(Mesh, RoundTripsKeepPositionsAndTriangles) {
    const auto box = shapes::box({1.0f, 2.0f, 3.0f});
    const auto sphere = shapes::sphere(1.5f, 12, 6);
    for (const auto& source : {box, sphere})
        for (const char* ext : {".obj", ".off", ".ply", ".stl"}) {
            SCOPED_TRACE(std::string(ext) + " " + std::to_string(source->triangleCount()) + " triangles");
            const auto file = std::filesystem::temp_directory_path() / (std::string("sgfx_roundtrip") + ext);
            writeMesh(*source, file);
            const auto loaded = loadMesh(file);
            // STL keeps no vertex identity: vertices are merged by position on reading, so the
            // sphere's zero-area pole triangles collapse and are dropped.
            std::size_t expected = source->triangleCount();
            if (std::string(ext) == ".stl") {
                expected = 0;
                for (std::size_t k = 0; k + 2 < source->indices.size(); k += 3) {
                    const glm::vec3 a = source->positions[source->indices[k]],
                                    b = source->positions[source->indices[k + 1]],
                                    c = source->positions[source->indices[k + 2]];
                    expected += a != b && b != c && a != c; // identical corners merge into a non-face
                }
            }
            EXPECT_EQ(loaded->triangleCount(), expected);
            for (const glm::vec3& p : source->positions)
                ASSERT_TRUE(contains(loaded->positions, p));
            for (const glm::vec3& p : loaded->positions)
                ASSERT_TRUE(contains(source->positions, p));
            ASSERT_EQ(loaded->normals.size(), loaded->positions.size());
            for (const glm::vec3& n : loaded->normals)
                EXPECT_NEAR(glm::length(n), 1.0f, 1e-4f);
            std::filesystem::remove(file);
        }
}

TEST(Mesh, NormalsAreMadeWhenTheFileHasNone) {
    const auto file = std::filesystem::temp_directory_path() / "sgfx_plain.off";
    std::ofstream(file) << "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
    const auto g = loadMesh(file);
    EXPECT_EQ(g->triangleCount(), 2u);
    for (const glm::vec3& n : g->normals)
        EXPECT_NEAR(n.z, 1.0f, 1e-5f);
    std::filesystem::remove(file);
}

TEST(Mesh, BadFilesSayWhy) {
    auto expectError = [](const std::filesystem::path& file, const std::string& needle) {
        try {
            (void)loadMesh(file);
            ADD_FAILURE() << "loaded " << file;
        } catch (const LoadError& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    expectError("/nonexistent/part.stl", "no such file");
    expectError("part.fbx", "is not one of");
    const auto garbage = std::filesystem::temp_directory_path() / "sgfx_garbage.off";
    std::ofstream(garbage) << "this is not an OFF file";
    expectError(garbage, "could not read");
    std::filesystem::remove(garbage);
    auto lines = shapes::box({1, 1, 1});
    lines->mode = PrimitiveMode::Lines;
    EXPECT_THROW(writeMesh(*lines, std::filesystem::temp_directory_path() / "sgfx_lines.obj"), LoadError);
}

// glTF writing: a scene of shapes with materials written as .glb and .gltf loads back through
// loadGltf with the same triangles, positions, attributes and material colours.
#include <sgfx/GltfLoader.h>
#include <sgfx/GltfWriter.h>
#include <sgfx/Group.h>
#include <sgfx/LOD.h>
#include <sgfx/Material.h>
#include <sgfx/ObjWriter.h>
#include <sgfx/Shapes.h>
#include <sgfx/StateSet.h>
#include <sgfx/Visitors.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

using namespace sgfx;

namespace {

std::filesystem::path tempFile(const std::string& name) {
    return std::filesystem::temp_directory_path() /
           ("sgfx_writer_" + std::to_string(::getpid()) + "_" + name);
}

// Each geometry as drawn: world-space corners in draw order, with its attributes and material.
struct Drawn {
    std::string name;
    std::vector<glm::vec3> corners, normals;
    std::vector<glm::vec2> texcoords;
    std::vector<glm::vec4> colors;
    std::shared_ptr<Material> material;
    BlendMode blend = BlendMode::Off;
};

class Flatten : public NodeVisitor {
public:
    Flatten()
        : NodeVisitor(Mode::ActiveChildren) {}
    void apply(Node& n) override {
        if (n.stateSet()) state_.push_back(state_.back().merged(*n.stateSet()));
        traverse(n);
        if (n.stateSet()) state_.pop_back();
    }
    void apply(Transform& t) override {
        const glm::mat4 saved = m_;
        m_ = m_ * t.matrix();
        apply(static_cast<Node&>(t));
        m_ = saved;
    }
    void apply(Geometry& g) override {
        const ResolvedState s = g.stateSet() ? state_.back().merged(*g.stateSet()) : state_.back();
        Drawn d;
        d.name = g.name;
        d.material = s.materialOrNull();
        d.blend = s.blendMode();
        const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(m_)));
        for (std::size_t k = 0; k < g.elementCount(); ++k) {
            const std::uint32_t i = g.indices.empty() ? std::uint32_t(k) : g.indices[k];
            d.corners.push_back(glm::vec3(m_ * glm::vec4(g.positions[i], 1.0f)));
            if (!g.normals.empty()) d.normals.push_back(glm::normalize(nm * g.normals[i]));
            if (!g.texcoords.empty()) d.texcoords.push_back(g.texcoords[i]);
            if (!g.colors.empty()) d.colors.push_back(g.colors[i]);
        }
        out.push_back(std::move(d));
    }
    std::vector<Drawn> out;

private:
    glm::mat4 m_{1.0f};
    std::vector<ResolvedState> state_{ResolvedState{}};
};

std::vector<Drawn> flatten(Node& n) {
    Flatten f;
    n.accept(f);
    return f.out;
}

std::shared_ptr<Material> material(glm::vec4 diffuse, glm::vec3 emissive = glm::vec3(0)) {
    auto m = Material::create();
    m->diffuse = diffuse;
    m->emissive = emissive;
    return m;
}

// A box, a sphere, a cylinder and a cone under rotated, scaled and mirrored transforms, with
// opaque, emissive, blended, masked and default materials, texcoords and vertex colours.
std::shared_ptr<Group> scene() {
    auto root = Group::create();
    auto red = material({0.8f, 0.1f, 0.1f, 1.0f});
    red->model = ShadingModel::MetallicRoughness;
    red->metallic = 0.7f;
    red->roughness = 0.35f;
    auto glowing = material({0.1f, 0.6f, 0.2f, 1.0f}, {0.5f, 0.25f, 0.0f});

    auto t1 = Transform::create(glm::rotate(glm::translate(glm::mat4(1.0f), {2, 0, 1}), 0.6f, {0, 0, 1}));
    auto box = shapes::box({1, 2, 0.5f});
    box->name = "box";
    box->getOrCreateStateSet().material.set(red);
    t1->addChild(box);
    root->addChild(t1);

    auto t2 = Transform::create(glm::scale(glm::translate(glm::mat4(1.0f), {-3, 1, 0}), {1.5f, 1.5f, 1.5f}));
    t2->getOrCreateStateSet().material.set(glowing);
    auto sphere = shapes::sphere(0.7f, 12, 6);
    sphere->name = "sphere";
    t2->addChild(sphere);
    auto glass = shapes::sphere(0.3f, 8, 4);
    glass->name = "glass";
    glass->getOrCreateStateSet().material.set(material({0.9f, 0.9f, 1.0f, 0.4f}));
    glass->getOrCreateStateSet().blend.set(BlendMode::Alpha);
    t2->addChild(glass);
    root->addChild(t2);

    // Mirrored: the writer turns the winding back.
    auto t3 = Transform::create(glm::scale(glm::translate(glm::mat4(1.0f), {0, -4, 0}), {-1, 1, 1}));
    auto cylinder = shapes::cylinder(0.5f, 2.0f, 10);
    cylinder->name = "cylinder"; // default material
    t3->addChild(cylinder);
    root->addChild(t3);

    auto cone = shapes::cone(1.0f, 1.5f, 9);
    cone->name = "cone";
    for (std::size_t i = 0; i < cone->positions.size(); ++i)
        cone->colors.push_back({float(i % 3) / 2.0f, 0.5f, 1.0f - float(i % 5) / 4.0f, 1.0f});
    auto masked = material({1, 1, 1, 1}, {2.0f, 1.0f, 0.5f}); // emission above 1
    masked->alphaCutoff = 0.3f;
    cone->getOrCreateStateSet().material.set(masked);
    root->addChild(cone);

    auto hidden = shapes::box({1, 1, 1});
    hidden->nodeMask = 0; // not written
    root->addChild(hidden);
    return root;
}

void expectSameScene(const std::vector<Drawn>& a, const std::vector<Drawn>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        SCOPED_TRACE(a[i].name);
        ASSERT_EQ(a[i].corners.size(), b[i].corners.size());
        ASSERT_EQ(a[i].normals.size(), b[i].normals.size());
        ASSERT_EQ(a[i].texcoords.size(), b[i].texcoords.size());
        ASSERT_EQ(a[i].colors.size(), b[i].colors.size());
        // The mirrored cylinder comes back with each triangle's last two corners swapped.
        const bool mirrored = a[i].name == "cylinder";
        auto corner = [&](std::size_t k) -> std::size_t {
            if (!mirrored || k % 3 == 0) return k;
            return k % 3 == 1 ? k + 1 : k - 1;
        };
        for (std::size_t k = 0; k < a[i].corners.size(); ++k) {
            const std::size_t j = corner(k);
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(a[i].corners[k][c], b[i].corners[j][c], 1e-5f) << "corner " << k;
            if (!a[i].normals.empty()) {
                EXPECT_GT(glm::dot(a[i].normals[k], b[i].normals[j]), 0.99999f) << "normal " << k;
            }
            if (!a[i].texcoords.empty()) {
                EXPECT_EQ(a[i].texcoords[k], b[i].texcoords[j]);
            }
            if (!a[i].colors.empty()) {
                EXPECT_EQ(a[i].colors[k], b[i].colors[j]);
            }
        }
        ASSERT_EQ(bool(a[i].material), bool(b[i].material));
        if (a[i].material) {
            EXPECT_EQ(a[i].material->diffuse, b[i].material->diffuse);
            const glm::vec3 ea = a[i].material->emissive, eb = b[i].material->emissive;
            // emissiveFactor holds [0, 1]; KHR_materials_emissive_strength carries the rest.
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(ea[c], eb[c], 1e-6f * std::max(1.0f, ea[c]));
            EXPECT_EQ(a[i].material->alphaCutoff, b[i].material->alphaCutoff);
            // glTF materials load as metallic-roughness; Blinn-Phong's shininess survives as the
            // roughness of the same lobe width.
            EXPECT_EQ(b[i].material->model, ShadingModel::MetallicRoughness);
            if (a[i].material->model == ShadingModel::MetallicRoughness) {
                EXPECT_FLOAT_EQ(a[i].material->metallic, b[i].material->metallic);
                EXPECT_FLOAT_EQ(a[i].material->roughness, b[i].material->roughness);
            } else {
                const float r = b[i].material->roughness;
                EXPECT_NEAR(2.0f / (r * r * r * r) - 2.0f, a[i].material->shininess,
                            0.01f * a[i].material->shininess);
                EXPECT_EQ(b[i].material->metallic, 0.0f);
            }
        }
        EXPECT_EQ(a[i].blend != BlendMode::Off, b[i].blend != BlendMode::Off);
    }
}

} // namespace

TEST(GltfWriter, RoundTripsThroughLoadGltfAsGlbAndGltf) {
    auto root = scene();
    const auto original = flatten(*root);
    StatsVisitor stats;
    root->accept(stats);
    for (const char* ext : {".glb", ".gltf"}) {
        SCOPED_TRACE(ext);
        const auto file = tempFile(std::string("scene") + ext);
        const GltfWriteResult written = writeGltf(*root, file);
        EXPECT_EQ(written.meshes, 5u);
        EXPECT_EQ(written.triangles, stats.triangles);
        EXPECT_EQ(written.materials, 4u); // red, glowing, glass (blended), masked; cylinder has none
        GltfStats loadedStats;
        GltfOptions keepOrder; // the comparison below is triangle by triangle
        keepOrder.optimizeOrder = false;
        auto loaded = loadGltf(file, keepOrder, &loadedStats);
        EXPECT_EQ(loadedStats.triangles, stats.triangles);
        EXPECT_EQ(loadedStats.opaque, 2u);
        EXPECT_EQ(loadedStats.masked, 1u);
        EXPECT_EQ(loadedStats.blended, 1u);
        expectSameScene(original, flatten(*loaded));
        // .gltf: one file, the buffer inside it as base64.
        if (std::string(ext) == ".gltf") {
            std::ifstream in(file);
            const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            EXPECT_NE(text.find("data:application/octet-stream;base64,"), std::string::npos);
            EXPECT_NE(text.find("KHR_materials_emissive_strength"), std::string::npos);
        } else {
            std::ifstream in(file, std::ios::binary);
            char magic[4] = {};
            in.read(magic, 4);
            EXPECT_EQ(std::string(magic, 4), "glTF");
        }
        std::filesystem::remove(file);
    }
}

TEST(GltfWriter, WithoutZUpTheFileKeepsSgfxAxes) {
    auto root = Group::create();
    auto q = shapes::quad(1, 1);
    root->addChild(q);
    const auto file = tempFile("axes.glb");
    writeGltf(*root, file, GltfWriteOptions{false});
    GltfOptions keep;
    keep.zUp = false;
    expectSameScene(flatten(*root), flatten(*loadGltf(file, keep)));
    // With zUp (the default for both) a quad facing +Z in sgfx faces +Y in the file: loaded
    // without the turn, its normal is +Y.
    writeGltf(*root, file);
    const auto raw = flatten(*loadGltf(file, keep));
    ASSERT_FALSE(raw.empty());
    EXPECT_NEAR(raw[0].normals[0].y, 1.0f, 1e-6f);
    std::filesystem::remove(file);
}

TEST(GltfWriter, OnlyTheMostDetailedLodLevelIsWritten) {
    // Levels overlap in space: a file gets the one shown nearest (largest pixel range), whatever
    // the order of the children. OBJ alike.
    auto lod = LOD::create();
    lod->addChild(shapes::box({1, 1, 1}), 0.0f, 100.0f);
    lod->addChild(shapes::sphere(1.0f, 16, 8), 100.0f, std::numeric_limits<float>::infinity());
    lod->addChild(shapes::cylinder(0.5f, 1.0f, 12), 20.0f, 60.0f);
    const auto file = tempFile("lod.glb");
    const auto r = writeGltf(*lod, file);
    EXPECT_EQ(r.meshes, 1u);
    EXPECT_EQ(r.triangles, 256u);
    const auto obj = tempFile("lod.obj");
    EXPECT_EQ(writeObj(*lod, obj).triangles, 256u);
    std::filesystem::remove(file);
    std::filesystem::remove(obj);
    std::filesystem::remove(tempFile("lod.mtl"));
}

TEST(GltfWriter, BadPathsAndGeometryAreRefused) {
    auto root = Group::create();
    root->addChild(shapes::box({1, 1, 1}));
    EXPECT_THROW(writeGltf(*root, tempFile("scene.obj")), std::invalid_argument);
    try {
        writeGltf(*root, "/nonexistent-dir/x.glb");
        ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.glb"), std::string::npos) << e.what();
    }
    auto broken = shapes::box({1, 1, 1});
    broken->normals.pop_back();
    root->addChild(broken);
    EXPECT_THROW(writeGltf(*root, tempFile("broken.glb")), std::invalid_argument);
    std::filesystem::remove(tempFile("broken.glb"));
}

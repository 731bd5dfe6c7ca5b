#include "sgfx/GltfWriter.h"

#include "WorldGeometryVisitor.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Material.h>
#include <sgfx/NodeVisitor.h>
#include <sgfx/StateSet.h>

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>

namespace sgfx {

namespace {

// glTF's metallic-roughness as far as a Blinn-Phong material has it: the inverse of loadGltf's
// shininess = 2 / roughness^4 - 2, and no metal. This is where Material's own metallic and
// roughness, once it has them, map instead.
struct MetallicRoughness {
    double metallic = 0.0;
    double roughness = 1.0;
};
MetallicRoughness metallicRoughnessOf(const Material& m) {
    MetallicRoughness mr;
    if (m.model == ShadingModel::MetallicRoughness) {
        mr.metallic = m.metallic;
        mr.roughness = m.roughness;
        return mr;
    }
    // Blinn-Phong: a dielectric whose GGX lobe has the exponent's width (s = 2/α² − 2, α = r²).
    mr.roughness = std::clamp(std::pow(2.0 / (double(m.shininess) + 2.0), 0.25), 0.05, 1.0);
    return mr;
}

// One material per distinct (Material, blended, double-sided): blending and face culling live in
// the state, not in the material, but glTF puts them in the material.
using MaterialKey = std::tuple<const Material*, bool, bool>;

tinygltf::Material toGltf(const Material& m, bool blended, bool doubleSided, std::size_t index) {
    tinygltf::Material out;
    out.name = "material" + std::to_string(index);
    out.pbrMetallicRoughness.baseColorFactor = {m.diffuse.r, m.diffuse.g, m.diffuse.b, m.diffuse.a};
    const MetallicRoughness mr = metallicRoughnessOf(m);
    out.pbrMetallicRoughness.metallicFactor = mr.metallic;
    out.pbrMetallicRoughness.roughnessFactor = mr.roughness;
    // emissiveFactor is limited to [0, 1]: brighter emission goes into the strength extension.
    const double peak = std::max({double(m.emissive.r), double(m.emissive.g), double(m.emissive.b)});
    const double scale = peak > 1.0 ? peak : 1.0;
    out.emissiveFactor = {m.emissive.r / scale, m.emissive.g / scale, m.emissive.b / scale};
    if (peak > 1.0)
        out.extensions["KHR_materials_emissive_strength"] =
            tinygltf::Value(tinygltf::Value::Object{{"emissiveStrength", tinygltf::Value(peak)}});
    if (m.alphaCutoff) {
        out.alphaMode = "MASK";
        out.alphaCutoff = double(*m.alphaCutoff);
    } else if (blended || m.diffuse.a < 1.0f) {
        out.alphaMode = "BLEND";
    } else {
        out.alphaMode = "OPAQUE";
    }
    out.doubleSided = doubleSided;
    return out;
}

class GltfVisitor : public WorldGeometryVisitor {
public:
    GltfVisitor(tinygltf::Model& model, const glm::mat4& root)
        : WorldGeometryVisitor(root)
        , model_(model) {
        model_.buffers.emplace_back();
    }

    GltfWriteResult result;

private:
    // Appends raw bytes as a buffer view (4-byte aligned, as accessors of floats require).
    int view(const void* data, std::size_t bytes, int target) {
        auto& buffer = model_.buffers.front().data;
        buffer.resize((buffer.size() + 3) / 4 * 4);
        tinygltf::BufferView v;
        v.buffer = 0;
        v.byteOffset = buffer.size();
        v.byteLength = bytes;
        v.target = target;
        const auto* p = static_cast<const unsigned char*>(data);
        buffer.insert(buffer.end(), p, p + bytes);
        model_.bufferViews.push_back(v);
        return int(model_.bufferViews.size() - 1);
    }

    template <class T> int accessor(const std::vector<T>& values, int type, int target) {
        tinygltf::Accessor a;
        a.bufferView = view(values.data(), values.size() * sizeof(T), target);
        a.count = values.size();
        a.type = type;
        a.componentType = std::is_same_v<T, std::uint32_t> ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT
                                                           : TINYGLTF_COMPONENT_TYPE_FLOAT;
        model_.accessors.push_back(a);
        return int(model_.accessors.size() - 1);
    }

    int material(const ResolvedState& state) {
        const Material* m = state.materialOrNull().get();
        if (!m) return -1; // glTF's default material, as sgfx's default
        const bool blended = state.blendMode() != BlendMode::Off;
        const bool doubleSided = state.cullFace.value && *state.cullFace.value == CullFace::None;
        auto [it, added] =
            materials_.emplace(MaterialKey{m, blended, doubleSided}, int(model_.materials.size()));
        if (added) model_.materials.push_back(toGltf(*m, blended, doubleSided, model_.materials.size()));
        return it->second;
    }

protected:
    void visit(const Geometry& g, const glm::mat4& world, const ResolvedState& state) override {
        const glm::mat3 linear(world);
        const glm::mat3 normalMatrix = glm::transpose(glm::inverse(linear));
        const bool mirrored = glm::determinant(linear) < 0.0f;
        std::vector<glm::vec3> positions, normals;
        std::vector<glm::vec4> tangents;
        positions.reserve(g.positions.size());
        glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        for (const auto& p : g.positions) {
            positions.push_back(glm::vec3(world * glm::vec4(p, 1.0f)));
            lo = glm::min(lo, positions.back());
            hi = glm::max(hi, positions.back());
        }
        auto unit = [](glm::vec3 v) {
            const float len = glm::length(v);
            return len > 0.0f ? v / len : glm::vec3(0, 0, 1);
        };
        for (const auto& n : g.normals)
            normals.push_back(unit(normalMatrix * n));
        for (const auto& t : g.tangents)
            tangents.emplace_back(unit(linear * glm::vec3(t)), mirrored ? -t.w : t.w);

        tinygltf::Primitive prim;
        prim.attributes["POSITION"] = accessor(positions, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
        auto& pos = model_.accessors.back();
        pos.minValues = {lo.x, lo.y, lo.z};
        pos.maxValues = {hi.x, hi.y, hi.z};
        if (!normals.empty())
            prim.attributes["NORMAL"] = accessor(normals, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
        if (!g.texcoords.empty())
            prim.attributes["TEXCOORD_0"] =
                accessor(g.texcoords, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER);
        if (!tangents.empty())
            prim.attributes["TANGENT"] = accessor(tangents, TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);
        if (!g.colors.empty())
            prim.attributes["COLOR_0"] = accessor(g.colors, TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);

        std::vector<std::uint32_t> indices = g.indices;
        // A mirroring transform turns the winding around: turn it back so front faces stay front
        // (triangle lists only; mirrored strips and fans keep the turned winding).
        if (mirrored && g.mode == PrimitiveMode::Triangles) {
            if (indices.empty())
                for (std::uint32_t i = 0; i < g.positions.size(); ++i)
                    indices.push_back(i);
            for (std::size_t k = 0; k + 2 < indices.size(); k += 3)
                std::swap(indices[k + 1], indices[k + 2]);
        }
        if (!indices.empty())
            prim.indices = accessor(indices, TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        switch (g.mode) {
        case PrimitiveMode::Points:
            prim.mode = TINYGLTF_MODE_POINTS;
            break;
        case PrimitiveMode::Lines:
            prim.mode = TINYGLTF_MODE_LINE;
            break;
        case PrimitiveMode::LineStrip:
            prim.mode = TINYGLTF_MODE_LINE_STRIP;
            break;
        case PrimitiveMode::Triangles:
            prim.mode = TINYGLTF_MODE_TRIANGLES;
            break;
        case PrimitiveMode::TriangleStrip:
            prim.mode = TINYGLTF_MODE_TRIANGLE_STRIP;
            break;
        case PrimitiveMode::TriangleFan:
            prim.mode = TINYGLTF_MODE_TRIANGLE_FAN;
            break;
        }
        prim.material = material(state);

        tinygltf::Mesh mesh;
        mesh.name = g.name;
        mesh.primitives.push_back(std::move(prim));
        model_.meshes.push_back(std::move(mesh));
        tinygltf::Node node;
        node.name = g.name;
        node.mesh = int(model_.meshes.size() - 1);
        model_.nodes.push_back(std::move(node));
        model_.scenes.front().nodes.push_back(int(model_.nodes.size() - 1));

        ++result.meshes;
        result.vertices += g.positions.size();
        result.triangles += g.triangleCount() / g.instanceCount(); // this instance
    }

private:
    tinygltf::Model& model_;
    std::map<MaterialKey, int> materials_;
};

} // namespace

GltfWriteResult writeGltf(Node& root, const std::filesystem::path& path, const GltfWriteOptions& options) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext != ".glb" && ext != ".gltf")
        throw std::invalid_argument("sgfx: writeGltf: '" + path.string() + "' does not end in .glb or .gltf");

    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "sgfx";
    model.scenes.emplace_back();
    model.defaultScene = 0;
    // Z up to Y up, (x, y, z) -> (x, z, -y): the inverse of loadGltf's +90° turn about X.
    glm::mat4 toYUp(1.0f);
    if (options.zUp)
        toYUp = glm::mat4(glm::vec4(1, 0, 0, 0), glm::vec4(0, 0, -1, 0), glm::vec4(0, 1, 0, 0),
                          glm::vec4(0, 0, 0, 1));
    GltfVisitor v(model, toYUp);
    root.accept(v);
    if (model.buffers.front().data.empty()) model.buffers.clear(); // nothing drawn: no empty buffer
    for (const auto& m : model.materials)
        if (!m.extensions.empty()) {
            model.extensionsUsed.push_back("KHR_materials_emissive_strength");
            break;
        }
    v.result.materials = model.materials.size();

    // Through a stream of our own: tinygltf's file writer reports no failure to open the file.
    const bool binary = ext == ".glb";
    std::ofstream out(path, binary ? std::ios::binary : std::ios::out);
    if (!out) throw std::runtime_error("sgfx: cannot write glTF file " + path.string());
    tinygltf::TinyGLTF writer;
    const bool ok = writer.WriteGltfSceneToStream(&model, out, !binary, binary);
    out.close();
    if (!ok || !out) throw std::runtime_error("sgfx: write error on glTF file " + path.string());
    return v.result;
}

} // namespace sgfx

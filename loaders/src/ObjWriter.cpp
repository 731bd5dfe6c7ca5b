#include "sgfx/ObjWriter.h"

#include "WorldGeometryVisitor.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/NodeVisitor.h>
#include <sgfx/StateSet.h>

#include <cstdio>
#include <map>
#include <memory>
#include <stdexcept>

namespace sgfx {

namespace {

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

class ObjVisitor : public WorldGeometryVisitor {
public:
    explicit ObjVisitor(std::FILE* obj)
        : obj_(obj) {}

protected:
    void visit(const Geometry& g, const glm::mat4& world, const ResolvedState& state) override {
        if (g.mode != PrimitiveMode::Triangles) return;
        const Material* mat = state.materialOrNull().get();
        auto [it, added] = materials.emplace(mat, "m" + std::to_string(materials.size()));
        std::fprintf(obj_, "o %s_%zu\nusemtl %s\n", g.name.empty() ? "geometry" : g.name.c_str(),
                     result.objects, it->second.c_str());
        const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(world)));
        for (const auto& p : g.positions) {
            const glm::vec3 w = glm::vec3(world * glm::vec4(p, 1));
            std::fprintf(obj_, "v %.6g %.6g %.6g\n", w.x, w.y, w.z);
        }
        const bool normals = !g.normals.empty();
        for (const auto& n : g.normals) {
            const glm::vec3 w = glm::normalize(nm * n);
            std::fprintf(obj_, "vn %.5g %.5g %.5g\n", w.x, w.y, w.z);
        }
        const std::size_t count = g.elementCount();
        auto index = [&](std::size_t i) { return g.indices.empty() ? i : std::size_t(g.indices[i]); };
        for (std::size_t i = 0; i + 2 < count; i += 3) {
            std::fprintf(obj_, "f");
            for (std::size_t k = 0; k < 3; ++k) {
                const std::size_t v = base_ + index(i + k) + 1;
                if (normals)
                    std::fprintf(obj_, " %zu//%zu", v, nbase_ + index(i + k) + 1);
                else
                    std::fprintf(obj_, " %zu", v);
            }
            std::fprintf(obj_, "\n");
        }
        base_ += g.positions.size();
        nbase_ += g.normals.size();
        ++result.objects;
        result.vertices += g.positions.size();
        result.triangles += count / 3;
    }

public:
    ObjWriteResult result;
    std::map<const Material*, std::string> materials;

private:
    std::FILE* obj_;
    std::size_t base_ = 0, nbase_ = 0;
};

File open(const std::filesystem::path& p) {
    File f(std::fopen(p.c_str(), "w"));
    if (!f) throw std::runtime_error("sgfx: cannot write OBJ file " + p.string());
    return f;
}

} // namespace

ObjWriteResult writeObj(Node& root, const std::filesystem::path& path) {
    File obj = open(path);
    auto mtlPath = path;
    mtlPath.replace_extension(".mtl");
    std::fprintf(obj.get(), "# written by sgfx\nmtllib %s\n", mtlPath.filename().c_str());
    ObjVisitor v(obj.get());
    root.accept(v);
    File mtl = open(mtlPath);
    for (const auto& [m, name] : v.materials) {
        const Material def;
        const Material& mm = m ? *m : def;
        std::fprintf(
            mtl.get(),
            "newmtl %s\nKa %.4g %.4g %.4g\nKd %.4g %.4g %.4g\nKs %.4g %.4g %.4g\nNs %.4g\nd %.4g\n\n",
            name.c_str(), mm.ambient.r, mm.ambient.g, mm.ambient.b, mm.diffuse.r, mm.diffuse.g, mm.diffuse.b,
            mm.specular.r, mm.specular.g, mm.specular.b, mm.shininess, mm.diffuse.a);
    }
    if (std::ferror(obj.get()) || std::ferror(mtl.get()))
        throw std::runtime_error("sgfx: write error on " + path.string());
    return v.result;
}

} // namespace sgfx

#include "sgfx/ObjWriter.h"

#include "ObjColour.h"
#include "WorldGeometryVisitor.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Image.h>
#include <sgfx/Material.h>
#include <sgfx/NodeVisitor.h>
#include <sgfx/StateSet.h>
#include <sgfx/Texture.h>

#include <algorithm>
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
        // Vertex colours as `v x y z r g b`, sRGB-encoded (ObjColour.h); alpha is not written.
        const bool colours = !g.colors.empty();
        for (std::size_t i = 0; i < g.positions.size(); ++i)
            obj::writeVertex(obj_, glm::vec3(world * glm::vec4(g.positions[i], 1)),
                             colours ? &g.colors[i] : nullptr);
        const bool normals = !g.normals.empty();
        for (const auto& n : g.normals) {
            const glm::vec3 w = glm::normalize(nm * n);
            std::fprintf(obj_, "vn %.5g %.5g %.5g\n", w.x, w.y, w.z);
        }
        // Texture coordinates only where a map needs them; OBJ's origin is bottom-left.
        const bool texcoords = !g.texcoords.empty() && mat && (mat->baseColorTexture || mat->alphaTexture);
        if (texcoords)
            for (const auto& t : g.texcoords)
                std::fprintf(obj_, "vt %.6g %.6g\n", t.x, 1.0f - t.y);
        const std::size_t count = g.elementCount();
        auto index = [&](std::size_t i) { return g.indices.empty() ? i : std::size_t(g.indices[i]); };
        for (std::size_t i = 0; i + 2 < count; i += 3) {
            std::fprintf(obj_, "f");
            for (std::size_t k = 0; k < 3; ++k) {
                const std::size_t v = base_ + index(i + k) + 1;
                const std::size_t t = tbase_ + index(i + k) + 1, n = nbase_ + index(i + k) + 1;
                if (normals && texcoords)
                    std::fprintf(obj_, " %zu/%zu/%zu", v, t, n);
                else if (normals)
                    std::fprintf(obj_, " %zu//%zu", v, n);
                else if (texcoords)
                    std::fprintf(obj_, " %zu/%zu", v, t);
                else
                    std::fprintf(obj_, " %zu", v);
            }
            std::fprintf(obj_, "\n");
        }
        base_ += g.positions.size();
        nbase_ += g.normals.size();
        if (texcoords) tbase_ += g.texcoords.size();
        ++result.objects;
        result.vertices += g.positions.size();
        result.triangles += count / 3;
    }

public:
    ObjWriteResult result;
    std::map<const Material*, std::string> materials;

private:
    std::FILE* obj_;
    std::size_t base_ = 0, nbase_ = 0, tbase_ = 0;
};

File open(const std::filesystem::path& p) {
    File f(std::fopen(p.c_str(), "w"));
    if (!f) throw std::runtime_error("sgfx: cannot write OBJ file " + p.string());
    return f;
}

// The material's base colour map with its alpha map folded into the alpha channel, as one RGBA
// image for map_Kd (what OBJ readers such as OpenSceneGraph's take); null without either map.
std::shared_ptr<Image> diffuseMap(const Material& m) {
    const Image* base = m.baseColorTexture ? m.baseColorTexture->image.get() : nullptr;
    const Image* alpha = m.alphaTexture ? m.alphaTexture->image.get() : nullptr;
    if (base && base->pixels.empty()) base = nullptr;
    if (alpha &&
        (alpha->pixels.empty() || (base && (alpha->width != base->width || alpha->height != base->height))))
        alpha = nullptr; // maps of different sizes: the colour map alone
    const Image* size = base ? base : alpha;
    if (!size) return nullptr;
    auto out = Image::create(size->width, size->height, 4);
    for (int y = 0; y < size->height; ++y)
        for (int x = 0; x < size->width; ++x) {
            std::uint8_t* o = out->pixel(x, y);
            o[0] = o[1] = o[2] = o[3] = 255;
            if (base) {
                const std::uint8_t* b = base->pixel(x, y);
                for (int c = 0; c < 3; ++c)
                    o[c] = b[std::min(c, base->channels - 1)];
                if (base->channels == 4 || base->channels == 2) o[3] = b[base->channels - 1];
            }
            if (alpha) o[3] = std::uint8_t(o[3] * alpha->pixel(x, y)[0] / 255);
        }
    return out;
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
        // Linear values, as loadMeshModel reads them back; Ke only when the material glows.
        std::fprintf(mtl.get(),
                     "newmtl %s\nKa %.6g %.6g %.6g\nKd %.6g %.6g %.6g\nKs %.6g %.6g %.6g\nNs %.6g\nd %.6g\n",
                     name.c_str(), mm.ambient.r, mm.ambient.g, mm.ambient.b, mm.diffuse.r, mm.diffuse.g,
                     mm.diffuse.b, mm.specular.r, mm.specular.g, mm.specular.b, mm.shininess, mm.diffuse.a);
        if (mm.emissive != glm::vec3(0.0f))
            std::fprintf(mtl.get(), "Ke %.6g %.6g %.6g\n", mm.emissive.r, mm.emissive.g, mm.emissive.b);
        std::fprintf(mtl.get(), "\n");
        if (const auto image = diffuseMap(mm)) {
            auto png = path;
            png.replace_filename(path.stem().string() + "_" + name + ".png");
            writePng(png, *image);
            std::fprintf(mtl.get(), "map_Kd %s\n\n", png.filename().c_str());
            ++v.result.textures;
        }
    }
    if (std::ferror(obj.get()) || std::ferror(mtl.get()))
        throw std::runtime_error("sgfx: write error on " + path.string());
    return v.result;
}

} // namespace sgfx

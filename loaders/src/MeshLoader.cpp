#include "sgfx/MeshLoader.h"

#include "ObjColour.h"

// OpenMesh wants its IO header before the kernel headers.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

namespace sgfx {

namespace {

using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& why) {
    throw LoadError("sgfx: mesh '" + file.string() + "': " + why);
}

std::string extensionOf(const std::filesystem::path& file) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

void checkExtension(const std::filesystem::path& file) {
    const std::string ext = extensionOf(file);
    if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl")
        fail(file, "'" + ext + "' is not one of .obj, .off, .ply, .stl");
}

// The OBJ file's vertex colours for the mesh OpenMesh read from it: its vertices are the file's
// `v` lines in order, then copies of them made for faces that would not fit a manifold mesh
// (OpenMesh's ImporterT copies the point only), which take the colour of the first file vertex at
// the same position.
std::vector<glm::vec4> objColours(const std::filesystem::path& file, const Mesh& mesh,
                                  const std::vector<glm::vec4>& colours) {
    if (colours.empty()) return {};
    if (mesh.n_vertices() < colours.size())
        fail(file, "OpenMesh read " + std::to_string(mesh.n_vertices()) + " of its " +
                       std::to_string(colours.size()) + " vertices: their colours cannot be matched");
    std::vector<glm::vec4> out(colours);
    std::map<std::array<float, 3>, std::size_t> firstAt;
    for (std::size_t i = colours.size(); i < mesh.n_vertices(); ++i) {
        if (firstAt.empty())
            for (std::size_t k = colours.size(); k-- > 0;) {
                const auto p = mesh.point(Mesh::VertexHandle(int(k)));
                firstAt[{p[0], p[1], p[2]}] = k;
            }
        const auto p = mesh.point(Mesh::VertexHandle(int(i)));
        const auto it = firstAt.find({p[0], p[1], p[2]});
        out.push_back(it == firstAt.end() ? glm::vec4(1.0f) : colours[it->second]);
    }
    return out;
}

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

// OpenMesh's OBJ writer has no vertex colours: a geometry with colours is written here, in the form
// that loadMesh and loadMeshModel read back (`v x y z r g b`, sRGB-encoded; ObjColour.h).
void writeColouredObj(const Geometry& g, const std::filesystem::path& file) {
    std::unique_ptr<std::FILE, FileCloser> f(std::fopen(file.c_str(), "w"));
    if (!f) fail(file, "cannot be written");
    std::fprintf(f.get(), "# written by sgfx\n");
    for (std::size_t i = 0; i < g.positions.size(); ++i)
        obj::writeVertex(f.get(), g.positions[i], &g.colors[i]);
    for (const glm::vec3& n : g.normals)
        std::fprintf(f.get(), "vn %.6g %.6g %.6g\n", double(n.x), double(n.y), double(n.z));
    const std::size_t n = g.elementCount();
    for (std::size_t k = 0; k + 2 < n; k += 3) {
        std::fprintf(f.get(), "f");
        for (std::size_t j = k; j < k + 3; ++j) {
            const std::size_t v = (g.indices.empty() ? j : std::size_t(g.indices[j])) + 1;
            if (g.normals.empty())
                std::fprintf(f.get(), " %zu", v);
            else
                std::fprintf(f.get(), " %zu//%zu", v, v);
        }
        std::fprintf(f.get(), "\n");
    }
    if (std::ferror(f.get())) fail(file, "write error");
}

} // namespace

std::shared_ptr<Geometry> loadMesh(const std::filesystem::path& file) {
    checkExtension(file);
    if (!std::filesystem::is_regular_file(file)) fail(file, "no such file");
    // OBJ vertex colours: read (and their lines checked) by sgfx, as loadMeshModel reads them.
    const std::vector<glm::vec4> colours =
        extensionOf(file) == ".obj" ? obj::readVertexColours(file) : std::vector<glm::vec4>();
    Mesh mesh;
    mesh.request_vertex_normals();
    OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexNormal;
    if (!OpenMesh::IO::read_mesh(mesh, file.string(), options))
        fail(file, "OpenMesh could not read it (not a valid " + extensionOf(file) + " file)");
    if (mesh.n_faces() == 0) fail(file, "has no faces");
    // STL holds face normals only; other formats may have none.
    if (!options.check(OpenMesh::IO::Options::VertexNormal) || extensionOf(file) == ".stl") {
        // Smooth normals from the faces around each vertex.
        mesh.request_face_normals();
        mesh.update_normals();
    }
    auto g = Geometry::create();
    g->name = file.filename().string();
    g->positions.reserve(mesh.n_vertices());
    for (const auto v : mesh.vertices()) {
        const auto p = mesh.point(v);
        const auto n = mesh.normal(v);
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            fail(file, "vertex " + std::to_string(v.idx()) + " has a NaN or infinite coordinate");
        g->positions.emplace_back(p[0], p[1], p[2]);
        glm::vec3 nn(n[0], n[1], n[2]);
        const float len = glm::length(nn);
        g->normals.push_back(len > 0.0f && std::isfinite(len) ? nn / len : glm::vec3(0, 0, 1));
    }
    for (const auto f : mesh.faces())
        for (const auto v : mesh.fv_range(f))
            g->indices.push_back(std::uint32_t(v.idx()));
    g->colors = objColours(file, mesh, colours);
    g->validate();
    return g;
}

void writeMesh(const Geometry& g, const std::filesystem::path& file) {
    checkExtension(file);
    if (g.mode != PrimitiveMode::Triangles) fail(file, "only triangle geometry can be written");
    g.validate();
    if (!g.colors.empty() && extensionOf(file) == ".obj") return writeColouredObj(g, file);
    Mesh mesh;
    mesh.request_vertex_normals();
    std::vector<Mesh::VertexHandle> handles;
    handles.reserve(g.positions.size());
    for (std::size_t i = 0; i < g.positions.size(); ++i) {
        const glm::vec3& p = g.positions[i];
        handles.push_back(mesh.add_vertex(Mesh::Point(p.x, p.y, p.z)));
        if (!g.normals.empty())
            mesh.set_normal(handles.back(), Mesh::Normal(g.normals[i].x, g.normals[i].y, g.normals[i].z));
    }
    const std::size_t n = g.elementCount();
    for (std::size_t k = 0; k + 2 < n; k += 3) {
        auto at = [&](std::size_t j) { return g.indices.empty() ? handles[j] : handles[g.indices[j]]; };
        mesh.add_face(at(k), at(k + 1), at(k + 2));
    }
    OpenMesh::IO::Options options;
    if (!g.normals.empty()) options += OpenMesh::IO::Options::VertexNormal;
    if (extensionOf(file) == ".stl") options = OpenMesh::IO::Options::Binary; // compact, and unambiguous
    if (!OpenMesh::IO::write_mesh(mesh, file.string(), options)) fail(file, "OpenMesh could not write it");
}

} // namespace sgfx

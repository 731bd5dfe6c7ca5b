// OBJ with MTL materials. OpenMesh's OBJ reader keeps one normal per vertex (not per corner), only
// tells faces apart by a texture index and colour (materials without map_Kd, or with equal Kd, cannot
// be told apart; Ks, Ns, Ke and d are lost) and drops faces it cannot add to a manifold mesh, so the
// faces, their `usemtl` ranges and the MTL file are read here; other formats go through loadMesh.
// Vertex colours (`v x y z r g b`, ObjColour.h) become Geometry::colors, decoded to linear; loadMesh
// reads them for its OBJ files through obj::readVertexColours.
#include "sgfx/MeshLoader.h"

#include "ObjColour.h"

#include <sgfx/Image.h>
#include <sgfx/Material.h>
#include <sgfx/StateSet.h>
#include <sgfx/Texture.h>

#include <stb_image.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>

namespace sgfx {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

// The line after its keyword, trimmed: names may contain spaces.
std::string rest(const std::string& line, const std::vector<std::string>& t) {
    std::string r = line.substr(line.find(t[0]) + t[0].size());
    const auto first = r.find_first_not_of(" \t");
    r = first == std::string::npos ? std::string() : r.substr(first);
    while (!r.empty() && std::isspace(static_cast<unsigned char>(r.back())))
        r.pop_back();
    return r;
}

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> out;
    std::istringstream in(line);
    for (std::string t; in >> t;)
        out.push_back(t);
    return out;
}

// One text file read line by line; errors name file:line.
struct Lines {
    std::filesystem::path file;
    std::ifstream in;
    std::size_t number = 0;
    std::string kind; // "OBJ" or "MTL"

    bool next(std::string& line) {
        if (!std::getline(in, line)) return false;
        ++number;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        return true;
    }
    [[noreturn]] void fail(const std::string& why) const {
        throw LoadError("sgfx: " + kind + " '" + file.string() + ":" + std::to_string(number) + "': " + why);
    }
    float number_(const std::string& token) const {
        float v = 0.0f;
        const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
        if (ec != std::errc() || end != token.data() + token.size() || !std::isfinite(v))
            fail("'" + token + "' is not a number");
        return v;
    }
    // `n` numbers after the keyword (at least `min`; missing ones repeat the first, as MTL allows
    // "Kd 0.5" for grey).
    std::vector<float> numbers(const std::vector<std::string>& t, std::size_t min, std::size_t n) const {
        if (t.size() - 1 < min || t.size() - 1 > n)
            fail("'" + t[0] + "' takes " +
                 (min == n ? std::to_string(n) : std::to_string(min) + ".." + std::to_string(n)) +
                 " numbers, not " + std::to_string(t.size() - 1));
        std::vector<float> v;
        for (std::size_t i = 1; i < t.size(); ++i)
            v.push_back(number_(t[i]));
        while (v.size() < n)
            v.push_back(v.front());
        return v;
    }
};

Lines open(const std::filesystem::path& file, const char* kind) {
    Lines l{file, std::ifstream(file), 0, kind};
    if (!l.in) throw LoadError(std::string("sgfx: ") + kind + " '" + file.string() + "': cannot be read");
    return l;
}

struct MtlMaterial {
    std::shared_ptr<Material> material = Material::create();
    bool ambientSet = false, blend = false;
    std::size_t line = 0;
};

// The file name of a map_ statement: its options (-o 1 1 1, -bm 0.5, ...) skipped.
std::string mapFile(const Lines& l, const std::vector<std::string>& t) {
    static const std::map<std::string, int> argCount = {
        {"-blendu", 1},  {"-blendv", 1}, {"-boost", 1}, {"-cc", 1}, {"-clamp", 1},
        {"-imfchan", 1}, {"-mm", 2},     {"-o", 3},     {"-s", 3},  {"-t", 3},
        {"-texres", 1},  {"-type", 1},   {"-bm", 1}};
    std::size_t i = 1;
    while (i < t.size() && t[i].size() > 1 && t[i][0] == '-') {
        const auto it = argCount.find(t[i]);
        if (it == argCount.end()) l.fail("unknown option '" + t[i] + "' of " + t[0]);
        ++i;
        // -o, -s and -t take 1 to 3 numbers; the file name is always last.
        for (int k = 0; k < it->second && i < t.size() - 1; ++k, ++i) {
            float v = 0.0f;
            if (it->second == 3 && k > 0 &&
                std::from_chars(t[i].data(), t[i].data() + t[i].size(), v).ec != std::errc())
                break;
        }
    }
    if (i >= t.size()) l.fail("'" + t[0] + "' names no file");
    std::string name = t[i];
    for (++i; i < t.size(); ++i)
        name += " " + t[i];
    return name;
}

std::shared_ptr<Texture>
loadTexture(const std::filesystem::path& mtl, const std::string& material, const std::filesystem::path& image,
            bool srgb, std::map<std::pair<std::string, bool>, std::shared_ptr<Texture>>& cache) {
    const std::string key = image.string();
    if (auto it = cache.find({key, srgb}); it != cache.end()) return it->second;
    auto fail = [&](const std::string& why) {
        throw LoadError("sgfx: MTL '" + mtl.string() + "': material '" + material + "': texture '" + key +
                        "' " + why);
    };
    std::error_code ec;
    if (!std::filesystem::is_regular_file(image, ec)) fail("does not exist");
    int w = 0, h = 0, comp = 0;
    stbi_uc* data = stbi_load(key.c_str(), &w, &h, &comp, 4);
    if (!data) fail(std::string("cannot be decoded: ") + stbi_failure_reason());
    auto img = Image::create(w, h, 4);
    img->pixels.assign(data, data + std::size_t(w) * std::size_t(h) * 4);
    stbi_image_free(data);
    auto tex = Texture::create(img, srgb);
    cache[{key, srgb}] = tex;
    return tex;
}

std::map<std::string, MtlMaterial> readMtl(const std::filesystem::path& file) {
    std::map<std::string, MtlMaterial> out;
    Lines l = open(file, "MTL");
    std::map<std::pair<std::string, bool>, std::shared_ptr<Texture>> textures;
    MtlMaterial* m = nullptr;
    std::string name;
    const std::filesystem::path dir = file.parent_path();
    for (std::string line; l.next(line);) {
        const auto t = split(line);
        if (t.empty()) continue;
        const std::string key = lower(t[0]);
        if (key == "newmtl") {
            if (t.size() < 2) l.fail("'newmtl' names no material");
            name = rest(line, t);
            m = &out[name];
            *m = MtlMaterial{};
            m->line = l.number;
            continue;
        }
        if (key == "illum" || key == "ni" || key == "tf" || key == "sharpness" || key == "map_ka" ||
            key == "map_ks" || key == "map_ke" || key == "map_ns" || key == "disp" || key == "decal" ||
            key == "refl" || key == "pr" || key == "pm")
            continue; // not part of sgfx's material model
        if (!m) l.fail("'" + t[0] + "' comes before any 'newmtl'");
        Material& mat = *m->material;
        auto colour = [&] {
            if (t.size() > 1 && (t[1] == "spectral" || t[1] == "xyz"))
                l.fail("only RGB colours are supported");
            const auto v = l.numbers(t, 1, 3);
            for (float c : v)
                if (c < 0.0f) l.fail("colour component " + std::to_string(c) + " is negative");
            return glm::vec3(v[0], v[1], v[2]);
        };
        if (key == "kd") {
            const glm::vec3 c = colour();
            mat.diffuse = glm::vec4(c, mat.diffuse.a);
            if (!m->ambientSet) mat.ambient = c;
        } else if (key == "ka") {
            mat.ambient = colour();
            m->ambientSet = true;
        } else if (key == "ks") {
            mat.specular = colour();
        } else if (key == "ke") {
            mat.emissive = colour();
        } else if (key == "ns") {
            const float ns = l.numbers(t, 1, 1)[0];
            if (ns < 0.0f) l.fail("Ns " + t[1] + " is negative");
            mat.shininess = ns;
        } else if (key == "d" || key == "tr") {
            const std::size_t first = t.size() > 1 && t[1] == "-halo" ? 2 : 1; // halo: ignored
            const float v = l.number_(t.size() > first ? t[first] : std::string("?"));
            if (t.size() != first + 1 || v < 0.0f || v > 1.0f)
                l.fail("'" + t[0] + "' takes one number in [0, 1]");
            mat.diffuse.a = key == "d" ? v : 1.0f - v;
            m->blend = mat.diffuse.a < 1.0f || mat.alphaTexture;
        } else if (key == "map_kd") {
            mat.baseColorTexture = loadTexture(file, name, dir / mapFile(l, t), true, textures);
        } else if (key == "map_d") {
            mat.alphaTexture = loadTexture(file, name, dir / mapFile(l, t), false, textures);
            m->blend = true;
        } else if (key == "map_bump" || key == "bump" || key == "norm") {
            mat.normalTexture = loadTexture(file, name, dir / mapFile(l, t), false, textures);
        } else {
            l.fail("unknown statement '" + t[0] + "'");
        }
    }
    return out;
}

// Vertex colours as the `v` lines give them (ObjColour.h): the numbers, and which vertices have them.
struct VertexColours {
    std::vector<glm::vec3> raw; // one per vertex, (1, 1, 1) for a vertex without a colour
    std::vector<bool> has;
    bool any = false;
    bool bytes = false; // a component above 1: the file's colours are 0..255

    // Linear, alpha 1; white for a vertex without a colour.
    glm::vec4 linear(std::size_t vertex) const {
        if (!has[vertex]) return glm::vec4(1.0f);
        const glm::vec3 s = raw[vertex] / (bytes ? 255.0f : 1.0f);
        return {obj::srgbToLinear(s.r), obj::srgbToLinear(s.g), obj::srgbToLinear(s.b), 1.0f};
    }
};

// A `v` line: x y z; x y z w (the weight of a rational curve's control point: ignored); or
// x y z r g b, a vertex colour (ObjColour.h). Returns the position, adds the colour.
glm::vec3 readVertex(const Lines& l, const std::vector<std::string>& t, VertexColours& colours) {
    if (t.size() != 4 && t.size() != 5 && t.size() != 7)
        l.fail("'v' takes 3, 4 or 6 numbers (x y z, x y z w or x y z r g b), not " +
               std::to_string(t.size() - 1));
    const glm::vec3 p(l.number_(t[1]), l.number_(t[2]), l.number_(t[3]));
    if (t.size() == 5) (void)l.number_(t[4]);
    glm::vec3 c(1.0f);
    if (t.size() == 7) {
        for (int k = 0; k < 3; ++k) {
            const std::string& s = t[std::size_t(4 + k)];
            c[k] = l.number_(s);
            if (c[k] < 0.0f) l.fail("colour component '" + s + "' is negative");
            if (c[k] > 255.0f)
                l.fail("colour component '" + s +
                       "' is above 255 (colours are 0..1, or 0..255 in a file where "
                       "any component is above 1)");
            colours.bytes = colours.bytes || c[k] > 1.0f;
        }
        colours.any = true;
    }
    colours.raw.push_back(c);
    colours.has.push_back(t.size() == 7);
    return p;
}

// The vertex of one face corner: position, texcoord and normal indices (-1: none).
using Corner = std::array<long, 3>;
struct CornerHash {
    std::size_t operator()(const Corner& c) const {
        return std::hash<long>()(c[0]) * 31u * 31u + std::hash<long>()(c[1]) * 31u + std::hash<long>()(c[2]);
    }
};

struct Group_ {
    std::string material;
    std::vector<Corner> corners; // three per triangle
};

// What the `v`, `vt` and `vn` lines gave, and the smooth normals made for corners without one.
struct Vertices {
    const std::vector<glm::vec3>& positions;
    const std::vector<glm::vec3>& normals;
    const std::vector<glm::vec2>& texcoords;
    const std::vector<glm::vec3>& smooth;
    const VertexColours& colours;
};

// One vertex per distinct (position, texcoord, normal) of the group's corners: glTF-style
// attributes. Texcoords when a corner has one, colours when a corner's position has one.
std::shared_ptr<Geometry> buildGeometry(const Group_& g, const Vertices& v) {
    auto geometry = Geometry::create();
    const bool uv =
        std::any_of(g.corners.begin(), g.corners.end(), [](const Corner& c) { return c[1] >= 0; });
    const bool coloured =
        v.colours.any && std::any_of(g.corners.begin(), g.corners.end(),
                                     [&](const Corner& c) { return v.colours.has[std::size_t(c[0])]; });
    std::unordered_map<Corner, std::uint32_t, CornerHash> vertexOf;
    for (const Corner& c : g.corners) {
        auto [it, added] = vertexOf.try_emplace(c, std::uint32_t(geometry->positions.size()));
        if (added) {
            geometry->positions.push_back(v.positions[std::size_t(c[0])]);
            glm::vec3 n = c[2] >= 0 ? v.normals[std::size_t(c[2])] : v.smooth[std::size_t(c[0])];
            const float len = glm::length(n);
            geometry->normals.push_back(len > 0.0f && std::isfinite(len) ? n / len : glm::vec3(0, 0, 1));
            if (uv)
                geometry->texcoords.push_back(c[1] >= 0 ? v.texcoords[std::size_t(c[1])] : glm::vec2(0.0f));
            if (coloured) geometry->colors.push_back(v.colours.linear(std::size_t(c[0])));
        }
        geometry->indices.push_back(it->second);
    }
    return geometry;
}

std::shared_ptr<Group> loadObj(const std::filesystem::path& file) {
    Lines l = open(file, "OBJ");
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> texcoords;
    VertexColours colours;
    std::vector<Group_> groups;
    std::map<std::string, std::size_t> groupOf;
    std::map<std::string, MtlMaterial> materials;
    std::size_t current = SIZE_MAX;
    auto use = [&](const std::string& material) {
        auto [it, added] = groupOf.try_emplace(material, groups.size());
        if (added) groups.push_back({material, {}});
        current = it->second;
    };
    for (std::string line; l.next(line);) {
        const auto t = split(line);
        if (t.empty()) continue;
        const std::string& key = t[0];
        if (key == "v") {
            positions.push_back(readVertex(l, t, colours));
        } else if (key == "vt") {
            if (t.size() < 2 || t.size() > 4) l.fail("'vt' takes 1 to 3 numbers");
            const float u = l.number_(t[1]), v = t.size() > 2 ? l.number_(t[2]) : 0.0f;
            texcoords.emplace_back(u, 1.0f - v); // OBJ's origin is bottom-left, sgfx's top-left
        } else if (key == "vn") {
            const auto v = l.numbers(t, 3, 3);
            glm::vec3 n(v[0], v[1], v[2]);
            const float len = glm::length(n);
            normals.push_back(len > 0.0f ? n / len : glm::vec3(0, 0, 1));
        } else if (key == "f") {
            if (t.size() < 4) l.fail("a face needs at least 3 corners");
            if (current == SIZE_MAX) use("");
            std::vector<Corner> face;
            for (std::size_t i = 1; i < t.size(); ++i) {
                Corner c{-1, -1, -1};
                const std::size_t sizes[3] = {positions.size(), texcoords.size(), normals.size()};
                std::size_t field = 0, start = 0;
                const std::string& s = t[i];
                for (; field < 3 && start <= s.size(); ++field) {
                    const std::size_t end = std::min(s.find('/', start), s.size());
                    if (end > start) {
                        long v = 0;
                        const auto [p, ec] = std::from_chars(s.data() + start, s.data() + end, v);
                        if (ec != std::errc() || p != s.data() + end || v == 0)
                            l.fail("'" + s + "' is not a face corner (v, v/vt, v//vn or v/vt/vn)");
                        // 1-based, or negative: counted back from the last one read.
                        const long index = v > 0 ? v - 1 : long(sizes[field]) + v;
                        if (index < 0 || std::size_t(index) >= sizes[field])
                            l.fail("'" + s + "' refers to " +
                                   (field == 0   ? "vertex "
                                    : field == 1 ? "texcoord "
                                                 : "normal ") +
                                   std::to_string(v) + " of " + std::to_string(sizes[field]));
                        c[field] = index;
                    } else if (field == 0) {
                        l.fail("'" + s + "' has no vertex index");
                    }
                    start = end + 1;
                }
                if (start <= s.size()) l.fail("'" + s + "' has more than 3 indices");
                face.push_back(c);
            }
            // Convex polygons as fans, as OpenMesh triangulates them for loadMesh.
            for (std::size_t k = 1; k + 1 < face.size(); ++k)
                for (const Corner& c : {face[0], face[k], face[k + 1]})
                    groups[current].corners.push_back(c);
        } else if (key == "usemtl") {
            use(rest(line, t));
        } else if (key == "mtllib") {
            if (t.size() < 2) l.fail("'mtllib' names no file");
            // One name with spaces, or several names. A missing library is common in exported
            // files: its materials fall back to the default.
            std::vector<std::filesystem::path> libraries{file.parent_path() / rest(line, t)};
            std::error_code ec;
            if (!std::filesystem::is_regular_file(libraries[0], ec)) {
                libraries.clear();
                for (std::size_t i = 1; i < t.size(); ++i)
                    libraries.push_back(file.parent_path() / t[i]);
            }
            for (const auto& mtl : libraries)
                if (std::filesystem::is_regular_file(mtl, ec))
                    for (auto& [name, m] : readMtl(mtl))
                        materials[name] = m;
        } else if (key == "o" || key == "g" || key == "s" || key == "l" || key == "p" || key == "vp" ||
                   key == "cstype" || key == "deg" || key == "curv" || key == "surf" || key == "parm" ||
                   key == "end" || key == "mg" || key == "usemap" || key == "maplib") {
            continue; // grouping, smoothing groups, lines, points and free-form geometry: not drawn
        } else {
            l.fail("unknown statement '" + key + "'");
        }
    }

    // Smooth normals for corners without one: area-weighted face normals around each position.
    std::vector<glm::vec3> smooth;
    for (const Group_& g : groups)
        for (std::size_t k = 0; k + 2 < g.corners.size(); k += 3) {
            if (g.corners[k][2] >= 0 && g.corners[k + 1][2] >= 0 && g.corners[k + 2][2] >= 0) continue;
            if (smooth.empty()) smooth.assign(positions.size(), glm::vec3(0.0f));
            const glm::vec3 n = glm::cross(
                positions[std::size_t(g.corners[k + 1][0])] - positions[std::size_t(g.corners[k][0])],
                positions[std::size_t(g.corners[k + 2][0])] - positions[std::size_t(g.corners[k][0])]);
            for (int j = 0; j < 3; ++j)
                smooth[std::size_t(g.corners[k + std::size_t(j)][0])] += n;
        }

    auto root = Group::create();
    root->name = file.filename().string();
    std::size_t triangles = 0;
    for (const Group_& g : groups) {
        if (g.corners.empty()) continue;
        auto geometry = buildGeometry(g, {positions, normals, texcoords, smooth, colours});
        geometry->name = g.material.empty() ? file.filename().string() : g.material;
        if (const auto m = materials.find(g.material); m != materials.end()) {
            auto state = std::make_shared<StateSet>();
            try {
                m->second.material->validate();
            } catch (const std::invalid_argument& e) {
                throw LoadError("sgfx: OBJ '" + file.string() + "': material '" + g.material +
                                "': " + e.what());
            }
            state->material.set(m->second.material);
            if (m->second.blend) state->blend.set(BlendMode::Alpha);
            geometry->setStateSet(state);
        }
        geometry->validate();
        triangles += geometry->triangleCount();
        root->addChild(geometry);
    }
    if (triangles == 0) throw LoadError("sgfx: OBJ '" + file.string() + "': has no faces");
    return root;
}

} // namespace

std::vector<glm::vec4> obj::readVertexColours(const std::filesystem::path& file) {
    Lines l = open(file, "OBJ");
    VertexColours colours;
    for (std::string line; l.next(line);) {
        // Only `v` lines are split: faces and the rest are OpenMesh's to read.
        const auto first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line[first] != 'v' || first + 1 >= line.size() ||
            !std::isspace(static_cast<unsigned char>(line[first + 1])))
            continue;
        (void)readVertex(l, split(line), colours);
    }
    std::vector<glm::vec4> out;
    for (std::size_t i = 0; colours.any && i < colours.has.size(); ++i)
        out.push_back(colours.linear(i));
    return out;
}

std::shared_ptr<Group> loadMeshModel(const std::filesystem::path& file) {
    std::string ext = lower(file.extension().string());
    if (ext != ".obj") {
        auto root = Group::create();
        root->name = file.filename().string();
        root->addChild(loadMesh(file)); // checks the extension and names the accepted ones
        return root;
    }
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        throw LoadError("sgfx: mesh '" + file.string() + "': no such file");
    return loadObj(file);
}

} // namespace sgfx

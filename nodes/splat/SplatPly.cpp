// The 3D Gaussian splatting PLY (Kerbl et al. 2023, the reference's save_ply): one vertex
// element of float properties. Every count is checked against the file's size before anything
// is allocated; every value is checked finite.
#include <sgfx/nodes/splat/SplatCloud.h>

#include <sgfx/LoadError.h>

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {

struct Property {
    std::string name, type;
    int size = 0;
};

struct Header {
    bool ascii = false;
    std::size_t count = 0, bodyOffset = 0, stride = 0;
    std::vector<Property> properties;
    std::map<std::string, std::size_t> index; // name -> position in properties
};

int typeSize(const std::string& t) {
    static const std::map<std::string, int> sizes = {
        {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
        {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
        {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
    const auto it = sizes.find(t);
    return it == sizes.end() ? 0 : it->second;
}

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what) {
    throw LoadError("sgfx: splat PLY '" + file.string() + "': " + what);
}

Header readHeader(std::istream& in, const std::filesystem::path& file) {
    Header h;
    std::string line;
    if (!std::getline(in, line) || line.substr(0, 3) != "ply") fail(file, "not a PLY file (no 'ply' line)");
    bool inVertex = false, sawVertex = false, sawFormat = false;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream words(line);
        std::string key;
        words >> key;
        if (key == "end_header") {
            if (!sawFormat) fail(file, "the header has no format line");
            if (!sawVertex) fail(file, "the header declares no 'vertex' element");
            h.bodyOffset = std::size_t(in.tellg());
            return h;
        }
        if (key == "format") {
            std::string f;
            words >> f;
            if (f == "ascii")
                h.ascii = true;
            else if (f != "binary_little_endian")
                fail(file, "format '" + f + "' is not read (binary_little_endian or ascii)");
            sawFormat = true;
        } else if (key == "element") {
            std::string name;
            long long n = -1;
            words >> name >> n;
            if (name != "vertex") {
                if (!sawVertex) fail(file, "element '" + name + "' before the vertex element is not read");
                inVertex = false; // elements after the splats are ignored
                continue;
            }
            if (n < 0 || n > (1ll << 30))
                fail(file, "element vertex count " + std::to_string(n) + " is outside [0, 2^30]");
            h.count = std::size_t(n);
            inVertex = sawVertex = true;
        } else if (key == "property" && inVertex) {
            Property p;
            words >> p.type;
            if (p.type == "list") fail(file, "vertex property lists are not splat properties");
            words >> p.name;
            p.size = typeSize(p.type);
            if (p.size == 0) fail(file, "property '" + p.name + "' has unknown type '" + p.type + "'");
            h.index[p.name] = h.properties.size();
            h.stride += std::size_t(p.size);
            h.properties.push_back(p);
        } else if (key != "comment" && key != "obj_info" && key != "property" && !key.empty()) {
            fail(file, "unexpected header line '" + line + "'");
        }
    }
    fail(file, "the header has no end_header line");
}

// The columns the splats need, in the order the cloud fills them, and the f_rest count.
std::vector<std::size_t> columns(const Header& h, const std::filesystem::path& file, int& degree) {
    std::vector<std::string> names = {"x",      "y",       "z",       "f_dc_0",  "f_dc_1",
                                      "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2",
                                      "rot_0",  "rot_1",   "rot_2",   "rot_3"};
    int rest = 0;
    while (h.index.count("f_rest_" + std::to_string(rest)))
        ++rest;
    static const int restByDegree[4] = {0, 9, 24, 45};
    const int* found = std::find(restByDegree, restByDegree + 4, rest);
    if (found == restByDegree + 4)
        fail(file, "property f_rest_" + std::to_string(rest) + " is missing: " + std::to_string(rest) +
                       " f_rest properties is not 0, 9, 24 or 45 (SH degree 0 to 3)");
    degree = int(found - restByDegree);
    for (int i = 0; i < rest; ++i)
        names.push_back("f_rest_" + std::to_string(i));
    std::vector<std::size_t> cols;
    for (const std::string& n : names) {
        const auto it = h.index.find(n);
        if (it == h.index.end()) fail(file, "vertex property '" + n + "' is missing");
        const Property& p = h.properties[it->second];
        if (p.type != "float" && p.type != "float32")
            fail(file, "vertex property '" + n + "' has type '" + p.type + "'; splat properties are float");
        cols.push_back(it->second);
    }
    return cols;
}

// Reads the body into rows of floats (one per property; the splat properties are float, the
// others are converted only to be skipped).
void readRow(std::istream& in, const Header& h, std::vector<float>& row, std::size_t splat,
             const std::filesystem::path& file) {
    if (h.ascii) {
        for (std::size_t p = 0; p < h.properties.size(); ++p) {
            double v = 0.0;
            if (!(in >> v))
                fail(file, "element vertex: the file ends (or is not a number) at splat " +
                               std::to_string(splat) + " of " + std::to_string(h.count) + ", property '" +
                               h.properties[p].name + "'");
            row[p] = float(v);
        }
        return;
    }
    char bytes[8];
    for (std::size_t p = 0; p < h.properties.size(); ++p) {
        const Property& prop = h.properties[p];
        if (!in.read(bytes, prop.size))
            fail(file, "element vertex: the file is truncated at splat " + std::to_string(splat) + " of " +
                           std::to_string(h.count) + ", property '" + prop.name + "'");
        float f = 0.0f;
        if (prop.size == 4 && (prop.type == "float" || prop.type == "float32")) std::memcpy(&f, bytes, 4);
        row[p] = f;
    }
}

} // namespace

namespace splat {

bool isSplatPly(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) return false;
    try {
        const Header h = readHeader(in, file);
        for (const char* n : {"f_dc_0", "opacity", "scale_0", "rot_0"})
            if (!h.index.count(n)) return false;
        return true;
    } catch (const LoadError&) {
        return false;
    }
}

SplatCloud loadPly(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) fail(file, "cannot open the file");
    in.seekg(0, std::ios::end);
    const auto fileSize = std::size_t(in.tellg());
    in.seekg(0);
    const Header h = readHeader(in, file);
    int degree = 0;
    const std::vector<std::size_t> cols = columns(h, file, degree);
    // Bound memory by the file before allocating: a binary body is count × stride bytes, an ascii
    // one at least two characters per value.
    const std::size_t body = fileSize - h.bodyOffset;
    const std::size_t need = h.ascii ? h.count * h.properties.size() * 2 : h.count * h.stride;
    if (need > body)
        fail(file, "element vertex declares " + std::to_string(h.count) + " splats (" + std::to_string(need) +
                       " bytes) but " + std::to_string(body) + " bytes follow the header");
    SplatCloud c;
    c.shDegree = degree;
    const int k = c.coefficients();
    c.positions.resize(h.count);
    c.scales.resize(h.count);
    c.rotations.resize(h.count);
    c.opacities.resize(h.count);
    c.sh.resize(h.count * std::size_t(k));
    std::vector<float> row(h.properties.size());
    for (std::size_t i = 0; i < h.count; ++i) {
        readRow(in, h, row, i, file);
        auto v = [&](std::size_t col) {
            const float f = row[cols[col]];
            if (!std::isfinite(f))
                fail(file, "element vertex " + std::to_string(i) + ": property '" +
                               h.properties[cols[col]].name + "' is not finite");
            return f;
        };
        c.positions[i] = {v(0), v(1), v(2)};
        c.opacities[i] = 1.0f / (1.0f + std::exp(-v(6)));
        c.scales[i] = glm::exp(glm::vec3(v(7), v(8), v(9)));
        glm::vec4 q(v(10), v(11), v(12), v(13));
        const float len = glm::length(q);
        if (!(len > 0.0f) || !std::isfinite(len) ||
            !std::isfinite(c.scales[i].x * c.scales[i].y * c.scales[i].z) ||
            !(c.scales[i].x > 0.0f && c.scales[i].y > 0.0f && c.scales[i].z > 0.0f))
            fail(file, "element vertex " + std::to_string(i) + ": zero rotation or scale out of range");
        c.rotations[i] = q / len;
        glm::vec3* sh = &c.sh[i * std::size_t(k)];
        sh[0] = {v(3), v(4), v(5)};
        // f_rest is channel-major: all of red's coefficients 1..k−1, then green's, then blue's.
        for (int ch = 0; ch < 3; ++ch)
            for (int j = 1; j < k; ++j)
                sh[j][ch] = v(14 + std::size_t(ch * (k - 1) + j - 1));
    }
    return c;
}

void savePly(const SplatCloud& c, const std::filesystem::path& file) {
    c.validate();
    std::ofstream out(file, std::ios::binary);
    if (!out) throw std::runtime_error("sgfx: splat::savePly: cannot write '" + file.string() + "'");
    const int k = c.coefficients();
    out << "ply\nformat binary_little_endian 1.0\nelement vertex " << c.size() << "\n";
    for (const char* n : {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"})
        out << "property float " << n << "\n";
    for (int i = 0; i < 3 * (k - 1); ++i)
        out << "property float f_rest_" << i << "\n";
    for (const char* n : {"opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"})
        out << "property float " << n << "\n";
    out << "end_header\n";
    std::vector<float> row;
    for (std::size_t i = 0; i < c.size(); ++i) {
        const glm::vec3* sh = &c.sh[i * std::size_t(k)];
        const float o = std::clamp(c.opacities[i], 1e-6f, 1.0f - 1e-6f);
        row = {c.positions[i].x, c.positions[i].y, c.positions[i].z, 0, 0, 0, sh[0].r, sh[0].g, sh[0].b};
        for (int ch = 0; ch < 3; ++ch)
            for (int j = 1; j < k; ++j)
                row.push_back(sh[j][ch]);
        row.insert(row.end(), {std::log(o / (1.0f - o)), std::log(c.scales[i].x), std::log(c.scales[i].y),
                               std::log(c.scales[i].z), c.rotations[i].x, c.rotations[i].y, c.rotations[i].z,
                               c.rotations[i].w});
        out.write(reinterpret_cast<const char*>(row.data()), std::streamsize(row.size() * sizeof(float)));
    }
}

} // namespace splat

namespace {
template <int N> bool finite(const glm::vec<N, float>& v) {
    for (int i = 0; i < N; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}
} // namespace

void SplatCloud::validate() const {
    auto refuse = [](const std::string& what) { throw std::invalid_argument("sgfx: SplatCloud: " + what); };
    if (shDegree < 0 || shDegree > 3) refuse("shDegree = " + std::to_string(shDegree) + " is outside [0, 3]");
    const std::size_t n = positions.size();
    if (scales.size() != n || rotations.size() != n || opacities.size() != n ||
        sh.size() != n * std::size_t(coefficients()))
        refuse("array sizes disagree: " + std::to_string(n) + " positions, " + std::to_string(scales.size()) +
               " scales, " + std::to_string(rotations.size()) + " rotations, " +
               std::to_string(opacities.size()) + " opacities, " + std::to_string(sh.size()) +
               " SH triples (" + std::to_string(coefficients()) + " per splat)");
    for (std::size_t i = 0; i < n; ++i) {
        const auto bad = [&](const char* what) { refuse("splat " + std::to_string(i) + ": " + what); };
        if (!finite(positions[i])) bad("position is not finite");
        if (!(finite(scales[i]) && glm::all(glm::greaterThan(scales[i], glm::vec3(0.0f)))))
            bad("scale is not finite and > 0");
        if (!(glm::length(rotations[i]) > 1e-6f) || !finite(rotations[i]))
            bad("rotation is not a finite non-zero quaternion");
        if (!(opacities[i] >= 0.0f && opacities[i] <= 1.0f)) bad("opacity is outside [0, 1]");
        for (int j = 0; j < coefficients(); ++j)
            if (!finite(sh[i * std::size_t(coefficients()) + std::size_t(j)])) bad("SH is not finite");
    }
}

SplatCloud SplatCloud::random(std::size_t count, std::uint32_t seed, float radius, float size, int degree) {
    SplatCloud c;
    c.shDegree = std::clamp(degree, 0, 3);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
    std::normal_distribution<float> gauss(0.0f, 1.0f);
    const int k = c.coefficients();
    for (std::size_t i = 0; i < count; ++i) {
        glm::vec3 p;
        do
            p = {u(rng), u(rng), u(rng)};
        while (glm::dot(p, p) > 1.0f);
        c.positions.push_back(p * radius);
        c.scales.push_back(size * glm::exp(glm::vec3(0.5f * u(rng), 0.5f * u(rng), 0.5f * u(rng))));
        glm::vec4 q(gauss(rng), gauss(rng), gauss(rng), gauss(rng));
        c.rotations.push_back(q / std::max(glm::length(q), 1e-6f));
        c.opacities.push_back(0.2f + 0.8f * u01(rng));
        c.sh.push_back(glm::vec3(u01(rng), u01(rng), u01(rng)) * 1.6f - 0.8f);
        for (int j = 1; j < k; ++j)
            c.sh.push_back(glm::vec3(u(rng), u(rng), u(rng)) * 0.3f);
    }
    return c;
}

} // namespace sgfx

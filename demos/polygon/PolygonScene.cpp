#include "PolygonScene.h"

#include <sgfx/nodes/particles/ParticleSystemNode.h>

#include "CameraPath.h"

#include <sgfx/Billboard.h>
#include <sgfx/Camera.h>
#include <sgfx/DOFTransform.h>
#include <sgfx/Geometry.h>
#include <sgfx/Image.h>
#include <sgfx/LOD.h>
#include <sgfx/Material.h>
#include <sgfx/Shapes.h>
#include <sgfx/StateSet.h>
#include <sgfx/Texture.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

namespace polygon {

float SplitMix64::normal() {
    // Box-Muller; u1 in (0, 1] so the log is finite.
    const float u1 = 1.0f - uniform();
    const float u2 = uniform();
    return std::sqrt(-2.0f * std::log(u1)) * std::cos(glm::two_pi<float>() * u2);
}

// ------------------------------------------------------------------------------------------ terrain
Terrain::Terrain(std::uint64_t seed) {
    SplitMix64 rng(seed ^ 0x7465727261696E00ull); // "terrain"
    // Long, low waves: the amplitudes sum to 7.8 m (< kMaxAmplitude) so |height| stays below 8 m.
    const float wavelengths[] = {420.0f, 260.0f, 150.0f, 90.0f, 55.0f};
    const float amplitudes[] = {3.0f, 2.2f, 1.4f, 0.8f, 0.4f};
    for (int i = 0; i < 5; ++i) {
        const float a = rng.uniform(0.0f, glm::two_pi<float>());
        waves_.push_back({glm::vec2(std::cos(a), std::sin(a)), glm::two_pi<float>() / wavelengths[i],
                          amplitudes[i], rng.uniform(0.0f, glm::two_pi<float>())});
    }
}

float Terrain::height(float x, float y) const {
    const float r = std::sqrt(x * x + y * y);
    const float f = glm::smoothstep(kFlatRadius, kBlendRadius, r);
    if (f <= 0.0f) return 0.0f;
    float h = 0.0f;
    for (const Wave& w : waves_)
        h += w.amplitude * std::sin(w.k * glm::dot(w.dir, glm::vec2(x, y)) + w.phase);
    return f * h;
}

glm::vec3 Terrain::normal(float x, float y) const {
    const float e = 0.25f;
    const float hx = height(x + e, y) - height(x - e, y);
    const float hy = height(x, y + e) - height(x, y - e);
    return glm::normalize(glm::vec3(-hx / (2 * e), -hy / (2 * e), 1.0f));
}

namespace {

using sgfx::Geometry;
using sgfx::Group;
using sgfx::StateSet;
using sgfx::Transform;

constexpr float kRoadWidth = 9.0f;
constexpr float kRoadOffset = 0.05f; // metres above the terrain
constexpr float kPlazaRadius = 60.0f;
constexpr int kTerrainTilesPerSide = 16;
constexpr int kAreaCellsPerSide = 8; // buildings and trees are grouped by area for culling

// Defaults at scale 1, chosen for about 600k triangles in total.
constexpr float kCellsPerTileAtScale1 = 22.0f;
constexpr float kBuildingsAtScale1 = 330.0f;
constexpr float kTreesAtScale1 = 1500.0f;
// Levels of detail: a coarser terrain level serves while its height error, seen from the
// nearest point of the tile's sphere, stays under kTerrainErrorPixels on screen (the screen-space
// error bound of chunked terrain LOD) for a view kTerrainViewPixels tall with the camera path's
// field of view; buildings show window boxes above kBuildingDetailPixels and flat panes below.
constexpr float kTerrainErrorPixels = 1.0f;
constexpr float kTerrainViewPixels = 720.0f;
constexpr float kBuildingDetailPixels = 160.0f;
// Trees smaller than this on screen (their sphere's diameter) are one leaf card turned to the
// eye (a Billboard) instead of four crossed cards: a quarter of the alpha-masked area to shade.
constexpr float kTreeBillboardPixels = 120.0f;

glm::mat4 translate(const glm::vec3& t) {
    return glm::translate(glm::mat4(1.0f), t);
}
glm::mat4 rotateZ(float radians) {
    return glm::rotate(glm::mat4(1.0f), radians, glm::vec3(0, 0, 1));
}
glm::mat4 rotateX(float radians) {
    return glm::rotate(glm::mat4(1.0f), radians, glm::vec3(1, 0, 0));
}
glm::mat4 rotateY(float radians) {
    return glm::rotate(glm::mat4(1.0f), radians, glm::vec3(0, 1, 0));
}
glm::mat4 scale(float s) {
    return glm::scale(glm::mat4(1.0f), glm::vec3(s));
}

// Blinn-Phong material whose ambient reflectance equals its diffuse colour (linear RGB).
std::shared_ptr<sgfx::Material> makeMaterial(const glm::vec3& rgb, float alpha = 1.0f,
                                             const glm::vec3& specular = {}, float shininess = 32.0f) {
    auto m = sgfx::Material::create();
    m->ambient = rgb;
    m->diffuse = glm::vec4(rgb, alpha);
    m->specular = specular;
    m->shininess = shininess;
    return m;
}

std::shared_ptr<StateSet> materialState(std::shared_ptr<sgfx::Material> m) {
    auto s = StateSet::create();
    s->material.set(std::move(m));
    return s;
}

std::shared_ptr<Transform> place(const glm::mat4& m, sgfx::NodePtr child, const std::string& name = {}) {
    auto t = Transform::create(m);
    t->name = name;
    t->addChild(std::move(child));
    return t;
}

// Flat-shaded polygon pieces with the same attribute layout as sgfx::shapes (normals, tangents,
// texcoords), so they can be mixed with shapes::append.
void addFlatTriangle(Geometry& g, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    const glm::vec4 t(glm::normalize(b - a), 1.0f);
    const auto base = std::uint32_t(g.positions.size());
    for (const glm::vec3& p : {a, b, c}) {
        g.positions.push_back(p);
        g.normals.push_back(n);
        g.tangents.push_back(t);
        g.texcoords.push_back(glm::vec2(p.x + p.y, p.z) * 0.25f);
    }
    g.indices.insert(g.indices.end(), {base, base + 1, base + 2});
}

void addFlatQuad(Geometry& g, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                 const glm::vec3& d) {
    addFlatTriangle(g, a, b, c);
    addFlatTriangle(g, a, c, d);
}

// Circles on the ground (buildings, trees, plaza) in a uniform grid for overlap tests.
class CircleGrid {
public:
    CircleGrid(float extent, float cell)
        : half_(extent * 0.5f)
        , cell_(cell)
        , n_(int(std::ceil(extent / cell))) {
        cells_.resize(std::size_t(n_) * n_);
    }
    bool overlaps(glm::vec2 p, float r) const {
        const int reach = int(std::ceil((r + maxRadius_) / cell_));
        const int cx = cellOf(p.x), cy = cellOf(p.y);
        for (int j = std::max(0, cy - reach); j <= std::min(n_ - 1, cy + reach); ++j)
            for (int i = std::max(0, cx - reach); i <= std::min(n_ - 1, cx + reach); ++i)
                for (const glm::vec3& c : cells_[std::size_t(j) * n_ + i])
                    if (glm::length(glm::vec2(c) - p) < c.z + r) return true;
        return false;
    }
    void add(glm::vec2 p, float r) {
        cells_[std::size_t(cellOf(p.y)) * n_ + cellOf(p.x)].push_back(glm::vec3(p, r));
        maxRadius_ = std::max(maxRadius_, r);
    }

private:
    int cellOf(float v) const { return std::clamp(int((v + half_) / cell_), 0, n_ - 1); }
    float half_, cell_;
    int n_;
    float maxRadius_ = 0.0f;
    std::vector<std::vector<glm::vec3>> cells_;
};

// Groups children by a square grid of areas so a whole area is culled with one test.
class AreaGroups {
public:
    AreaGroups(std::string prefix, float extent, std::shared_ptr<Group> parent)
        : prefix_(std::move(prefix))
        , half_(extent * 0.5f)
        , cell_(extent / kAreaCellsPerSide)
        , parent_(std::move(parent)) {}
    void add(glm::vec2 p, sgfx::NodePtr child) {
        const int i = std::clamp(int((p.x + half_) / cell_), 0, kAreaCellsPerSide - 1);
        const int j = std::clamp(int((p.y + half_) / cell_), 0, kAreaCellsPerSide - 1);
        auto& g = groups_[{j, i}];
        if (!g) {
            g = Group::create();
            g->name = prefix_ + "_" + std::to_string(i) + "_" + std::to_string(j);
        }
        g->addChild(std::move(child));
    }
    // Adds the non-empty areas to the parent, in a deterministic order.
    void finish() {
        for (auto& [key, g] : groups_)
            parent_->addChild(g);
    }

private:
    std::string prefix_;
    float half_, cell_;
    std::shared_ptr<Group> parent_;
    std::map<std::pair<int, int>, std::shared_ptr<Group>> groups_;
};

// Distance from p to the nearest road centreline (ring road of radius ringRadius, cross roads on the axes).
float roadDistance(glm::vec2 p, float ringRadius) {
    return std::min({std::abs(p.x), std::abs(p.y), std::abs(glm::length(p) - ringRadius)});
}

// ------------------------------------------------------------------------------------------ terrain
// Upper bound of the gap between the smooth terrain and its linear interpolation over `cell` metres
// (sum over the waves of A k^2 d^2 / 8, with d the cell diagonal); used to lift roads on coarse
// terrain and to lower coarse terrain levels under them.
float interpolationError(float cell) {
    const float wavelengths[] = {420.0f, 260.0f, 150.0f, 90.0f, 55.0f};
    const float amplitudes[] = {3.0f, 2.2f, 1.4f, 0.8f, 0.4f};
    const float d2 = 2.0f * cell * cell;
    float e = 0.0f;
    for (int i = 0; i < 5; ++i) {
        const float k = glm::two_pi<float>() / wavelengths[i];
        e += amplitudes[i] * k * k * d2 / 8.0f;
    }
    return e;
}

// How far a tile drawn with n x n cells strays from the terrain, measured on a grid finer than
// the finest level: `drop` lowers it so it never rises over the terrain (and the roads on it),
// `error` is then its largest distance from the terrain. Smooth and flat tiles measure far
// below interpolationError's worst case, so they coarsen sooner.
struct LevelError {
    float drop = 0.0f;
    float error = 0.0f;
};
LevelError measureLevel(const Terrain& terrain, float x0, float y0, float tile, int n, int samples) {
    auto h = [&](int i, int j) {
        return terrain.height(x0 + tile * float(i) / float(n), y0 + tile * float(j) / float(n));
    };
    float above = 0.0f, below = 0.0f;
    for (int sj = 0; sj <= samples; ++sj)
        for (int si = 0; si <= samples; ++si) {
            // The point in cell (i, j) at (u, v), split along its (0,0)-(1,1) diagonal as
            // shapes::heightfield triangulates it.
            const float fx = float(n) * float(si) / float(samples),
                        fy = float(n) * float(sj) / float(samples);
            const int i = std::min(int(fx), n - 1), j = std::min(int(fy), n - 1);
            const float u = fx - float(i), v = fy - float(j);
            const float ha = h(i, j), hb = h(i + 1, j), hc = h(i, j + 1), hd = h(i + 1, j + 1);
            const float drawn =
                u >= v ? ha + u * (hb - ha) + v * (hd - hb) : ha + v * (hc - ha) + u * (hd - hc);
            const float diff = drawn - terrain.height(x0 + tile * fx / float(n), y0 + tile * fy / float(n));
            above = std::max(above, diff);
            below = std::max(below, -diff);
        }
    // A margin for what falls between the samples.
    const float drop = above * 1.1f + 0.01f;
    return {drop, drop + below};
}

// One terrain tile of cells x cells, lowered by `drop` metres, with `skirt` metre skirts: strips
// hanging from the four edges, facing out, that hide the cracks where tiles of different levels
// meet.
std::shared_ptr<Geometry> terrainTile(const Terrain& terrain, float x0, float y0, float tile, int cells,
                                      float drop, float skirt) {
    const auto height = [&terrain, drop](float x, float y) { return terrain.height(x, y) - drop; };
    auto g = sgfx::shapes::heightfield(x0, y0, tile, tile, cells, cells, height);
    if (skirt <= 0.0f) return g;
    const glm::vec2 corners[] = {{x0, y0}, {x0 + tile, y0}, {x0 + tile, y0 + tile}, {x0, y0 + tile}};
    for (int e = 0; e < 4; ++e) {
        // Corners run counter-clockwise seen from above, so (b - a) x down faces out of the tile.
        const glm::vec2 a = corners[e], b = corners[(e + 1) % 4];
        const auto base = std::uint32_t(g->positions.size());
        for (int k = 0; k <= cells; ++k) {
            const glm::vec2 p = glm::mix(a, b, float(k) / float(cells));
            const float z = height(p.x, p.y);
            for (float dz : {0.0f, -skirt}) {
                g->positions.push_back(glm::vec3(p, z + dz));
                g->normals.push_back(terrain.normal(p.x, p.y)); // shaded like the ground it hangs from
                if (!g->tangents.empty()) g->tangents.push_back(glm::vec4(glm::normalize(b - a), 0.0f, 1.0f));
                if (!g->texcoords.empty()) g->texcoords.push_back((p - glm::vec2(x0, y0)) / tile);
            }
        }
        for (std::uint32_t k = 0; k < std::uint32_t(cells); ++k) {
            const std::uint32_t top0 = base + 2 * k, bottom0 = top0 + 1, top1 = top0 + 2, bottom1 = top0 + 3;
            g->indices.insert(g->indices.end(), {top0, bottom0, bottom1, top0, bottom1, top1});
        }
    }
    g->dirty();
    return g;
}

std::shared_ptr<Group> buildTerrain(const Terrain& terrain, float extent, int cells, bool lod,
                                    SceneInfo& info) {
    auto group = Group::create();
    group->name = "terrain";
    // One grass material for all tiles. (No vertex colours: the OBJ export, which the
    // OpenSceneGraph peer benchmark renders, keeps only material colours.)
    group->setStateSet(materialState(makeMaterial(glm::vec3(0.14f, 0.26f, 0.055f))));
    const float tile = extent / kTerrainTilesPerSide;
    for (int j = 0; j < kTerrainTilesPerSide; ++j)
        for (int i = 0; i < kTerrainTilesPerSide; ++i) {
            const float x0 = -extent * 0.5f + tile * float(i), y0 = -extent * 0.5f + tile * float(j);
            const std::string name = "terrain_" + std::to_string(i) + "_" + std::to_string(j);
            ++info.terrainTiles;
            if (!lod || cells < 8) {
                auto full = terrainTile(terrain, x0, y0, tile, cells, 0.0f, 0.0f);
                full->name = name;
                group->addChild(full);
                continue;
            }
            // Distant tiles at half and quarter resolution. Each coarser level is lowered by its
            // own interpolation error so it never rises over the roads, which follow the fine one.
            auto levels = sgfx::LOD::create();
            levels->name = name + "_lod";
            const float radius = 0.7072f * tile;
            levels->setUserSphere(glm::vec3(x0 + 0.5f * tile, y0 + 0.5f * tile, 0.0f), radius);
            // The sphere is p = 2rK/d pixels across at centre distance d (K: focal length in
            // pixels). A height error e seen from the sphere's nearest point, d - r away, spans
            // eK/(d - r) pixels, at most kTerrainErrorPixels (tau) while p <= 2K / (1 + eK/(r tau)).
            const float focal = 0.5f * kTerrainViewPixels / std::tan(glm::radians(0.5f * kPathFovyDegrees));
            auto maxPixels = [&](float error) {
                return 2.0f * focal / (1.0f + error * focal / (radius * kTerrainErrorPixels));
            };
            const int n[3] = {cells, std::max(2, cells / 2), std::max(2, cells / 4)};
            LevelError measured[3];
            for (int level = 1; level < 3; ++level)
                measured[level] = measureLevel(terrain, x0, y0, tile, n[level], 2 * cells);
            measured[2].error = std::max(measured[2].error, measured[1].error); // ranges stay ordered
            // Every level hangs skirts deep enough for the largest step between two levels
            // (the coarsest level's drop plus its own interpolation error, at worst), so
            // whichever side of a boundary the eye is on, the nearer tile's skirt fills the gap.
            const float skirt = 2.0f * interpolationError(tile / float(n[2])) + 0.25f;
            for (int level = 0; level < 3; ++level) {
                // Level k serves from where level k + 1's error would show up to where its own does.
                const float lower = level == 2 ? 0.0f : maxPixels(measured[level + 1].error);
                const float upper =
                    level == 0 ? std::numeric_limits<float>::infinity() : maxPixels(measured[level].error);
                auto g = terrainTile(terrain, x0, y0, tile, n[level], measured[level].drop, skirt);
                g->name = level == 0 ? name : name + "_level" + std::to_string(level);
                levels->addChild(g, lower, upper);
            }
            group->addChild(levels);
            ++info.terrainLods;
        }
    info.terrainCellsPerTile = cells;
    return group;
}

// ------------------------------------------------------------------------------------------ roads
// A strip of `width` along centre(s) for s in [s0, s1], following the terrain at `lift` above it.
std::shared_ptr<Geometry> roadStrip(const Terrain& terrain, const std::function<glm::vec2(float)>& centre,
                                    float s0, float s1, float width, float lift, float step) {
    auto g = Geometry::create();
    const int along = std::max(1, int(std::ceil((s1 - s0) / step)));
    const int across = std::max(1, int(std::ceil(width / step)));
    for (int a = 0; a <= along; ++a) {
        const float s = s0 + (s1 - s0) * float(a) / float(along);
        const glm::vec2 c = centre(s);
        const float ds = 0.01f;
        const glm::vec2 dir = glm::normalize(centre(s + ds) - centre(s - ds));
        const glm::vec2 side(-dir.y, dir.x);
        for (int k = 0; k <= across; ++k) {
            const float u = float(k) / float(across);
            const glm::vec2 p = c + side * (width * (u - 0.5f));
            g->positions.push_back(glm::vec3(p, terrain.height(p.x, p.y) + lift));
            g->normals.push_back(terrain.normal(p.x, p.y));
            g->tangents.push_back(glm::vec4(dir, 0.0f, 1.0f));
            g->texcoords.push_back(glm::vec2(u, s / width));
        }
    }
    const auto row = std::uint32_t(across + 1);
    for (int a = 0; a < along; ++a)
        for (int k = 0; k < across; ++k) {
            const auto i0 = std::uint32_t(a) * row + std::uint32_t(k), i1 = i0 + 1, i2 = i0 + row,
                       i3 = i2 + 1;
            // side points to the left of the direction of travel, so (i0, i1, i3) is counter-clockwise from
            // above
            g->indices.insert(g->indices.end(), {i0, i3, i1, i0, i2, i3});
        }
    // Make the winding face up whatever the direction of travel.
    if (g->indices.size() >= 3) {
        const glm::vec3 n = glm::cross(g->positions[g->indices[1]] - g->positions[g->indices[0]],
                                       g->positions[g->indices[2]] - g->positions[g->indices[0]]);
        if (n.z < 0.0f)
            for (std::size_t t = 0; t + 2 < g->indices.size(); t += 3)
                std::swap(g->indices[t + 1], g->indices[t + 2]);
    }
    g->dirty();
    return g;
}

std::shared_ptr<Group> buildRoads(const Terrain& terrain, float extent, float ringRadius, float terrainCell,
                                  SceneInfo& info) {
    auto group = Group::create();
    group->name = "roads";
    group->setStateSet(
        materialState(makeMaterial(glm::vec3(0.045f, 0.045f, 0.05f), 1.0f, glm::vec3(0.05f), 16.0f)));
    const float step = std::min(2.0f, terrainCell);
    const float lift = kRoadOffset + interpolationError(terrainCell) + interpolationError(step);
    const float half = extent * 0.5f - 4.0f;
    const float piece = 50.0f;
    // Cross roads along the X and Y axes, in pieces so each can be culled.
    const int pieces = std::max(1, int(std::round(2.0f * half / piece)));
    for (int axis = 0; axis < 2; ++axis)
        for (int p = 0; p < pieces; ++p) {
            const float s0 = -half + 2.0f * half * float(p) / float(pieces);
            const float s1 = -half + 2.0f * half * float(p + 1) / float(pieces);
            auto centre = [axis](float s) { return axis == 0 ? glm::vec2(s, 0.0f) : glm::vec2(0.0f, s); };
            auto g = roadStrip(terrain, centre, s0, s1, kRoadWidth, lift, step);
            g->name = std::string(axis == 0 ? "road_x_" : "road_y_") + std::to_string(p);
            group->addChild(g);
            ++info.roadPieces;
        }
    // Ring road, slightly higher than the cross roads so the crossings do not fight in depth.
    const int ringPieces = std::max(8, int(std::round(glm::two_pi<float>() * ringRadius / piece)));
    for (int p = 0; p < ringPieces; ++p) {
        const float s0 = glm::two_pi<float>() * ringRadius * float(p) / float(ringPieces);
        const float s1 = glm::two_pi<float>() * ringRadius * float(p + 1) / float(ringPieces);
        auto centre = [ringRadius](float s) {
            const float a = s / ringRadius;
            return glm::vec2(std::cos(a), std::sin(a)) * ringRadius;
        };
        auto g = roadStrip(terrain, centre, s0, s1, kRoadWidth, lift + 0.02f, step);
        g->name = "road_ring_" + std::to_string(p);
        group->addChild(g);
        ++info.roadPieces;
    }
    return group;
}

// ------------------------------------------------------------------------------------------ buildings
struct BuildingPrototype {
    std::shared_ptr<Group> node;
    float halfDiagonal = 0.0f;
    std::size_t triangles = 0; // at full detail
    std::size_t windows = 0;
};

struct BuildingMaterials {
    std::vector<std::shared_ptr<StateSet>> walls;
    std::shared_ptr<StateSet> windows, flatRoof, tileRoof, slateRoof;
};

BuildingMaterials makeBuildingMaterials() {
    BuildingMaterials m;
    const glm::vec3 walls[] = {{0.62f, 0.60f, 0.55f}, {0.55f, 0.45f, 0.32f}, {0.40f, 0.40f, 0.40f},
                               {0.45f, 0.20f, 0.12f}, {0.65f, 0.55f, 0.30f}, {0.32f, 0.13f, 0.09f},
                               {0.38f, 0.45f, 0.50f}, {0.50f, 0.50f, 0.46f}};
    for (const glm::vec3& c : walls)
        m.walls.push_back(materialState(makeMaterial(c)));
    m.windows = materialState(makeMaterial(glm::vec3(0.04f, 0.06f, 0.09f), 1.0f, glm::vec3(0.6f), 64.0f));
    m.flatRoof = materialState(makeMaterial(glm::vec3(0.12f, 0.12f, 0.12f)));
    m.tileRoof = materialState(makeMaterial(glm::vec3(0.35f, 0.08f, 0.04f)));
    m.slateRoof = materialState(makeMaterial(glm::vec3(0.09f, 0.10f, 0.12f)));
    return m;
}

// The outward face of a window box (1.4 x 1.6 m, centred on `centre`, facing `out`): what is
// left of a window when its 8 cm depth is below a pixel.
void addWindowPane(Geometry& g, const glm::vec3& centre, const glm::vec3& out) {
    const glm::vec3 up(0, 0, 1), t = glm::cross(out, up) * 0.7f, u = up * 0.8f;
    addFlatQuad(g, centre + t - u, centre - t - u, centre - t + u, centre + t + u);
}

// A building of footprint w x d and `floors` storeys, base at z = 0 (the walls reach 4 m below
// so instances on slopes never float). Walls inherit the instance's colour.
//   lod:           window boxes above kBuildingDetailPixels, flat panes below (12 -> 2 triangles)
//   manyDrawables: every window its own drawable (a shared box, or pane, under its own
//                  Transform): the many-drawables benchmark scene
BuildingPrototype makeBuildingPrototype(float w, float d, int floors, bool gable, bool slate,
                                        const BuildingMaterials& mats, int index, bool lod,
                                        bool manyDrawables) {
    constexpr float kFloorHeight = 3.2f, kFoundation = 4.0f;
    const float h = kFloorHeight * float(floors);
    auto node = Group::create();
    node->name = "building_prototype_" + std::to_string(index);

    auto walls = Geometry::create();
    walls->name = "walls";
    sgfx::shapes::append(*walls, *sgfx::shapes::box({w, d, h + kFoundation}),
                         translate({0, 0, 0.5f * (h - kFoundation)}));

    // Windows: protruding dark boxes, one row per floor on every facade.
    auto windows = Geometry::create();
    windows->name = "windows";
    auto panes = Geometry::create();
    panes->name = "window_panes";
    auto windowGroup = Group::create(), paneGroup = Group::create();
    windowGroup->name = "windows";
    windowGroup->setStateSet(mats.windows);
    paneGroup->name = "window_panes";
    paneGroup->setStateSet(mats.windows);
    // One pane per facing (+X, -X, +Y, -Y) for the many-drawables scene's distant level.
    std::map<std::pair<int, int>, std::shared_ptr<Geometry>> paneMeshes;
    auto windowX = sgfx::shapes::box({1.4f, 0.16f, 1.6f}); // on the facades facing +-Y
    auto windowY = sgfx::shapes::box({0.16f, 1.4f, 1.6f}); // on the facades facing +-X
    std::size_t windowCount = 0;
    auto addWindow = [&](const std::shared_ptr<Geometry>& box, const glm::vec3& at, const glm::vec3& out) {
        if (manyDrawables) {
            windowGroup->addChild(place(translate(at), box));
            auto& pane = paneMeshes[{int(out.x), int(out.y)}];
            if (!pane) {
                pane = Geometry::create();
                pane->name = "window_pane";
                addWindowPane(*pane, glm::vec3(0.0f), out);
            }
            paneGroup->addChild(place(translate(at + 0.08f * out), pane));
        } else
            sgfx::shapes::append(*windows, *box, translate(at));
        addWindowPane(*panes, at + 0.08f * out, out);
        ++windowCount;
    };
    for (int f = 0; f < floors; ++f) {
        const float z = kFloorHeight * float(f) + 1.7f;
        const int nx = std::max(1, int((w - 2.0f) / 3.0f)), ny = std::max(1, int((d - 2.0f) / 3.0f));
        for (int i = 0; i < nx; ++i) {
            const float x = -0.5f * w + w * (float(i) + 0.5f) / float(nx);
            for (float sy : {-1.0f, 1.0f})
                addWindow(windowX, {x, sy * 0.5f * d, z}, {0, sy, 0});
        }
        for (int i = 0; i < ny; ++i) {
            const float y = -0.5f * d + d * (float(i) + 0.5f) / float(ny);
            for (float sx : {-1.0f, 1.0f})
                addWindow(windowY, {sx * 0.5f * w, y, z}, {sx, 0, 0});
        }
    }
    windows->setStateSet(mats.windows);
    panes->setStateSet(mats.windows);

    auto roof = Geometry::create();
    roof->name = "roof";
    if (gable) {
        // Ridge along the longer side; the eaves overhang by `ov` all round.
        const bool alongX = w >= d;
        const float L = alongX ? w : d, S = alongX ? d : w; // ridge length, span
        const float ov = 0.5f, rise = 0.35f * S;
        const float HL = 0.5f * L + ov, HS = 0.5f * S + ov;
        const float z0 = h - ov * rise / (0.5f * S); // eave height, so the slope meets the wall top
        const float zr = z0 + rise * HS / (0.5f * S);
        // Roof-local (ridge along x), rotated into place below.
        auto r = Geometry::create();
        addFlatQuad(*r, {-HL, -HS, z0}, {HL, -HS, z0}, {HL, 0, zr}, {-HL, 0, zr});
        addFlatQuad(*r, {HL, HS, z0}, {-HL, HS, z0}, {-HL, 0, zr}, {HL, 0, zr});
        const glm::mat4 m = alongX ? glm::mat4(1.0f) : rotateZ(glm::half_pi<float>());
        sgfx::shapes::append(*roof, *r, m);
        // Gable ends belong to the walls (same colour).
        auto gables = Geometry::create();
        const float hl = 0.5f * L, hs = 0.5f * S;
        addFlatTriangle(*gables, {hl, -hs, h}, {hl, hs, h}, {hl, 0, zr});
        addFlatTriangle(*gables, {-hl, -hs, h}, {-hl, 0, zr}, {-hl, hs, h});
        sgfx::shapes::append(*walls, *gables, m);
        roof->setStateSet(slate ? mats.slateRoof : mats.tileRoof);
    } else {
        // Flat roof: parapet and a roof-top plant room.
        const float t = 0.3f, ph = 0.9f;
        sgfx::shapes::append(*roof, *sgfx::shapes::box({w, t, ph}),
                             translate({0, 0.5f * (d - t), h + 0.5f * ph}));
        sgfx::shapes::append(*roof, *sgfx::shapes::box({w, t, ph}),
                             translate({0, -0.5f * (d - t), h + 0.5f * ph}));
        sgfx::shapes::append(*roof, *sgfx::shapes::box({t, d - 2 * t, ph}),
                             translate({0.5f * (w - t), 0, h + 0.5f * ph}));
        sgfx::shapes::append(*roof, *sgfx::shapes::box({t, d - 2 * t, ph}),
                             translate({-0.5f * (w - t), 0, h + 0.5f * ph}));
        sgfx::shapes::append(*roof, *sgfx::shapes::box({0.3f * w, 0.3f * d, 2.2f}),
                             translate({0.15f * w, -0.1f * d, h + 1.1f}));
        roof->setStateSet(mats.flatRoof);
    }
    node->addChild(walls);
    node->addChild(roof);
    const float halfDiagonal = 0.5f * std::sqrt(w * w + d * d) + 0.5f;
    const std::size_t boxTriangles = windowCount * windowX->triangleCount();
    if (lod) {
        auto levels = sgfx::LOD::create();
        levels->name = "windows_lod";
        // Switch on the building's size, not the windows' bound.
        levels->setUserSphere({0, 0, 0.5f * h}, std::sqrt(halfDiagonal * halfDiagonal + 0.25f * h * h));
        levels->addChild(manyDrawables ? windowGroup : sgfx::NodePtr(windows), kBuildingDetailPixels,
                         std::numeric_limits<float>::infinity());
        levels->addChild(manyDrawables ? paneGroup : sgfx::NodePtr(panes), 0.0f, kBuildingDetailPixels);
        node->addChild(levels);
    } else {
        node->addChild(manyDrawables ? windowGroup : sgfx::NodePtr(windows));
    }
    return {node, halfDiagonal, walls->triangleCount() + boxTriangles + roof->triangleCount(), windowCount};
}

// ------------------------------------------------------------------------------------------ trees
// Leaf-cluster silhouette for the tree cards: 1 channel, 255 = leaf. Image rows run top to
// bottom like the cards' texture coordinates (glTF convention), so the crown is drawn upright.
std::shared_ptr<sgfx::Image> makeLeafMask(std::uint64_t seed, int size) {
    SplitMix64 rng(seed ^ 0x6C656166ull); // "leaf"
    struct Disc {
        glm::vec2 c;
        float r;
    };
    std::vector<Disc> discs;
    while (discs.size() < 140) {
        const glm::vec2 c(rng.uniform(0.08f, 0.92f), rng.uniform(0.12f, 0.95f));
        // Crown: an ellipse a little above the middle of the card, narrowing at the top.
        const glm::vec2 q = (c - glm::vec2(0.5f, 0.56f)) / glm::vec2(0.40f - 0.08f * (c.y - 0.5f), 0.40f);
        if (glm::dot(q, q) > 1.0f) continue;
        discs.push_back({c, rng.uniform(0.045f, 0.095f)});
    }
    auto img = sgfx::Image::create(size, size, 1);
    const float px = 1.0f / float(size);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const glm::vec2 p((float(x) + 0.5f) * px, 1.0f - (float(y) + 0.5f) * px); // y up
            float coverage = 0.0f;
            for (const Disc& d : discs)
                coverage = std::max(
                    coverage, std::clamp((d.r - glm::length(p - d.c)) / (1.5f * px) + 0.5f, 0.0f, 1.0f));
            *img->pixel(x, y) = std::uint8_t(std::lround(255.0f * coverage));
        }
    return img;
}

// One tree: trunk cylinder plus three crossed vertical leaf cards and one horizontal card
// (seen from the air), alpha-masked with the leaf silhouette; with levels of detail, distant
// trees are the trunk and one card facing the eye.
std::shared_ptr<Group> makeTree(std::uint64_t seed, bool lod) {
    auto tree = Group::create();
    tree->name = "tree";
    auto trunk = sgfx::shapes::cylinder(0.24f, 3.8f, 8, false);
    trunk->name = "trunk";
    trunk->setStateSet(materialState(makeMaterial(glm::vec3(0.12f, 0.07f, 0.035f))));

    auto leaves = Geometry::create();
    leaves->name = "leaves";
    const float cardW = 6.0f, cardH = 6.4f, bottom = 1.9f;
    auto card = sgfx::shapes::quad(cardW, cardH); // XY plane; rotate upright (local y -> z)
    for (int i = 0; i < 3; ++i)
        sgfx::shapes::append(*leaves, *card,
                             translate({0, 0, bottom + 0.5f * cardH}) *
                                 rotateZ(glm::pi<float>() * float(i) / 3.0f) *
                                 rotateX(glm::half_pi<float>()));
    sgfx::shapes::append(*leaves, *sgfx::shapes::quad(cardW * 0.9f, cardW * 0.9f),
                         translate({0, 0, bottom + 0.6f * cardH}));
    auto mat = makeMaterial(glm::vec3(0.08f, 0.22f, 0.04f));
    auto maskTexture = sgfx::Texture::create(makeLeafMask(seed, 128), false);
    maskTexture->wrapS = maskTexture->wrapT = sgfx::Wrap::ClampToEdge;
    mat->alphaTexture = std::move(maskTexture);
    mat->alphaCutoff = 0.5f;
    auto leafState = materialState(mat);
    leafState->cullFace.set(sgfx::CullFace::None);
    leaves->setStateSet(leafState);

    tree->addChild(trunk);
    tree->addChild(leaves);
    if (!lod) return tree;
    auto facing = Geometry::create();
    facing->name = "leaves_billboard";
    sgfx::shapes::append(*facing, *card,
                         translate({0, 0, bottom + 0.5f * cardH}) * rotateX(glm::half_pi<float>()));
    // Seen from its lit side, a card facing the eye is brighter than three crossed cards, whose
    // visible faces turn from the light by a uniformly spread angle: their mean diffuse
    // factor, weighted by projected area, is E[cos^2]/E[|cos|] = pi/4 of the facing card's.
    auto facingMat = std::make_shared<sgfx::Material>(*mat);
    facingMat->diffuse = glm::vec4(glm::vec3(mat->diffuse) * glm::quarter_pi<float>(), mat->diffuse.a);
    auto facingState = std::make_shared<StateSet>(*leafState);
    facingState->material.set(facingMat);
    facing->setStateSet(facingState);
    auto billboard = sgfx::Billboard::create(); // turns about z; the card's -Y side to the eye
    billboard->addChild(facing);
    auto distant = Group::create();
    distant->name = "tree_distant";
    distant->addChild(trunk);
    distant->addChild(billboard);
    auto levels = sgfx::LOD::create();
    levels->name = "tree_lod";
    levels->setUserSphere({0, 0, 0.5f * (bottom + cardH)}, 0.5f * (bottom + cardH));
    levels->addChild(tree, kTreeBillboardPixels, std::numeric_limits<float>::infinity());
    levels->addChild(distant, 0.0f, kTreeBillboardPixels);
    auto root = Group::create();
    root->name = "tree";
    root->addChild(levels);
    return root;
}

// ------------------------------------------------------------------------------------------ vehicle
// A wheel that turns about its axle (the vehicle's y through its centre); `shape` has its axis
// along +Z from z = 0, and is turned onto y and centred across the wheel's width.
std::shared_ptr<sgfx::DOFTransform> spinningWheel(const VehicleWheel& w, sgfx::NodePtr shape) {
    auto dof = sgfx::DOFTransform::create();
    dof->name = w.name;
    dof->setFrame(translate(w.centre));
    dof->setBase(translate(w.centre) * rotateX(-glm::half_pi<float>()) * translate({0, 0, -0.125f}));
    dof->addAxis("spin", sgfx::DOFTransform::Kind::RotateY, 0.0, glm::two_pi<double>(),
                 sgfx::DOFTransform::Limit::Wrap);
    dof->addChild(std::move(shape));
    return dof;
}

// A tracked robot vehicle, x forward, ground at z = 0, about 6.6 m long.
std::shared_ptr<Group> makeVehicle() {
    auto v = Group::create();
    v->name = "vehicle";
    auto olive = materialState(makeMaterial(glm::vec3(0.16f, 0.19f, 0.08f), 1.0f, glm::vec3(0.15f), 24.0f));
    auto dark = materialState(makeMaterial(glm::vec3(0.05f, 0.05f, 0.05f)));
    auto rubber = materialState(makeMaterial(glm::vec3(0.02f, 0.02f, 0.02f)));
    auto steel = materialState(makeMaterial(glm::vec3(0.30f, 0.30f, 0.32f), 1.0f, glm::vec3(0.5f), 48.0f));
    auto lens = materialState(makeMaterial(glm::vec3(0.05f, 0.15f, 0.35f), 1.0f, glm::vec3(0.9f), 96.0f));

    auto body = Group::create();
    body->name = "hull";
    body->setStateSet(olive);
    auto hull = sgfx::shapes::box({5.6f, 2.3f, 1.1f});
    hull->name = "hull";
    body->addChild(place(translate({0, 0, 1.05f}), hull));
    auto deck = sgfx::shapes::box({4.6f, 3.9f, 0.25f});
    deck->name = "deck";
    body->addChild(place(translate({-0.3f, 0, 1.72f}), deck));
    auto glacis = sgfx::shapes::box({1.2f, 2.3f, 0.7f});
    glacis->name = "glacis";
    body->addChild(place(translate({2.8f, 0, 1.1f}) * rotateY(0.5f), glacis));

    auto tracks = Group::create();
    tracks->name = "tracks";
    tracks->setStateSet(dark);
    auto track = sgfx::shapes::box({6.2f, 0.8f, 1.1f});
    track->name = "track";
    for (float s : {-1.0f, 1.0f})
        tracks->addChild(place(translate({0, s * 1.55f, 0.55f}), track));

    auto wheels = Group::create();
    wheels->name = "road_wheels";
    wheels->setStateSet(rubber);
    auto wheel = sgfx::shapes::cylinder(0.38f, 0.25f, 20); // axis +Z, rotated onto Y below
    wheel->name = "wheel";
    auto sprocket = sgfx::shapes::cylinder(0.46f, 0.25f, 20);
    sprocket->name = "sprocket";
    for (const VehicleWheel& w : vehicleWheels())
        wheels->addChild(spinningWheel(w, w.name.find("sprocket") != std::string::npos ? sprocket : wheel));

    // Turret with gun barrel and a sensor mast: the turret turns about its ring's axis, the gun
    // about its trunnion at the barrel's breech.
    const glm::vec3 ring0(-0.4f, 0, 1.84f);
    auto turret = sgfx::DOFTransform::create();
    turret->name = kTurretNode;
    turret->setFrame(translate(ring0));
    turret->setBase(translate(ring0)); // the children in the ring's frame
    turret->addAxis("yaw", sgfx::DOFTransform::Kind::RotateZ, -glm::pi<double>(), glm::pi<double>(),
                    sgfx::DOFTransform::Limit::Wrap, kTurretRestYaw);
    turret->setStateSet(olive);
    auto ring = sgfx::shapes::cylinder(1.15f, 0.75f, 28);
    ring->name = "turret_ring";
    turret->addChild(ring);
    auto mantlet = sgfx::shapes::box({0.5f, 0.8f, 0.5f});
    mantlet->name = "mantlet";
    turret->addChild(place(translate({1.2f, 0, 0.4f}), mantlet));
    auto barrel = sgfx::shapes::cylinder(0.09f, 3.4f, 12);
    barrel->name = "gun_barrel";
    barrel->setStateSet(steel);
    const glm::vec3 trunnion(1.35f, 0, 0.42f);
    auto gun = sgfx::DOFTransform::create();
    gun->name = kGunNode;
    // Frame axes: x along the trunnion (the turret's -y), y forward, z up (OpenFlight's pitch).
    gun->setFrame(trunnion, glm::mat3(glm::vec3(0, -1, 0), glm::vec3(1, 0, 0), glm::vec3(0, 0, 1)));
    gun->setBase(translate(trunnion) * rotateY(glm::half_pi<float>())); // level, along +x
    gun->addAxis("elevation", sgfx::DOFTransform::Kind::RotateX, kGunMinElevation, kGunMaxElevation,
                 sgfx::DOFTransform::Limit::Clamp, kGunRestElevation);
    gun->addChild(barrel);
    turret->addChild(gun);
    auto mast = sgfx::shapes::cylinder(0.05f, 1.3f, 8);
    mast->name = "mast";
    mast->setStateSet(steel);
    turret->addChild(place(translate({-0.6f, 0.5f, 0.75f}), mast));
    auto head = sgfx::shapes::sphere(0.2f, 16, 8);
    head->name = "sensor_head";
    head->setStateSet(lens);
    turret->addChild(place(translate({-0.6f, 0.5f, 2.1f}), head));

    v->addChild(body);
    v->addChild(tracks);
    v->addChild(wheels);
    v->addChild(turret);
    return v;
}

// ------------------------------------------------------------------------------------------ glass
// Two panes on stands and a closed glass cabin (double-sided: drawn back faces first), in a
// TransparencyBin whose mode the demo chooses.
std::shared_ptr<sgfx::TransparencyBin> makeGlass(const Terrain& terrain) {
    auto group = sgfx::TransparencyBin::create();
    group->name = "glass";
    auto glass = StateSet::create();
    glass->material.set(makeMaterial(glm::vec3(0.55f, 0.75f, 0.85f), 0.3f, glm::vec3(0.8f), 80.0f));
    glass->blend.set(sgfx::BlendMode::Alpha);
    glass->cullFace.set(sgfx::CullFace::None);
    glass->renderBin.set(sgfx::RenderBin::Transparent);
    auto frameState =
        materialState(makeMaterial(glm::vec3(0.25f, 0.25f, 0.27f), 1.0f, glm::vec3(0.4f), 32.0f));
    // The metal frames stay opaque inside the bin.
    frameState->renderBin.set(sgfx::RenderBin::Opaque);
    frameState->blend.set(sgfx::BlendMode::Off);

    const float w = 9.0f, h = 4.5f;
    auto pane = sgfx::shapes::quad(w, h); // upright below: local y -> z, facing -Y
    pane->name = "glass_pane";
    pane->setStateSet(glass);
    auto post = sgfx::shapes::box({0.15f, 0.15f, h + 0.2f});
    post->name = "glass_post";
    post->setStateSet(frameState);
    struct Spot {
        glm::vec2 p;
        float yaw;
    };
    for (const Spot& s : {Spot{{34.0f, 15.0f}, 1.35f}, Spot{{25.0f, 31.0f}, 0.45f}}) {
        const float z = terrain.height(s.p.x, s.p.y);
        auto t = Transform::create(translate(glm::vec3(s.p, z)) * rotateZ(s.yaw));
        t->name = "glass_stand";
        t->addChild(place(translate({0, 0, 0.5f * h + 0.1f}) * rotateX(glm::half_pi<float>()), pane));
        for (float sx : {-1.0f, 1.0f})
            t->addChild(place(translate({sx * (0.5f * w + 0.075f), 0, 0.5f * (h + 0.2f)}), post));
        group->addChild(t);
    }
    // Two tinted panes crossing each other: no order of the two is right everywhere, so sorting
    // gets one side wrong and order-independent transparency does not.
    auto amber = StateSet::create();
    *amber = *glass;
    amber->material.set(makeMaterial(glm::vec3(0.95f, 0.55f, 0.1f), 0.5f, glm::vec3(0.6f), 60.0f));
    const glm::vec2 cross(24.0f, 12.0f);
    const float crossZ = terrain.height(cross.x, cross.y) + 1.5f;
    for (int i = 0; i < 2; ++i) {
        auto q = sgfx::shapes::quad(4.0f, 3.0f);
        q->name = i == 0 ? "glass_cross_blue" : "glass_cross_amber";
        q->setStateSet(i == 0 ? glass : amber);
        group->addChild(
            place(translate(glm::vec3(cross, crossZ)) * rotateZ(0.6f + float(i) * glm::half_pi<float>()) *
                      rotateX(glm::half_pi<float>()),
                  q, "glass_cross"));
    }
    const glm::vec2 cabin(29.0f, 22.0f);
    auto box = sgfx::shapes::box({3.0f, 3.0f, 2.5f});
    box->name = "glass_cabin";
    box->setStateSet(glass);
    group->addChild(
        place(translate(glm::vec3(cabin, terrain.height(cabin.x, cabin.y) + 1.25f)) * rotateZ(0.3f), box,
              "glass_cabin_pose"));
    return group;
}

} // namespace

std::vector<VehicleWheel> vehicleWheels() {
    std::vector<VehicleWheel> out;
    for (float s : {-1.0f, 1.0f}) {
        const std::string side = s > 0.0f ? "l" : "r";
        const float y = s * 1.9f;   // just proud of the track's outer face
        for (int i = 0; i < 6; ++i) // six road wheels, rear first, numbered from the front
            out.push_back({"vehicle.wheel." + side + std::to_string(6 - i),
                           {-2.2f + 4.4f * float(i) / 5.0f, y, 0.40f},
                           0.38f});
        out.push_back({"vehicle.sprocket." + side + "r", {-2.85f, y, 0.62f}, 0.46f});
        out.push_back({"vehicle.sprocket." + side + "f", {2.85f, y, 0.62f}, 0.46f});
    }
    return out;
}

std::shared_ptr<sgfx::Group> buildVehicle() {
    return makeVehicle();
}

// ------------------------------------------------------------------------------------------ scene
PolygonScene buildPolygonScene(const SceneOptions& options) {
    if (!(options.scale > 0.0f && options.scale <= 16.0f))
        throw std::invalid_argument("polygon: scale must be in (0, 16]");
    if (!(options.extent > 0.0f) || !std::isfinite(options.extent))
        throw std::invalid_argument("polygon: extent must be finite and > 0");
    const float extent = options.extent, half = 0.5f * extent;
    const Terrain terrain(options.seed);
    SplitMix64 rng(options.seed);
    PolygonScene scene;
    scene.extent = extent;
    scene.root = Group::create();
    scene.root->name = "polygon";

    // Lights first: they are positional state for the whole scene.
    auto sun = sgfx::Light::create(sgfx::LightType::Directional);
    sun->name = "sun";
    const float az = glm::radians(-35.0f), el = glm::radians(50.0f);
    sun->direction = -glm::vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    sun->color = glm::vec3(1.0f, 0.95f, 0.86f);
    sun->intensity = 1.1f;
    auto ambient = sgfx::Light::create(sgfx::LightType::Ambient);
    ambient->name = "sky_ambient";
    ambient->color = glm::vec3(0.30f, 0.34f, 0.42f);
    scene.root->addChild(sun);
    scene.root->addChild(ambient);

    // Triangle count ~ scale: terrain cells grow with sqrt(scale) per side, the others linearly.
    const float s = options.scale;
    const int buildingCount = int(std::lround(kBuildingsAtScale1 * s));
    const int treeCount = int(std::lround(kTreesAtScale1 * s));
    // Above scale 1 villages and forests spread wider so their density, not their size, stays put.
    const float spread = std::sqrt(std::max(1.0f, s));
    const float ringRadius = 0.45f * half;
    scene.ringRadius = ringRadius;
    // The benchmark camera circles at this radius, 12 to 42 m up: keep buildings out of its way.
    const float cameraRadius = glm::length(glm::vec2(cameraPose(0.0f, extent).eye));

    // Obstacles: roads are tested analytically; the plaza, buildings and trees as circles.
    CircleGrid occupied(extent, 25.0f);
    occupied.add({0, 0}, kPlazaRadius);
    auto isFree = [&](glm::vec2 p, float r, float roadMargin) {
        if (std::abs(p.x) > half - r - 6.0f || std::abs(p.y) > half - r - 6.0f) return false;
        if (roadDistance(p, ringRadius) < 0.5f * kRoadWidth + r + roadMargin) return false;
        return !occupied.overlaps(p, r);
    };

    // Buildings: a dozen shared prototypes, instanced in villages and scattered farms.
    const BuildingMaterials mats = makeBuildingMaterials();
    std::vector<BuildingPrototype> prototypes;
    {
        const int floorsChoice[] = {1, 2, 2, 3, 3, 4, 5, 6, 8, 10};
        for (int i = 0; i < 12; ++i) {
            const float w = std::round(rng.uniform(8.0f, 22.0f)), d = std::round(rng.uniform(7.0f, 15.0f));
            const int floors = floorsChoice[rng.index(10)];
            const bool gable = floors <= 3;
            prototypes.push_back(makeBuildingPrototype(w, d, floors, gable, rng.uniform() < 0.4f, mats, i,
                                                       options.lod, options.manyDrawables));
        }
    }
    scene.info.buildingPrototypes = int(prototypes.size());
    scene.buildings = Group::create();
    scene.buildings->name = "buildings";
    AreaGroups buildingAreas("buildings", extent, scene.buildings);
    // Centres of building villages and forests: inside the ground's margin, away from the middle.
    auto clusterCentres = [&](std::size_t count, float margin, float minRadius) {
        std::vector<glm::vec2> centres;
        while (centres.size() < count) {
            const glm::vec2 c(rng.uniform(-half + margin, half - margin),
                              rng.uniform(-half + margin, half - margin));
            if (glm::length(c) > minRadius) centres.push_back(c);
        }
        return centres;
    };
    const std::vector<glm::vec2> villages = clusterCentres(7, 60.0f, 110.0f);
    std::size_t buildingTriangles = 0, prototypeTriangles = 0;
    for (const BuildingPrototype& p : prototypes)
        prototypeTriangles += p.triangles;
    for (int placed = 0, attempts = 0; placed < buildingCount && attempts < 60 * buildingCount + 100;
         ++attempts) {
        const BuildingPrototype& proto = prototypes[rng.index(prototypes.size())];
        const float sc = rng.uniform(0.9f, 1.1f);
        const float yaw = glm::half_pi<float>() * float(rng.index(4)) + rng.uniform(-0.12f, 0.12f);
        glm::vec2 p;
        if (rng.uniform() < 0.75f)
            p = villages[rng.index(villages.size())] +
                glm::vec2(rng.normal(), rng.normal()) * (55.0f * spread);
        else
            p = glm::vec2(rng.uniform(-half, half), rng.uniform(-half, half));
        const float r = proto.halfDiagonal * sc;
        const std::size_t colour = rng.index(mats.walls.size());
        if (std::abs(glm::length(p) - cameraRadius) < r + 8.0f || !isFree(p, r + 1.5f, 2.0f)) continue;
        occupied.add(p, r + 1.5f);
        // Sit on the lowest point of the footprint; the foundation hides the rest.
        float z = terrain.height(p.x, p.y);
        for (float dx : {-r, r})
            for (float dy : {-r, r})
                z = std::min(z, terrain.height(p.x + dx, p.y + dy));
        auto t = Transform::create(translate(glm::vec3(p, z - 0.1f)) * rotateZ(yaw) * scale(sc));
        t->name = "building_" + std::to_string(placed);
        t->setStateSet(mats.walls[colour]);
        t->addChild(proto.node);
        buildingAreas.add(p, t);
        ++placed;
        buildingTriangles += proto.triangles;
        scene.info.buildings = placed;
        scene.info.windows += int(proto.windows);
    }
    buildingAreas.finish();
    scene.info.buildingsRequested = buildingCount;

    // Trees: one shared tree under many Transforms, mostly in small forests.
    auto tree = makeTree(options.seed, options.lod);
    scene.trees = Group::create();
    scene.trees->name = "trees";
    AreaGroups treeAreas("trees", extent, scene.trees);
    const std::vector<glm::vec2> forests = clusterCentres(12, 30.0f, 90.0f);
    for (int placed = 0, attempts = 0; placed < treeCount && attempts < 60 * treeCount + 100; ++attempts) {
        glm::vec2 p;
        if (rng.uniform() < 0.75f)
            p = forests[rng.index(forests.size())] + glm::vec2(rng.normal(), rng.normal()) * (38.0f * spread);
        else
            p = glm::vec2(rng.uniform(-half, half), rng.uniform(-half, half));
        const float sc = rng.uniform(0.75f, 1.35f);
        const float yaw = rng.uniform(0.0f, glm::two_pi<float>());
        if (!isFree(p, 1.2f * sc, 1.0f)) continue;
        occupied.add(p, 1.2f * sc);
        auto t = Transform::create(translate(glm::vec3(p, terrain.height(p.x, p.y) - 0.15f)) * rotateZ(yaw) *
                                   scale(sc));
        t->addChild(tree);
        treeAreas.add(p, t);
        ++placed;
        scene.info.trees = placed;
    }
    treeAreas.finish();
    scene.info.treesRequested = treeCount;

    // Terrain and roads. At large scales the ground runs out of room for buildings and trees;
    // the terrain then gets finer so the total triangle count stays roughly linear in the scale.
    std::size_t treeTriangles = 0;
    for (const auto& c : tree->children())
        if (auto g = std::dynamic_pointer_cast<Geometry>(c)) treeTriangles += g->triangleCount();
    const double expected = double(buildingCount) * double(prototypeTriangles) /
                                double(std::max<std::size_t>(1, prototypes.size())) +
                            double(treeCount) * double(treeTriangles);
    const double placedTriangles =
        double(buildingTriangles) + double(scene.info.trees) * double(treeTriangles);
    const double nominalCells = double(kCellsPerTileAtScale1) * std::sqrt(double(s));
    double terrainTriangles = 2.0 * kTerrainTilesPerSide * kTerrainTilesPerSide * nominalCells * nominalCells;
    if (placedTriangles < 0.9 * expected) terrainTriangles += expected - placedTriangles;
    const int cells = std::max(
        2,
        int(std::lround(std::sqrt(terrainTriangles / (2.0 * kTerrainTilesPerSide * kTerrainTilesPerSide)))));
    scene.terrain = buildTerrain(terrain, extent, cells, options.lod, scene.info);
    scene.roads =
        buildRoads(terrain, extent, ringRadius, extent / float(kTerrainTilesPerSide * cells), scene.info);

    // The robot vehicle and the glass panes on the flat test area at the centre.
    scene.vehicle = Group::create();
    scene.vehicle->name = "vehicle_site";
    scene.vehiclePose =
        place(translate({18.0f, 17.0f, terrain.height(18.0f, 17.0f)}) * rotateZ(glm::radians(215.0f)),
              makeVehicle(), "vehicle_pose");
    scene.vehicle->addChild(scene.vehiclePose);
    scene.glassBin = makeGlass(terrain);
    scene.glass = scene.glassBin;

    scene.root->addChild(scene.terrain);
    scene.root->addChild(scene.roads);
    scene.root->addChild(scene.buildings);
    scene.root->addChild(scene.trees);
    scene.root->addChild(scene.vehicle);
    scene.root->addChild(scene.glass);
    scene.ground = Group::create();
    scene.ground->name = "ground";
    scene.ground->addChild(scene.terrain);
    scene.ground->addChild(scene.roads);
    return scene;
}

sgfx::NodePtr withRainFollowing(sgfx::NodePtr world, std::shared_ptr<const sgfx::Camera> camera, float area,
                                std::uint32_t count, float above, float lowest) {
    auto rain = sgfx::ParticleSystemNode::rain({area, area}, count);
    auto place = sgfx::Transform::create();
    // Weak: the camera holds the scene, and the scene this callback (no cycle).
    place->updateCallback = [weakCamera = std::weak_ptr<const sgfx::Camera>(camera), rain = rain.get(), above,
                             lowest](sgfx::Node& n, sgfx::UpdateVisitor&) {
        const auto cam = weakCamera.lock();
        if (!cam) return;
        const glm::vec3 eye(glm::inverse(cam->viewMatrix)[3]);
        const float height = eye.z + above;
        static_cast<sgfx::Transform&>(n).setMatrix(glm::translate(glm::mat4(1.0f), {eye.x, eye.y, height}));
        sgfx::particles::Emitter e = rain->settings().emitter;
        const float lifetime = std::max(1.0f, (height - lowest) / -e.velocity.z);
        if (std::abs(lifetime - e.lifetime) > 0.05f * e.lifetime) {
            e.lifetime = lifetime;
            rain->setEmitter(e);
        }
    };
    place->addChild(rain);
    auto group = sgfx::Group::create();
    group->addChild(world);
    group->addChild(place);
    return group;
}

} // namespace polygon

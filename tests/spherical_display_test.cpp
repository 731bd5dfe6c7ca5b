// The spherical-mirror display (OSG's panoramic and 3D spherical displays): the .view reader against
// OSG's sample files and bad input; the distortion mesh against an independent inverse of OSG's
// formulas; and rendered images (64×64 projector image, 32² cube faces) against the colour of the
// world in the direction the formulas give each pixel, and against the intensity map.
#include "TestUtil.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/LoadError.h>
#include <sgfx/OsgViewConfig.h>
#include <sgfx/ShaderComposer.h>
#include <sgfx/Shapes.h>
#include <sgfx/SphericalDisplay.h>
#include <sgfx/nodes/spherical/SphericalDisplayRig.h>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <optional>

using namespace sgfx;
using namespace sgfx::test;
namespace fs = std::filesystem;

namespace {

constexpr int kOut = 64, kFace = 32;
const double kPi = glm::pi<double>();

fs::path configs() {
    return fs::path(SGFX_SOURCE_DIR) / ".." / "shared" / "assets" / "osg" / "Configuration";
}

// The intensity map of OSG's sample files (0 100, 90 100, 135 50, 180 0), evaluated on its own.
double sampleIntensity(double angleDeg) {
    if (angleDeg <= 90.0) return 1.0;
    if (angleDeg >= 180.0) return 0.0;
    if (angleDeg <= 135.0) return 1.0 - 0.5 * (angleDeg - 90.0) / 45.0;
    return 0.5 - 0.5 * (angleDeg - 135.0) / 45.0;
}

SphericalDisplayParams sampleParams(SphericalDisplayKind kind) {
    SphericalDisplayParams p;
    p.kind = kind;
    p.radius = 1.0;
    p.collar = 0.43;
    p.intensityMap = {{0, 100}, {90, 100}, {135, 50}, {180, 0}};
    return p;
}

// What a pixel of the projector image shows: the direction from the eye (display frame: +Y forward,
// +Z up) and the angle its intensity is read at. Inverses and forward maps written from OSG's mesh
// code, not shared with the library. Panoramic: the pixel at radius ρ·R, azimuth α shows the
// direction at azimuth α whose angle seen from the projector is γ = ρπ/2; on the unit sphere
// tan γ = sin β / (cos β + d), so sin(β − γ) = d sin γ.
struct PixelView {
    glm::dvec3 direction;
    double angleDeg;
};

std::optional<PixelView> panoramicPixel(double px, double py, double collar) {
    const double d = std::sqrt(1.0 - collar * collar), r = kOut * 0.5;
    const double sx = (px - r) / r, sy = (py - r) / r, rho = std::hypot(sx, sy);
    if (rho > 0.93) return std::nullopt; // OSG drops the mesh's quads that cross the rim
    const double gamma = rho * kPi / 2, alpha = std::atan2(sx, -sy);
    const double beta = gamma + std::asin(d * std::sin(gamma));
    return PixelView{{std::sin(beta) * std::sin(alpha), std::sin(beta) * std::cos(alpha), std::cos(beta)},
                     glm::degrees(beta)};
}

// 3D: the projector ray at angle φ (radius ρ·R ↦ ρπ/2) from the axis, followed to the mirror.
PixelView threeDPixel(double px, double py, double collar) {
    const double d = std::sqrt(1.0 - collar * collar), r = kOut * 0.5;
    const double dx = px - r, dy = py - r;
    const double theta = std::atan2(-dy, dx), phi = std::min(kPi / 2 * std::hypot(dx, dy) / r, kPi / 2);
    // Ray (sin φ, cos φ) from (0, −d) meets the unit circle at distance e.
    const double e = d * std::cos(phi) + std::sqrt(1.0 - d * d * std::sin(phi) * std::sin(phi));
    const glm::dvec3 hit(e * std::sin(phi) * std::cos(theta), e * std::sin(phi) * std::sin(theta),
                         e * std::cos(phi) - d);
    return {hit, glm::degrees(phi) * 2.0};
}

// A box of six coloured walls 10 m around the eye at the origin, unlit (the application's program).
const std::array<glm::vec3, 6> kWallColour = {
    glm::vec3(1, 0, 0), glm::vec3(0, 1, 1), glm::vec3(0, 1, 0),
    glm::vec3(1, 0, 1), glm::vec3(0, 0, 1), glm::vec3(1, 1, 0)}; // +X, −X, +Y, −Y, +Z, −Z (world)

NodePtr box(bool white) {
    auto root = Group::create();
    const glm::mat4 I(1.0f);
    const std::array<glm::mat4, 6> place = {
        glm::rotate(glm::translate(I, {10, 0, 0}), glm::half_pi<float>(), {0, 1, 0}),
        glm::rotate(glm::translate(I, {-10, 0, 0}), glm::half_pi<float>(), {0, 1, 0}),
        glm::rotate(glm::translate(I, {0, 10, 0}), glm::half_pi<float>(), {1, 0, 0}),
        glm::rotate(glm::translate(I, {0, -10, 0}), glm::half_pi<float>(), {1, 0, 0}),
        glm::translate(I, {0, 0, 10}),
        glm::translate(I, {0, 0, -10})};
    for (int f = 0; f < 6; ++f) {
        auto q = shapes::quad(20.5f, 20.5f);
        auto& ss = q->getOrCreateStateSet();
        ss.program.set(ShaderProgram::create("app", kForeignVert, kForeignFrag));
        ss.setUniform("appColor", white ? glm::vec3(1.0f) : kWallColour[std::size_t(f)]);
        ss.cullFace.set(CullFace::None);
        auto t = Transform::create(place[std::size_t(f)]);
        t->addChild(q);
        root->addChild(t);
    }
    return root;
}

// The wall a world direction meets, or none within `margin` (ratio of the two largest components)
// of an edge of the box, where the face cameras' filtering may blend.
std::optional<int> wallOf(const glm::dvec3& w, double margin = 1.15) {
    const glm::dvec3 a = glm::abs(w);
    int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    double second = 0.0;
    for (int k = 0; k < 3; ++k)
        if (k != axis) second = std::max(second, a[k]);
    if (a[axis] < margin * second) return std::nullopt;
    return axis * 2 + (w[axis] > 0.0 ? 0 : 1);
}

Image render(const SphericalDisplayParams& p, NodePtr scene, const glm::mat4& eyeView) {
    SphericalDisplaySetup s;
    s.width = s.height = kOut;
    s.faceSize = kFace;
    auto rig = SphericalDisplayRig::create(p, s, scene);
    rig->setEyeView(eyeView);
    auto v = Viewer::createHeadless(kOut, kOut);
    rig->configureOutputCamera(*v->camera());
    v->setSceneData(rig->root());
    v->frame();
    expectNoGlErrors(*v);
    return v->capture();
}

// GL pixel centre of image column x, row y (rows top to bottom).
glm::dvec2 centre(int x, int y) {
    return {x + 0.5, kOut - 1 - y + 0.5};
}

} // namespace

// ---- .view files ---------------------------------------------------------------------------------

TEST(OsgViewConfig, OsgSampleFilesGiveTheirParameters) {
    SGFX_REQUIRE(fs::exists(configs() / "PanoramicSphericalDisplay.view"),
                 "../shared/assets/osg/Configuration");
    const std::vector<IntensityPoint> map = {{0, 100}, {90, 100}, {135, 50}, {180, 0}};
    for (const auto& [file, kind] :
         {std::pair{"PanoramicSphericalDisplay.view", SphericalDisplayKind::Panoramic},
          std::pair{"3DSphericalDisplay.view", SphericalDisplayKind::ThreeD}}) {
        SCOPED_TRACE(file);
        const OsgViewConfig c = loadOsgView(configs() / file);
        EXPECT_EQ(c.kind, OsgViewConfig::Kind::Spherical);
        EXPECT_EQ(c.spherical.kind, kind);
        EXPECT_DOUBLE_EQ(c.spherical.radius, 1.0);
        EXPECT_DOUBLE_EQ(c.spherical.collar, 0.43);
        EXPECT_EQ(c.spherical.screenNum, 0u);
        EXPECT_EQ(c.spherical.intensityMap, map);
        EXPECT_EQ(c.spherical.projector, glm::dmat4(1.0));
    }
    const OsgViewConfig single = loadOsgView(configs() / "SingleScreen.view");
    EXPECT_EQ(single.kind, OsgViewConfig::Kind::SingleScreen);
    EXPECT_EQ(single.screenNum, 0u);
}

TEST(OsgViewConfig, DefaultsOptionalFieldsAndOsgOrder) {
    const OsgViewConfig c = parseOsgView(R"(osgViewer::View {
  setUpViewFor3DSphericalDisplay {
    screenNum 2
    intensityFormat 16
    intensityMap { 180 0 0 100 }
    projectorMatrix { 1 0 0 0  0 1 0 0  0 0 1 0  0.5 0 0 1 }
  }
})",
                                         "mem.view");
    EXPECT_DOUBLE_EQ(c.spherical.radius, 1.0);  // OSG's default
    EXPECT_DOUBLE_EQ(c.spherical.collar, 0.45); // OSG's default
    EXPECT_EQ(c.spherical.screenNum, 2u);
    ASSERT_EQ(c.spherical.intensityMap.size(), 2u);
    EXPECT_EQ(c.spherical.intensityMap[0], (IntensityPoint{0, 100})); // sorted, as OSG's std::map
    // The file's 4th row is OSG's translation (row vectors): x' = x + 0.5.
    const glm::dvec4 moved = c.spherical.projector * glm::dvec4(0, 0, 0, 1);
    EXPECT_DOUBLE_EQ(moved.x, 0.5);
}

TEST(OsgViewConfig, ErrorsNameFileLineAndField) {
    const std::string head = "osgViewer::View\n{\n  setUpViewForPanoramicSphericalDisplay\n  {\n";
    struct Case {
        std::string text, where, field;
    };
    const std::vector<Case> cases = {
        {head + "    radiuss 1.0\n  }\n}\n", ":5:", "radiuss"},
        {head + "    radius abc\n  }\n}\n", ":5:", "radius"},
        {head + "    radius -1\n  }\n}\n", ":5:", "radius"},
        {head + "    radius 1\n    collar 1.5\n  }\n}\n", ":6:", "collar"},
        {head + "    intensityFile ramp.png\n  }\n}\n", ":5:", "intensityFile"},
        {head + "    intensityMap {\n 0 100\n 200 50\n }\n  }\n}\n", ":7:", "intensityMap angle"},
        {head + "    intensityMap {\n 0 100\n 0 50\n }\n  }\n}\n", ":7:", "intensityMap angle"},
        {head + "    intensityMap {\n 0 -5\n }\n  }\n}\n", ":6:", "intensityMap percent"},
        {head + "    intensityMap {\n 0\n }\n  }\n}\n", ":7:", "intensityMap percent"},
        {head + "    intensityFormat 12\n  }\n}\n", ":5:", "intensityFormat"},
        {head + "    projectorMatrix { 1 0 0 }\n  }\n}\n", ":5:", "projectorMatrix"},
        {head + "    radius 1.0\n", ":5:", "unexpected end of file"},
        {"osg::Group\n{\n}\n", ":1:", "osgViewer::View"},
        {"osgViewer::View\n{\n  setUpViewAcrossAllScreens\n}\n", ":3:", "setUpViewAcrossAllScreens"},
        {"osgViewer::View\n{\n  setUpViewOnSingleScreen x\n}\n", ":3:", "setUpViewOnSingleScreen"},
        {"osgViewer::View\n{\n  setUpViewOnSingleScreen 0\n}\nmore\n", ":5:", "more"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.text);
        try {
            parseOsgView(c.text, "bad.view");
            ADD_FAILURE() << "no error";
        } catch (const LoadError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("bad.view" + c.where), std::string::npos) << msg;
            EXPECT_NE(msg.find(c.field), std::string::npos) << msg;
        }
    }
    try {
        loadOsgView("/nonexistent/x.view");
        ADD_FAILURE() << "no error";
    } catch (const LoadError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/x.view"), std::string::npos);
    }
}

TEST(SphericalDisplay, BadParametersAndSetupAreRefusedByName) {
    SphericalDisplayParams p = sampleParams(SphericalDisplayKind::Panoramic);
    p.collar = 1.0;
    EXPECT_THROW(p.validate(), std::invalid_argument);
    p = sampleParams(SphericalDisplayKind::Panoramic);
    p.intensityMap = {{90, 100}, {10, 50}};
    EXPECT_THROW(p.validate(), std::invalid_argument);
    p = sampleParams(SphericalDisplayKind::Panoramic);
    p.projector[3][0] = NAN;
    EXPECT_THROW(sphericalWarpMesh(p, 64, 64), std::invalid_argument);
    SphericalDisplaySetup s;
    s.faceSize = 0;
    EXPECT_THROW(SphericalDisplayRig::create(sampleParams(SphericalDisplayKind::ThreeD), s, Group::create()),
                 std::invalid_argument);
    auto rig = SphericalDisplayRig::create(sampleParams(SphericalDisplayKind::ThreeD), {}, Group::create());
    const glm::mat4 before = rig->faces()[0]->viewMatrix;
    EXPECT_THROW(rig->setEyeView(glm::mat4(0.0f)), std::invalid_argument);
    EXPECT_EQ(rig->faces()[0]->viewMatrix, before) << "the old view stays";
}

// ---- mesh maths ------------------------------------------------------------------------------------

// Every vertex OSG's panoramic mesh keeps lands where the independent inverse says its direction is.
TEST(SphericalDisplay, PanoramicMeshMatchesTheInverse) {
    const SphericalDisplayParams p = sampleParams(SphericalDisplayKind::Panoramic);
    const WarpMesh m = sphericalWarpMesh(p, kOut, kOut);
    ASSERT_EQ(m.vertices.size(), 160u * 160u);
    ASSERT_FALSE(m.indices.empty());
    int checked = 0;
    for (const WarpVertex& v : m.vertices) {
        const auto pv = panoramicPixel(v.pixel.x, v.pixel.y, p.collar);
        if (!pv || glm::length(glm::dvec2(v.pixel) - glm::dvec2(32.0)) < 0.5)
            continue; // azimuth undefined at 0
        ++checked;
        EXPECT_LT(glm::length(pv->direction - glm::dvec3(v.direction)), 1e-4)
            << v.pixel.x << "," << v.pixel.y;
        EXPECT_NEAR(pv->angleDeg, v.angleDeg, 1e-3);
    }
    EXPECT_GT(checked, 10000);
}

// The projector matrix turns each direction before it is placed (OSG: pos = dir * projectorMatrix): a
// 90° turn about the vertical moves every vertex to where the forward map puts the turned direction.
TEST(SphericalDisplay, ProjectorMatrixTurnsDirectionsBeforeTheyArePlaced) {
    SphericalDisplayParams p = sampleParams(SphericalDisplayKind::Panoramic);
    p.projector = glm::rotate(glm::dmat4(1.0), kPi / 2, glm::dvec3(0, 0, 1));
    const WarpMesh m = sphericalWarpMesh(p, kOut, kOut, 40);
    const double d = std::sqrt(1.0 - p.collar * p.collar), r = kOut * 0.5;
    int checked = 0;
    for (const WarpVertex& v : m.vertices) {
        const glm::dvec3 q = glm::dmat3(p.projector) * glm::dvec3(v.direction);
        const double rho = std::hypot(q.x, q.y);
        if (rho < 1e-6) continue;
        const double alpha = std::atan2(q.x, q.y), gamma = std::atan2(rho, q.z + d);
        const glm::dvec2 want =
            glm::dvec2(r) + glm::dvec2(std::sin(alpha), -std::cos(alpha)) * gamma * 2.0 / kPi * r;
        EXPECT_LT(glm::length(glm::dvec2(v.pixel) - want), 1e-3);
        EXPECT_NEAR(v.angleDeg, glm::degrees(std::atan2(rho, q.z)), 1e-3);
        ++checked;
    }
    EXPECT_GT(checked, 1000);
    // Forward (+Y), turned to −X, lands where −X did without the turn: the image's left, not its bottom.
    const WarpVertex forward = m.vertices[std::size_t(0 * 40 + 20)]; // theta 0, phi ~ 90°
    EXPECT_NEAR(forward.direction.y, 1.0f, 0.01f);
    EXPECT_LT(forward.pixel.x, 0.5 * r);
}

// Every prefix of a sample file is either read or refused with a LoadError: never a crash or hang.
TEST(OsgViewConfig, TruncatedFilesAreRefusedCleanly) {
    const std::string text = "osgViewer::View\n{\n  setUpViewFor3DSphericalDisplay\n  {\n    radius 1.0\n"
                             "    collar 0.43\n    intensityMap\n    {\n      0 100\n      180 0\n    }\n"
                             "    projectorMatrix { 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 }\n  }\n}\n";
    int refused = 0;
    for (std::size_t n = 0; n < text.size(); ++n) {
        try {
            parseOsgView(text.substr(0, n), "cut.view");
        } catch (const LoadError& e) {
            EXPECT_NE(std::string(e.what()).find("cut.view:"), std::string::npos);
            ++refused;
        }
    }
    EXPECT_EQ(refused, int(text.size()) - 1) << "only the whole text (its last newline aside) is complete";
    EXPECT_NO_THROW(parseOsgView(text, "whole.view"));
}

TEST(SphericalDisplay, IntensityAtIsOsgsPiecewiseLinearMap) {
    const auto& map = sampleParams(SphericalDisplayKind::Panoramic).intensityMap;
    for (double a = -10.0; a <= 190.0; a += 0.5)
        EXPECT_NEAR(intensityAt(map, a), sampleIntensity(a), 1e-6) << a;
    EXPECT_EQ(intensityAt({}, 120.0), 1.0);
}

// ---- rendered --------------------------------------------------------------------------------------

// Six coloured walls: each sampled pixel shows the colour of the wall in the direction the formulas
// give it (pixels within ~4° of a wall's edge left out). Panoramic looking along +Y; 3D with the eye
// turned 90° to the left, so the display's forward is world −X.
TEST(SphericalDisplayRender, EachPixelShowsTheWorldInItsDirection) {
    const glm::mat4 forwardY = glm::lookAt(glm::vec3(0.0f), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1));
    const glm::mat4 forwardMinusX = glm::lookAt(glm::vec3(0.0f), glm::vec3(-1, 0, 0), glm::vec3(0, 0, 1));
    for (const auto kind : {SphericalDisplayKind::Panoramic, SphericalDisplayKind::ThreeD}) {
        SCOPED_TRACE(kind == SphericalDisplayKind::Panoramic ? "panoramic" : "3D");
        SphericalDisplayParams p = sampleParams(kind);
        p.intensityMap.clear(); // colours exact: 0 or 255
        const glm::mat4 view = kind == SphericalDisplayKind::Panoramic ? forwardY : forwardMinusX;
        const Image img = render(p, box(false), view);
        // Display frame → eye view space → world.
        const glm::dmat3 worldFromEye = glm::transpose(glm::dmat3(glm::mat3(view)));
        std::array<int, 6> seen{};
        int wrong = 0;
        for (int y = 0; y < kOut; ++y) {
            for (int x = 0; x < kOut; ++x) {
                const glm::dvec2 c = centre(x, y);
                std::optional<PixelView> pv;
                if (kind == SphericalDisplayKind::Panoramic)
                    pv = panoramicPixel(c.x, c.y, p.collar);
                else
                    pv = threeDPixel(c.x, c.y, p.collar);
                if (!pv) continue;
                const glm::dvec3 d = pv->direction;
                const auto wall = wallOf(worldFromEye * glm::dvec3(d.x, d.z, -d.y));
                if (!wall) continue;
                ++seen[std::size_t(*wall)];
                const glm::ivec4 got = pixelAt(img, x, y);
                const glm::ivec3 want = glm::ivec3(kWallColour[std::size_t(*wall)] * 255.0f);
                if (glm::any(glm::greaterThan(glm::abs(glm::ivec3(got) - want), glm::ivec3(1)))) {
                    if (++wrong <= 5)
                        ADD_FAILURE() << "pixel " << x << "," << y << " wall " << *wall << " got " << got.r
                                      << " " << got.g << " " << got.b;
                }
            }
        }
        EXPECT_EQ(wrong, 0);
        for (int f = 0; f < 6; ++f)
            EXPECT_GT(seen[std::size_t(f)], 8) << "wall " << f << " sampled";
    }
}

// A white world: the image is the intensity map alone, read at each pixel's angle: no line at the
// faces' borders (those pixels are not left out here), tolerance 2 of 255.
TEST(SphericalDisplayRender, WhiteWorldGivesTheIntensityMapWithoutSeams) {
    for (const auto kind : {SphericalDisplayKind::Panoramic, SphericalDisplayKind::ThreeD}) {
        SCOPED_TRACE(kind == SphericalDisplayKind::Panoramic ? "panoramic" : "3D");
        const SphericalDisplayParams p = sampleParams(kind);
        const Image img = render(p, box(true), glm::lookAt(glm::vec3(0.0f), {0, 1, 0}, {0, 0, 1}));
        int checked = 0, worst = 0;
        double minAngle = 180.0, maxAngle = 0.0;
        for (int y = 0; y < kOut; ++y) {
            for (int x = 0; x < kOut; ++x) {
                const glm::dvec2 c = centre(x, y);
                const std::optional<PixelView> pv =
                    kind == SphericalDisplayKind::Panoramic
                        ? panoramicPixel(c.x, c.y, p.collar)
                        : std::optional<PixelView>(threeDPixel(c.x, c.y, p.collar));
                if (!pv) continue;
                const int want = srgbByte(sampleIntensity(pv->angleDeg));
                const glm::ivec4 got = pixelAt(img, x, y);
                for (int k = 0; k < 3; ++k)
                    worst = std::max(worst, std::abs(got[k] - want));
                EXPECT_LE(std::abs(got.g - want), 2) << x << "," << y << " angle " << pv->angleDeg;
                minAngle = std::min(minAngle, pv->angleDeg);
                maxAngle = std::max(maxAngle, pv->angleDeg);
                ++checked;
            }
        }
        EXPECT_GT(checked, 2000);
        EXPECT_LT(minAngle, 10.0);
        EXPECT_GT(maxAngle, 140.0) << "every segment of the map is read";
        EXPECT_LE(worst, 2);
    }
}

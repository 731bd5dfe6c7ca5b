// GlslCompat: OSG compatibility-profile GLSL translated into foreign programs. Text-level checks
// (identifier boundaries, comments, versions, errors), then OSMesa renders whose pixels are
// compared with values computed here on the CPU, under fog and ambient occlusion too.
#include "TestUtil.h"

#include <sgfx/GlslCompat.h>
#include <sgfx/Group.h>
#include <sgfx/ShaderComposer.h>
#include <sgfx/Shapes.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/fog/FogMath.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/shadow/ShadowNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <optional>

using namespace sgfx;
using namespace sgfx::test;

namespace {

bool contains(const std::string& s, const std::string& what) {
    return s.find(what) != std::string::npos;
}

// glsl_simple.osgt (OSG's example data): the first program, colour from the object position.
const char* const kSimpleVert = "varying vec4 color;\nvoid main(void)\n{\n    color = gl_Vertex;\n"
                                "    gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex;\n}\n";
const char* const kSimpleFrag =
    "varying vec4 color;void main(void){gl_FragColor = clamp( color, 0.0, 1.0 );}";

// glsl_simple.osgt's second program: blocky.vert and blocky.frag (Mike Weiblen, 3Dlabs), verbatim.
const char* const kBlockyVert = R"(// blocky.vert - an OGLSL vertex shader with animation
// Mike Weiblen 2003-09-16 : derived from brick.vert
// Copyright 2003 3Dlabs Inc.
// see http://www.3dlabs.com/opengl2/ for more OpenGL Shading Language info.
// the App updates uniforms "slowly" (eg once per frame) for animation.
uniform float Sine;
const vec3 LightPosition = vec3(0.0, 0.0, 4.0);
const float BlockScale = 0.30;
// varyings are written by vert shader, interpolated, and read by frag shader.
varying float LightIntensity;
varying vec2  BlockPosition;
void main(void)
{
    // per-vertex diffuse lighting
    vec4 ecPosition	= gl_ModelViewMatrix * gl_Vertex;
    vec3 tnorm		= normalize(gl_NormalMatrix * gl_Normal);
    vec3 lightVec	= normalize(LightPosition - vec3 (ecPosition));
    LightIntensity	= max(dot(lightVec, tnorm), 0.0);
    // blocks will be determined by fragment's position on the XZ plane.
    BlockPosition = gl_Vertex.xz / BlockScale;
    // scale the geometry based on an animation variable.
    vec4 vertex	= gl_Vertex;
    vertex.w	= 1.0 + 0.4 * (Sine + 1.0);
    gl_Position	= gl_ModelViewProjectionMatrix * vertex;
}
)";
const char* const kBlockyFrag = R"(// blocky.frag - an OGLSL fragment shader with animation
// Mike Weiblen 2003-09-16 : derived from brick.frag
// Copyright 2003 3Dlabs Inc.
// see http://www.3dlabs.com/opengl2/ for more OpenGL Shading Language info.
// the App updates uniforms "slowly" (eg once per frame) for animation.
uniform float Sine;
uniform vec3 Color1;
uniform vec3 Color2;
// varyings are written by vert shader, interpolated, and read by frag shader.
varying vec2  BlockPosition;
varying float LightIntensity;
void main(void)
{
    vec3 color;
    float ss, tt, w, h;
    
    ss = BlockPosition.x;
    tt = BlockPosition.y;
    if (fract(tt * 0.5) > 0.5)
        ss += 0.5;
    ss = fract(ss);
    tt = fract(tt);
    // animate the proportion of block to mortar
    float blockFract = (Sine + 1.1) * 0.4;
    w = step(ss, blockFract);
    h = step(tt, blockFract);
    color = mix(Color2, Color1, w * h) * LightIntensity;
    gl_FragColor = vec4 (color, 1.0);
}
)";

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const CompatError& e) {
        return e.what();
    }
    return "(no error)";
}

} // namespace

// ---- text ----

TEST(GlslCompatText, ReplacesAtIdentifierBoundariesOnly) {
    const char* vert = "#version 120\n"
                       "// gl_Vertex in a comment stays as written\n"
                       "uniform vec4 my_gl_Vertex;\n"
                       "/* texture2D( and gl_Normal */ varying vec4 c;\n"
                       "void main() { c = my_gl_Vertex + gl_Vertex; gl_Position = ftransform(); }\n";
    const CompatProgram p = translateCompatibilityProgram("boundaries", vert,
                                                          "varying vec4 c;\n"
                                                          "void main() { gl_FragColor = c; }\n");
    const std::string& v = p.program->vertexSource;
    EXPECT_TRUE(v.starts_with("#version 450 core\n")) << v;
    EXPECT_FALSE(contains(v, "#version 120")) << v;
    EXPECT_TRUE(contains(v, "// gl_Vertex in a comment stays as written")) << v;
    EXPECT_TRUE(contains(v, "/* texture2D( and gl_Normal */ out vec4 c;")) << v;
    EXPECT_TRUE(contains(v, "uniform vec4 my_gl_Vertex;")) << v;
    EXPECT_TRUE(contains(v, "c = my_gl_Vertex + osg_Vertex; gl_Position = osg_ftransform();")) << v;
    EXPECT_TRUE(contains(v, "layout(location = 0) in vec4 osg_Vertex;")) << v;
    EXPECT_FALSE(contains(v, "osg_Normal")) << "declared only what is used:\n" << v;
    EXPECT_TRUE(contains(v, "void osg_main()")) << v;
    const std::string& f = p.program->fragmentSource;
    EXPECT_TRUE(contains(f, "in vec4 c;")) << f;
    EXPECT_TRUE(contains(f, "osg_FragColor = c;")) << f;
    EXPECT_TRUE(contains(f, "layout(location = 0) out vec4 osg_FragColor;")) << f;
    // The original lines keep their numbers: line 5 of the source follows `#line 1`.
    const std::size_t at = v.find("#line 1 0\n");
    ASSERT_NE(at, std::string::npos);
    const std::string body = v.substr(at + 10);
    EXPECT_EQ(std::count(body.begin(), body.begin() + long(body.find("c = my_gl_Vertex")), '\n'), 4) << body;
}

TEST(GlslCompatText, OsgAliasedDeclarationsAreDroppedAndNamesMapped) {
    const char* vert =
        "#version 130\nin vec4 osg_Vertex;\nattribute vec3 osg_Normal;\n"
        "uniform mat4 osg_ModelViewProjectionMatrix;\nuniform float osg_FrameTime;\nout float t;\n"
        "void main() { t = osg_FrameTime + osg_Normal.x; gl_Position = osg_ModelViewProjectionMatrix "
        "* osg_Vertex; }\n";
    const CompatProgram p = translateCompatibilityProgram("aliased", vert,
                                                          "in float t;\nout vec4 result;\n"
                                                          "void main() { result = vec4(t); }\n");
    const std::string& v = p.program->vertexSource;
    EXPECT_FALSE(contains(v, "\nin vec4 osg_Vertex;")) << v;
    EXPECT_FALSE(contains(v, "uniform mat4 osg_ModelViewProjectionMatrix;")) << v;
    EXPECT_FALSE(contains(v, "uniform float osg_FrameTime;")) << v;
    EXPECT_TRUE(contains(v, "#define osg_ModelViewProjectionMatrix (sgfx_viewProjection * sgfx_model)")) << v;
    EXPECT_TRUE(contains(v, "#define osg_FrameTime (sgfx_time.x)")) << v;
    EXPECT_TRUE(contains(v, "layout(location = 1) in vec3 osg_Normal;")) << v;
    // A 1.30 fragment stage with its own output: the AO wrap darkens that output.
    EXPECT_TRUE(contains(p.program->fragmentSource, "result.rgb *= 1.0 - sgfx_ambientOcclusion();"))
        << p.program->fragmentSource;
}

TEST(GlslCompatText, OldSourcesMayUseLaterKeywordsAsNames) {
    const char* frag =
        "uniform sampler2D tex;\nvoid main() {\n    vec4 texture = texture2D(tex, vec2(0.5));\n"
        "    float sample = 1.0;\n    gl_FragColor = texture * sample;\n}\n";
    const CompatProgram p = translateCompatibilityProgram("keywords", "", frag);
    const std::string& f = p.program->fragmentSource;
    EXPECT_TRUE(contains(f, "vec4 texture_osg = texture(tex, vec2(0.5));")) << f;
    EXPECT_TRUE(contains(f, "osg_FragColor = texture_osg * sample_osg;")) << f;
}

TEST(GlslCompatText, SamplersAreReportedFromBothStages) {
    const char* vert = "uniform sampler2D heightMap;\nvoid main() { gl_Position = ftransform() + "
                       "texture2DLod(heightMap, gl_MultiTexCoord0.xy, 0.0); }\n";
    const char* frag =
        "uniform sampler2D baseTexture;\nuniform sampler2DShadow shadowTexture, extra[2];\n"
        "uniform samplerCube env;\nuniform float notASampler;\n"
        "void main() { gl_FragColor = texture2D(baseTexture, gl_TexCoord[0].xy) * "
        "shadow2D(shadowTexture, vec3(0.5)).r + textureCube(env, vec3(1.0)) * notASampler; }\n";
    const CompatProgram p = translateCompatibilityProgram("samplers", vert, frag);
    const std::vector<CompatSampler> expected = {{"heightMap", "sampler2D", 0},
                                                 {"baseTexture", "sampler2D", 0},
                                                 {"shadowTexture", "sampler2DShadow", 0},
                                                 {"extra", "sampler2DShadow", 2},
                                                 {"env", "samplerCube", 0}};
    EXPECT_EQ(p.samplers, expected);
    EXPECT_TRUE(contains(p.program->vertexSource, "textureLod(heightMap, osg_MultiTexCoord0.xy, 0.0)"));
    EXPECT_TRUE(contains(p.program->fragmentSource, "osg_shadow(shadowTexture, vec3(0.5)).r"));
}

TEST(GlslCompatText, UntranslatableConstructsNameProgramStageAndLine) {
    const std::string fog = errorOf([] {
        translateCompatibilityProgram(
            "foggy", "void main()\n{\n    gl_Position = ftransform() * gl_FogCoord;\n}\n", "");
    });
    EXPECT_TRUE(contains(fog, "'foggy'")) << fog;
    EXPECT_TRUE(contains(fog, "vertex shader line 3")) << fog;
    EXPECT_TRUE(contains(fog, "gl_FogCoord")) << fog;
    const std::string mrt = errorOf([] {
        translateCompatibilityProgram("mrt", "",
                                      "void main() {\n    gl_FragData[0] = vec4(1.0);\n"
                                      "    gl_FragData[1] = vec4(0.0);\n}\n");
    });
    EXPECT_TRUE(contains(mrt, "'mrt', fragment shader line 3")) << mrt;
    EXPECT_TRUE(contains(mrt, "gl_FragData")) << mrt;
    const std::string geometry = errorOf([] {
        const CompatShader shaders[] = {{CompatStage::Vertex, "void main() { gl_Position = ftransform(); }"},
                                        {CompatStage::Geometry, "void main() { EmitVertex(); }"}};
        translateCompatibilityProgram("explode", shaders);
    });
    EXPECT_TRUE(contains(geometry, "'explode', geometry shader")) << geometry;
    const std::string noMain =
        errorOf([] { translateCompatibilityProgram("lib", "float f() { return 1.0; }", ""); });
    EXPECT_TRUE(contains(noMain, "'lib', vertex shader")) << noMain;
    EXPECT_TRUE(contains(noMain, "main")) << noMain;
}

TEST(GlslCompatText, StandInsAndNotes) {
    const CompatProgram onlyFrag =
        translateCompatibilityProgram("frag_only", "",
                                      "#extension GL_ARB_texture_rectangle : enable\n"
                                      "void main() { gl_FragColor = gl_Color * gl_TexCoord[1]; }\n");
    const std::string& v = onlyFrag.program->vertexSource;
    EXPECT_TRUE(contains(v, "osg_FrontColor = osg_Color;")) << v;
    EXPECT_TRUE(contains(v, "osg_TexCoord[0] = osg_MultiTexCoord0;")) << v;
    EXPECT_TRUE(contains(v, "osg_TexCoord[1] = osg_MultiTexCoord1;")) << v;
    EXPECT_TRUE(contains(v, "out vec4 osg_TexCoord[2];")) << v;
    EXPECT_TRUE(contains(onlyFrag.program->fragmentSource, "in vec4 osg_TexCoord[2];"));
    const auto& notes = onlyFrag.notes;
    EXPECT_TRUE(std::any_of(notes.begin(), notes.end(),
                            [](const std::string& n) { return contains(n, "#extension"); }));
    EXPECT_TRUE(std::any_of(notes.begin(), notes.end(),
                            [](const std::string& n) { return contains(n, "stand-in"); }));
    const CompatProgram onlyVert = translateCompatibilityProgram("vert_only", kSimpleVert, "");
    EXPECT_TRUE(contains(onlyVert.program->fragmentSource, "osg_FragColor = osg_FrontColor;"));
    // The vertex shader writes no gl_FrontColor: the wrapper passes gl_Color on.
    EXPECT_TRUE(contains(onlyVert.program->vertexSource, "osg_FrontColor = osg_Color;"));
}

TEST(GlslCompatText, AttributeBindingsLocateTheShadersOwnInputs) {
    CompatOptions options;
    options.attributeLocations["tangent"] = 2;
    const CompatShader shaders[] = {
        {CompatStage::Vertex, "attribute vec4 tangent;\nattribute float weight;\nvarying vec4 t;\n"
                              "void main() { t = tangent * weight; gl_Position = ftransform(); }\n"},
        {CompatStage::Fragment, "varying vec4 t;\nvoid main() { gl_FragColor = t; }\n"}};
    const CompatProgram p = translateCompatibilityProgram("bound", shaders, options);
    EXPECT_TRUE(contains(p.program->vertexSource, "layout(location = 2) in vec4 tangent;"))
        << p.program->vertexSource;
    EXPECT_TRUE(std::any_of(p.notes.begin(), p.notes.end(),
                            [](const std::string& n) { return contains(n, "'weight'"); }));
}

TEST(GlslCompatText, MaterialUniformsCarryBothFaces) {
    CompatMaterial front, back;
    front.diffuse = {0.1f, 0.2f, 0.3f, 1.0f};
    back.shininess = 42.0f;
    const auto u = compatMaterialUniforms(front, back);
    ASSERT_EQ(u.size(), 10u);
    auto find = [&](const char* n) {
        for (const auto& [name, value] : u)
            if (name == n) return value;
        ADD_FAILURE() << "no " << n;
        return UniformValue{};
    };
    EXPECT_EQ(std::get<glm::vec4>(find(compat_uniforms::kFrontDiffuse)), front.diffuse);
    EXPECT_EQ(std::get<float>(find(compat_uniforms::kBackShininess)), 42.0f);
    EXPECT_EQ(std::get<glm::vec4>(find(compat_uniforms::kBackAmbient)), glm::vec4(0.2f, 0.2f, 0.2f, 1.0f));
    const CompatProgram p = translateCompatibilityProgram(
        "lit", "", "void main() { gl_FragColor = gl_FrontMaterial.diffuse * gl_LightSource[0].diffuse; }");
    EXPECT_TRUE(p.usesMaterial);
    EXPECT_TRUE(
        contains(p.program->fragmentSource, std::string("uniform vec4 ") + compat_uniforms::kFrontDiffuse));
    EXPECT_FALSE(translateCompatibilityProgram("plain", kSimpleVert, kSimpleFrag).usesMaterial);
}

// ---- renders (OSMesa) ----

namespace {

constexpr int kSize = 32;

// Linear RGBA of a frame of `scene` seen by orthoTopViewer(kSize, 1): pixel (x, y) shows the
// world point pixelWorld(x, y) on the plane z = 0.
struct Frame {
    FloatImage image;
    glm::vec3 at(int x, int y) const {
        const float* p = &image.rgba[(std::size_t(y) * image.width + x) * 4];
        return {p[0], p[1], p[2]};
    }
};

glm::dvec3 pixelWorld(int x, int y) {
    return {-1.0 + (x + 0.5) * 2.0 / kSize, 1.0 - (y + 0.5) * 2.0 / kSize, 0.0};
}

std::unique_ptr<Viewer> viewer() {
    auto v = orthoTopViewer(kSize, 1.0f);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    return v;
}

Frame render(Viewer& v, std::shared_ptr<Node> scene) {
    v.setSceneData(std::move(scene));
    v.frame();
    expectNoGlErrors(v);
    return {v.renderer().readPixelsLinear()};
}

Frame render(std::shared_ptr<Node> scene, const std::function<void(Viewer&)>& setup = {}) {
    auto v = viewer();
    if (setup) setup(*v);
    return render(*v, std::move(scene));
}

// One triangle covering the view, with the attributes a test gives it.
std::shared_ptr<Geometry> bigTriangle(const glm::vec3 (&p)[3]) {
    auto g = Geometry::create();
    g->positions.assign(std::begin(p), std::end(p));
    return g;
}

// Barycentric coordinates of world point q in the screen triangle a, b, c (xy only).
glm::dvec3 barycentric(glm::dvec2 q, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    const double d = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
    const double l0 = ((b.y - c.y) * (q.x - c.x) + (c.x - b.x) * (q.y - c.y)) / d;
    const double l1 = ((c.y - a.y) * (q.x - c.x) + (a.x - c.x) * (q.y - c.y)) / d;
    return {l0, l1, 1.0 - l0 - l1};
}

std::shared_ptr<Node> with(std::shared_ptr<Geometry> g, const CompatProgram& p,
                           const glm::mat4& m = glm::mat4(1.0f)) {
    g->getOrCreateStateSet().program.set(p.program);
    g->getOrCreateStateSet().cullFace.set(CullFace::None);
    auto t = Transform::create(m);
    t->addChild(std::move(g));
    return t;
}

} // namespace

TEST(GlslCompatRender, SimpleProgramShowsTheObjectPosition) {
    // glsl_simple's first program: colour = clamp(gl_Vertex). The quad is scaled and moved, so
    // gl_Vertex (object space) differs from the world position the pixel shows.
    const CompatProgram p = translateCompatibilityProgram("glsl_simple_1", kSimpleVert, kSimpleFrag);
    const glm::mat4 m = glm::scale(glm::translate(glm::mat4(1.0f), {0.25f, -0.1f, 0}), glm::vec3(0.5f));
    const Frame f = render(with(shapes::quad(4, 4), p, m));
    int checked = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const glm::dvec3 w = pixelWorld(x, y);
            const glm::dvec3 object((w.x - 0.25) / 0.5, (w.y + 0.1) / 0.5, 0.0);
            if (std::abs(object.x) > 1.95 || std::abs(object.y) > 1.95) continue; // outside or on the edge
            const glm::dvec3 expected = glm::clamp(object, 0.0, 1.0);
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(f.at(x, y)[c], expected[c], 0.01) << x << "," << y << " channel " << c;
            ++checked;
        }
    EXPECT_GT(checked, kSize * kSize * 3 / 4);
}

TEST(GlslCompatRender, BlockyProgramMatchesTheCpu) {
    // glsl_simple's second program. Its blocks lie on the object's XZ plane, so the triangle lies
    // there (normal +Y) and a rotation turns it to the camera. Sine = 0 scales gl_Position's w by
    // 1.4, which shrinks the drawing 1.4 times; the light is per vertex (Gouraud), so the CPU
    // interpolates the three vertices' intensities.
    const CompatProgram p = translateCompatibilityProgram("glsl_simple_2", kBlockyVert, kBlockyFrag);
    const double wScale = 1.4, sine = 0.0;
    const glm::vec3 color1(0.9f, 0.6f, 0.2f), color2(0.2f, 0.3f, 0.8f);
    const glm::mat4 m = glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0));
    // Screen (after the w scale) → object: world (x, y) = (ox, -oz) / 1.4.
    auto object = [&](glm::dvec2 s) { return glm::dvec3(s.x * wScale, 0.0, -s.y * wScale); };
    const glm::dvec2 screen[3] = {{-1.1, -1.1}, {4.0, -1.1}, {-1.1, 4.0}};
    glm::vec3 corners[3];
    for (int i = 0; i < 3; ++i)
        corners[i] = glm::vec3(object(screen[i]));
    auto g = bigTriangle(corners);
    g->normals.assign(3, glm::vec3(0, 1, 0));
    auto node = with(g, p, m);
    g->getOrCreateStateSet().setUniform("Sine", float(sine));
    g->getOrCreateStateSet().setUniform("Color1", color1);
    g->getOrCreateStateSet().setUniform("Color2", color2);
    const Frame f = render(node);
    // Per vertex: eye position (the camera sits at z = 10 looking down), eye normal (0, 0, 1).
    double intensity[3];
    for (int i = 0; i < 3; ++i) {
        const glm::dvec3 world = glm::dmat4(m) * glm::dvec4(glm::dvec3(corners[i]), 1.0);
        const glm::dvec3 eye = world - glm::dvec3(0, 0, 10);
        intensity[i] = std::max(glm::normalize(glm::dvec3(0, 0, 4) - eye).z, 0.0);
    }
    const double blockFract = (sine + 1.1) * 0.4;
    int checked = 0, bricks = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const glm::dvec3 w = pixelWorld(x, y);
            const glm::dvec3 b = barycentric(glm::dvec2(w), screen[0], screen[1], screen[2]);
            const glm::dvec3 o = object(glm::dvec2(w));
            double ss = o.x / 0.30, tt = o.z / 0.30;
            if (std::fmod(tt * 0.5 - std::floor(tt * 0.5), 1.0) > 0.5) ss += 0.5;
            ss -= std::floor(ss);
            tt -= std::floor(tt);
            // Pixels at a block edge may go either way: skip them.
            auto near = [](double a, double e) { return std::abs(a - e) < 0.06 || a < 0.03 || a > 0.97; };
            if (near(ss, blockFract) || near(tt, blockFract)) continue;
            const double inBlock = (ss <= blockFract) && (tt <= blockFract) ? 1.0 : 0.0;
            const double light = b.x * intensity[0] + b.y * intensity[1] + b.z * intensity[2];
            const glm::dvec3 expected = glm::mix(glm::dvec3(color2), glm::dvec3(color1), inBlock) * light;
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(f.at(x, y)[c], expected[c], 0.01) << x << "," << y << " channel " << c;
            ++checked;
            bricks += inBlock > 0;
        }
    EXPECT_GT(checked, kSize * kSize / 3);
    EXPECT_GT(bricks, 20);
    EXPECT_GT(checked - bricks, 20);
}

TEST(GlslCompatRender, ColourDefaultsToWhiteAndTexCoordsPassThrough) {
    // Fragment stage only: the stand-in vertex stage passes gl_Color and gl_MultiTexCoord0.
    const CompatProgram p = translateCompatibilityProgram(
        "uv", "", "void main() { gl_FragColor = vec4(gl_Color.rgb * vec3(gl_TexCoord[0].xy, 1.0), 1.0); }");
    const glm::vec3 corners[3] = {{-1.5f, -1.5f, 0}, {4, -1.5f, 0}, {-1.5f, 4, 0}};
    const glm::vec2 uv[3] = {{0.1f, 0.2f}, {0.9f, 0.3f}, {0.2f, 0.8f}};
    const glm::vec3 vertexColour(0.5f, 1.0f, 0.25f);
    // One viewer, the coloured geometry first: its colour array must not leave a current value
    // behind for the next geometry without colours.
    auto v = viewer();
    for (const bool coloured : {true, false}) {
        auto g = bigTriangle(corners);
        g->texcoords.assign(std::begin(uv), std::end(uv));
        if (coloured) g->colors.assign(3, glm::vec4(vertexColour, 1.0f));
        const Frame f = render(*v, with(g, p));
        const glm::dvec3 tint =
            coloured ? glm::dvec3(vertexColour) : glm::dvec3(1.0); // OSG: white without colours
        for (int y = 0; y < kSize; y += 3)
            for (int x = 0; x < kSize; x += 3) {
                const glm::dvec3 w = pixelWorld(x, y);
                const glm::dvec3 b =
                    barycentric(glm::dvec2(w), glm::dvec2(glm::vec2(corners[0])),
                                glm::dvec2(glm::vec2(corners[1])), glm::dvec2(glm::vec2(corners[2])));
                const glm::dvec2 t =
                    b.x * glm::dvec2(uv[0]) + b.y * glm::dvec2(uv[1]) + b.z * glm::dvec2(uv[2]);
                const glm::dvec3 expected = tint * glm::dvec3(t, 1.0);
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(f.at(x, y)[c], expected[c], 0.01)
                        << (coloured ? "coloured " : "uncoloured ") << x << "," << y << " channel " << c;
            }
    }
}

TEST(GlslCompatRender, EyeSpaceNormalsLightsAndMaterial) {
    // gl_NormalMatrix * gl_Normal dotted with gl_LightSource[0].position (eye space), times the
    // material and light colours. The model scales unevenly and the camera rolls, so neither the
    // world normal nor the object normal would give the same picture.
    const char* vert = "varying vec3 n;\nvoid main() {\n    n = gl_NormalMatrix * gl_Normal;\n"
                       "    gl_Position = ftransform();\n}\n";
    const char* frag =
        "varying vec3 n;\nvoid main() {\n"
        "    float d = max(dot(normalize(n), normalize(gl_LightSource[0].position.xyz)), 0.0);\n"
        "    gl_FragColor = vec4(gl_FrontLightModelProduct.sceneColor.rgb + \n"
        "        gl_FrontMaterial.diffuse.rgb * gl_LightSource[0].diffuse.rgb * d, 1.0);\n}\n";
    const CompatProgram p = translateCompatibilityProgram("lit", vert, frag);
    ASSERT_TRUE(p.usesMaterial);
    const glm::vec3 objectNormal = glm::normalize(glm::vec3(0.3f, -0.2f, 1.0f));
    const glm::mat4 m = glm::scale(glm::rotate(glm::mat4(1.0f), glm::radians(25.0f), glm::vec3(0, 1, 0)),
                                   glm::vec3(1.0f, 2.0f, 0.5f));
    const glm::vec3 corners[3] = {{-3, -3, 0}, {6, -3, 0}, {-3, 6, 0}};
    auto g = bigTriangle(corners);
    g->normals.assign(3, objectNormal);
    auto scene = Group::create();
    auto light = Light::create(LightType::Directional);
    light->direction = glm::normalize(glm::vec3(-0.4f, -0.3f, -1.0f));
    light->color = {1.0f, 0.8f, 0.6f};
    scene->addChild(light);
    scene->addChild(with(g, p, m));
    CompatMaterial front;
    front.diffuse = {0.7f, 0.5f, 0.9f, 1.0f};
    front.emission = {0.05f, 0.02f, 0.0f, 1.0f};
    front.ambient = {0.0f, 0.0f, 0.0f, 1.0f};
    for (const auto& [name, value] : compatMaterialUniforms(front, CompatMaterial{}))
        g->getOrCreateStateSet().setUniform(name, value);
    const glm::vec3 eye(0, 0, 10), up(1, 0, 0);
    const Frame f = render(scene, [&](Viewer& v) { v.camera()->setLookAt(eye, {0, 0, 0}, up); });
    // CPU: the eye normal from the inverse transpose, the light direction into eye space.
    const glm::dmat4 view = glm::lookAt(glm::dvec3(eye), glm::dvec3(0), glm::dvec3(up));
    const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(view * glm::dmat4(m))));
    const glm::dvec3 n = glm::normalize(normalMatrix * glm::dvec3(objectNormal));
    const glm::dvec3 toLight = glm::normalize(glm::dmat3(view) * -glm::dvec3(light->direction));
    const glm::dvec3 expected = glm::dvec3(front.emission) + glm::dvec3(front.diffuse) *
                                                                 glm::dvec3(light->color) *
                                                                 std::max(glm::dot(n, toLight), 0.0);
    ASSERT_GT(glm::dot(n, toLight), 0.2);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(f.at(kSize / 2, kSize / 2)[c], expected[c], 0.01) << "channel " << c;
    EXPECT_NEAR(f.at(3, 28)[1], expected[1], 0.01) << "flat shading: the same everywhere";
}

TEST(GlslCompatRender, DriverErrorsPointAtTheOriginalLine) {
    const CompatProgram p = translateCompatibilityProgram(
        "typo", kSimpleVert, "varying vec4 color;\nvoid main()\n{\n    gl_FragColor = colour;\n}\n");
    auto v = orthoTopViewer(kSize, 1.0f);
    v->setSceneData(with(shapes::quad(2, 2), p));
    try {
        v->frame();
        FAIL() << "a broken shader compiled";
    } catch (const ShaderError& e) {
        EXPECT_TRUE(contains(e.what(), "typo.frag:4:")) << e.what();
    }
}

TEST(GlslCompatRender, ProgramsOwnGlFogFogsNothing) {
    // A program that fogs itself with gl_Fog (exp2, linear) shows its colour unfogged: sgfx's
    // FogNode does the fog (the test above), gl_Fog has density 0 and reaches to 1e30.
    const CompatProgram p = translateCompatibilityProgram(
        "selffog", "",
        "void main() {\n"
        "    float z = gl_FragCoord.z / gl_FragCoord.w;\n"
        "    float e = exp(-gl_Fog.density * gl_Fog.density * z * z);\n"
        "    float l = clamp((gl_Fog.end - z) * gl_Fog.scale, 0.0, 1.0);\n"
        "    gl_FragColor = mix(gl_Fog.color, vec4(0.25, 0.5, 0.75, 1.0), e * l);\n"
        "}\n");
    EXPECT_FALSE(p.notes.empty());
    const Frame f = render(with(shapes::quad(2, 2), p));
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(f.at(kSize / 2, kSize / 2)[c], 0.25 * (c + 1), 0.01) << c;
}

TEST(GlslCompatRender, FogAppliesToTranslatedPrograms) {
    // glsl_simple's first program under homogeneous fog: each pixel is the fog formula
    // (FogMath.h, the CPU mirror) applied to the same pixel unfogged.
    const CompatProgram p = translateCompatibilityProgram("glsl_simple_1", kSimpleVert, kSimpleFrag);
    FogParameters fp;
    fp.density = 0.05f;
    fp.falloff = 0.0f;
    fp.color = {0.2f, 0.4f, 0.6f};
    fp.sky = FogSky::Off;
    auto fog = FogNode::create(fp);
    fog->addChild(with(shapes::quad(2, 2), p));
    const Frame plain = render(with(shapes::quad(2, 2), p));
    const Frame fogged = render(fog);
    const glm::dvec3 eye(0, 0, 10);
    for (int y = 1; y < kSize - 1; y += 2)
        for (int x = 1; x < kSize - 1; x += 2) {
            const glm::dvec3 w = pixelWorld(x, y);
            const double F = fog::opticalDepth<double>(fp.density, fp.falloff, eye.z - fp.referenceHeight,
                                                       w.z - fp.referenceHeight, glm::length(w - eye));
            const double k = fog::amount<double>(F, fog::Response::Exponential, fp.maxOpacity);
            ASSERT_GT(k, 0.3);
            for (int c = 0; c < 3; ++c) {
                const double expected = plain.at(x, y)[c] * (1 - k) + fp.color[c] * k;
                ASSERT_NEAR(fogged.at(x, y)[c], expected, 0.01) << x << "," << y << " channel " << c;
            }
        }
}

namespace {

// The corner of ao_test's ForeignShadersOptIn (a floor and a wall meeting at y = 2) drawn with
// `program`, seen in perspective under an ambient light, with AO when asked: the red channel at
// the world point `p`.
double cornerRed(const std::shared_ptr<ShaderProgram>& program, bool ao, glm::vec3 p) {
    auto scene = Group::create();
    for (int i = 0; i < 2; ++i) {
        auto q = shapes::quad(20, 20);
        q->getOrCreateStateSet().program.set(program);
        q->getOrCreateStateSet().cullFace.set(CullFace::None);
        auto t = Transform::create(
            i == 0 ? glm::mat4(1.0f)
                   : glm::translate(glm::mat4(1.0f), {0, 2, 0}) *
                         glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0)));
        t->addChild(q);
        scene->addChild(t);
    }
    auto v = Viewer::createHeadless(96, 96); // ao_test's size
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    auto& cam = *v->camera();
    cam.setPerspective(60.0f, 0.5f, 500.0f);
    cam.setLookAt({0, -3, 3}, {0, 2, 0}, {0, 0, 1});
    auto root = Group::create();
    root->addChild(Light::create(LightType::Ambient));
    if (ao) {
        auto node = AmbientOcclusionNode::create();
        node->addChild(scene);
        root->addChild(node);
    } else {
        root->addChild(scene);
    }
    v->setSceneData(root);
    v->frame();
    expectNoGlErrors(*v);
    const FloatImage img = v->renderer().readPixelsLinear();
    const glm::vec4 c = cam.projectionMatrix * cam.viewMatrix * glm::vec4(p, 1.0f);
    const int x = int((c.x / c.w * 0.5f + 0.5f) * float(img.width));
    const int y = int((0.5f - c.y / c.w * 0.5f) * float(img.height));
    return img.rgba[(std::size_t(y) * img.width + x) * 4];
}

} // namespace

TEST(GlslCompatRender, AmbientOcclusionDarkensTranslatedPrograms) {
    // A white OSG program: under AO it shows 1 − k, as the hand-written opt-in shader of the AO
    // tests does (kForeignAoFrag).
    const CompatProgram p = translateCompatibilityProgram(
        "white", "void main() { gl_Position = ftransform(); }", "void main() { gl_FragColor = vec4(1.0); }");
    const auto reference = ShaderProgram::create("reference_ao", kForeignVert, kForeignAoFrag);
    const glm::vec3 crease(0.3f, 1.96f, 0.0f), open(0.3f, 0.5f, 0.0f);
    EXPECT_NEAR(cornerRed(p.program, false, crease), 1.0, 1e-4) << "no AO node: untouched";
    const double k = 1.0 - cornerRed(p.program, true, crease);
    EXPECT_GT(k, 0.2) << "the crease";
    EXPECT_NEAR(k, 1.0 - cornerRed(reference, true, crease), 0.02) << "as the opt-in reference shader";
    EXPECT_LE(1.0 - cornerRed(p.program, true, open), 0.02) << "the open floor";
}

TEST(GlslCompatRender, FrameTimeIsTheSimulationTime) {
    const CompatProgram p = translateCompatibilityProgram(
        "clock", "",
        "uniform float osg_FrameTime;\nvoid main() { gl_FragColor = vec4(osg_FrameTime * 0.1); }");
    auto v = viewer();
    v->setSceneData(with(shapes::quad(2, 2), p));
    v->frame(2.5);
    expectNoGlErrors(*v);
    const Frame f{v->renderer().readPixelsLinear()};
    ASSERT_GT(v->simulationTime(), 1.0);
    EXPECT_NEAR(f.at(kSize / 2, kSize / 2).x, v->simulationTime() * 0.1, 1e-4);
}

TEST(GlslCompatRender, ShadowsReachGlLightSource) {
    // A plane showing gl_LightSource[0].diffuse under a ShadowNode, a box above it, the sun
    // slanting along +X: the box's shadow falls on −X of it, the rest is lit.
    const CompatProgram p = translateCompatibilityProgram(
        "receiver", "", "void main() { gl_FragColor = vec4(gl_LightSource[0].diffuse.rgb, 1.0); }");
    auto sun = Light::create(LightType::Directional);
    sun->direction = glm::normalize(glm::vec3(-1, 0, -1));
    auto shadow = ShadowNode::create(sun);
    auto plane = shapes::quad(6, 6);
    plane->getOrCreateStateSet().program.set(p.program);
    shadow->addChild(plane);
    auto box = Transform::create(glm::translate(glm::mat4(1.0f), {0, 0, 1}));
    box->addChild(shapes::box({0.6f, 0.6f, 0.6f}));
    shadow->addChild(box);
    auto root = Group::create();
    root->addChild(sun);
    root->addChild(shadow);
    auto v = orthoTopViewer(64, 2.0f);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    v->setSceneData(root);
    v->frame();
    expectNoGlErrors(*v);
    const FloatImage img = v->renderer().readPixelsLinear();
    auto red = [&](double wx, double wy) {
        const int x = int((wx + 2) / 4 * 64), y = int((2 - wy) / 4 * 64);
        return img.rgba[(std::size_t(y) * img.width + x) * 4];
    };
    EXPECT_LT(red(-1.0, 0.0), 0.1) << "in the box's shadow (x from -1.6 to -0.4)";
    EXPECT_GT(red(1.2, 0.0), 0.9) << "lit, on the sun's side";
    EXPECT_GT(red(-1.0, 1.0), 0.9) << "lit, beside the shadow";
}

TEST(GlslCompatRender, EveryTranslatedBuiltInCompilesUnderEveryEffect) {
    // One program touching most of what is translated, drawn under AO, fog and shadows at once
    // (and alone): it compiles, links and draws without a GL error.
    const char* vert = R"(#version 120
#extension GL_EXT_gpu_shader4 : enable
uniform float osg_SimulationTime;
uniform mat4 osg_ViewMatrixInverse;
attribute vec4 tangent;
varying vec3 normal, lightDir;
void main() {
    vec4 ec = gl_ModelViewMatrix * gl_Vertex;
    normal = gl_NormalMatrix * gl_Normal + (gl_ModelViewMatrixInverse * ec).xyz * 0.0;
    lightDir = gl_LightSource[0].position.xyz - ec.xyz * gl_LightSource[0].position.w;
    gl_FrontColor = gl_Color * gl_FrontMaterial.diffuse;
    gl_BackColor = gl_Color;
    gl_TexCoord[0] = gl_TextureMatrix[0] * gl_MultiTexCoord0;
    gl_TexCoord[1] = gl_MultiTexCoord1 + gl_MultiTexCoord2 + tangent;
    gl_ClipVertex = ec;
    gl_Position = gl_ProjectionMatrix * ec + vec4(osg_ViewMatrixInverse[3].xyz * 0.0, 0.0)
        + 0.0 * osg_SimulationTime;
}
)";
    const char* frag = R"(#version 120
uniform sampler2D baseTexture;
uniform sampler2DShadow shadowTexture;
uniform samplerCube reflectionMap;
varying vec3 normal, lightDir;
void main() {
    vec3 n = normalize(normal);
    float d = max(dot(n, normalize(lightDir)), 0.0);
    vec4 base = texture2D(baseTexture, gl_TexCoord[0].st) + texture2DProj(baseTexture, gl_TexCoord[1]);
    float lit = shadow2D(shadowTexture, gl_TexCoord[0].stp).r;
    vec4 env = textureCube(reflectionMap, reflect(n, vec3(0.0, 0.0, 1.0)));
    vec4 c = gl_FrontLightModelProduct.sceneColor + gl_FrontLightProduct[0].diffuse * d * lit
        + gl_LightModel.ambient * gl_FrontMaterial.ambient + pow(d, gl_FrontMaterial.shininess) * gl_FrontMaterial.specular;
    gl_FragData[0] = c * gl_Color * base + env * 0.0;
}
)";
    const CompatProgram p = translateCompatibilityProgram("kitchen_sink", vert, frag);
    EXPECT_EQ(p.samplers.size(), 3u);
    for (int effects = 0; effects < 2; ++effects) {
        SCOPED_TRACE(effects ? "under AO, fog and shadows" : "alone");
        auto sun = Light::create(LightType::Directional);
        auto g = shapes::box({1, 1, 1});
        g->colors.assign(g->positions.size(), glm::vec4(1.0f));
        std::shared_ptr<Node> scene = with(g, p);
        if (effects) {
            auto ao = AmbientOcclusionNode::create();
            ao->addChild(scene);
            auto fog = FogNode::create(FogParameters{});
            fog->addChild(ao);
            auto shadow = ShadowNode::create(sun);
            shadow->addChild(fog);
            scene = shadow;
        }
        auto root = Group::create();
        root->addChild(sun);
        root->addChild(scene);
        auto v = viewer();
        v->setSceneData(root);
        EXPECT_NO_THROW(v->frame());
        expectNoGlErrors(*v);
    }
}

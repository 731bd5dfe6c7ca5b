// ShaderComposer: text composition (no GL), then variant caching, foreign wrapping and error
// messages on a real OSMesa context.
#include "TestUtil.h"

#include <sgfx/Group.h>
#include <sgfx/ShaderComposer.h>
#include <sgfx/Shapes.h>
#include <sgfx/gl/Objects.h>
#include <sgfx/nodes/debugtint/DebugTintNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

using namespace sgfx;
using namespace sgfx::test;

namespace {

class SnippetEffect : public EffectNode {
public:
    explicit SnippetEffect(ShaderSnippet s, std::string kind = "test")
        : snippet_(std::move(s))
        , kind_(std::move(kind)) {}
    std::string_view kind() const override { return kind_; }
    const ShaderSnippet& snippet() const override { return snippet_; }

private:
    ShaderSnippet snippet_;
    std::string kind_;
};

ShaderSnippet snippet(std::string name, std::string decl, std::string color) {
    ShaderSnippet s;
    s.name = std::move(name);
    s.fragmentDecl = std::move(decl);
    s.colorCode = std::move(color);
    return s;
}

std::size_t countOf(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + 1))
        ++n;
    return n;
}

} // namespace

TEST(ComposerText, HooksReceiveSnippetCodeInOrder) {
    const ShaderSnippet a = snippet("alpha", "uniform float alphaU;", "sgfx_color.r += 0.1;");
    ShaderSnippet b = snippet("beta", "", "sgfx_color.g += 0.2;");
    b.ambientCode = "sgfx_ambient *= 0.5;";
    b.vertexCode = "sgfx_worldPos.z += 1.0;";
    b.defines = "#define BETA 1";
    const ShaderSnippet* list[] = {&a, &b};
    const ComposedProgram p = ShaderComposer::composeBuiltin(ShaderComposer::blinnPhong(), list);
    EXPECT_EQ(p.description, "blinn_phong + [alpha, beta] {LIGHT_COUNT 0}");
    // Each piece appears once, in the right stage, after its hook, alpha before beta.
    EXPECT_EQ(countOf(p.fragment, "uniform float alphaU;"), 1u);
    EXPECT_EQ(countOf(p.vertex, "sgfx_worldPos.z += 1.0;"), 1u);
    EXPECT_EQ(countOf(p.fragment, "sgfx_worldPos.z += 1.0;"), 0u);
    EXPECT_LT(p.fragment.find("sgfx_color.r += 0.1;"), p.fragment.find("sgfx_color.g += 0.2;"));
    EXPECT_LT(p.fragment.find("sgfx_ambient *= 0.5;"), p.fragment.find("vec3 color = sgfx_matEmissive"));
    EXPECT_GT(p.fragment.find("sgfx_color.g += 0.2;"),
              p.fragment.find("vec4 sgfx_color = vec4(color + added, base.a);"));
    EXPECT_EQ(p.fragment.rfind("#version 450 core", 0), 0u); // #version stays first
    EXPECT_NE(p.fragment.find("#define BETA 1"), std::string::npos);
    // Source names for #line numbers.
    EXPECT_NE(std::find(p.fragmentSources.begin(), p.fragmentSources.end(), "alpha.colorCode"),
              p.fragmentSources.end());
    EXPECT_NE(std::find(p.fragmentSources.begin(), p.fragmentSources.end(), "blinn_phong.frag"),
              p.fragmentSources.end());
    EXPECT_NE(std::find(p.vertexSources.begin(), p.vertexSources.end(), "beta.vertexCode"),
              p.vertexSources.end());
    // No snippets: no hook code, and no stray marker text left as code.
    const ComposedProgram plain = ShaderComposer::composeBuiltin(ShaderComposer::blinnPhong(), {});
    EXPECT_EQ(plain.description, "blinn_phong + [] {LIGHT_COUNT 0}");
    // Feature variants become defines and are named in the description.
    const ComposedProgram masked = ShaderComposer::composeBuiltin(
        ShaderComposer::blinnPhong(), {}, FeatureAlphaMask | FeatureNormals | (2u << FeatureLightCountShift));
    EXPECT_NE(masked.fragment.find("#define SGFX_ALPHA_MASK"), std::string::npos);
    EXPECT_NE(masked.fragment.find("#define SGFX_LIGHT_COUNT 2"), std::string::npos);
    EXPECT_EQ(plain.fragment.find("#define SGFX_ALPHA_MASK"), std::string::npos);
    EXPECT_EQ(masked.description, "blinn_phong + [] {NORMALS ALPHA_MASK LIGHT_COUNT 2}");
    EXPECT_EQ(countOf(plain.fragment, "alphaU"), 0u);
}

TEST(ComposerText, ForeignMainIsRenamedAndWrapped) {
    const ShaderSnippet a = snippet("tintish", "uniform vec4 tintU;", "sgfx_color.rgb *= tintU.rgb;");
    const ShaderSnippet* list[] = {&a};
    auto prog = ShaderProgram::create("app", kForeignVert, kForeignFrag);
    const ComposedProgram p = ShaderComposer::composeForeign(*prog, list);
    EXPECT_NE(p.fragment.find("void sgfx_user_main()"), std::string::npos);
    EXPECT_EQ(countOf(p.fragment, "void main()"), 1u); // only the wrapper
    EXPECT_NE(p.fragment.find("vec4 sgfx_color = fragOut;"), std::string::npos);
    EXPECT_NE(p.fragment.find("fragOut = sgfx_color;"), std::string::npos);
    EXPECT_EQ(p.vertex, prog->vertexSource);
    // An output without a location is pinned to 0 (snippets may add located outputs).
    auto unlocated = ShaderProgram::create(
        "app2", kForeignVert, "#version 450 core\nout vec4 color;\nvoid main() { color = vec4(1); }\n");
    const ComposedProgram u = ShaderComposer::composeForeign(*unlocated, list);
    EXPECT_NE(u.fragment.find("layout(location = 0) out vec4 color;"), std::string::npos) << u.fragment;
    EXPECT_EQ(countOf(u.fragment, "out vec4 color;"), 1u);
    // A shader without a colour output cannot be wrapped: say so.
    auto bad = ShaderProgram::create("noout", kForeignVert, "#version 450 core\nvoid main() {}\n");
    try {
        (void)ShaderComposer::composeForeign(*bad, list);
        FAIL();
    } catch (const ShaderError& e) {
        EXPECT_NE(std::string(e.what()).find("'noout'"), std::string::npos) << e.what();
    }
}

TEST(ComposerText, DriverLogsAreTranslatedToOriginalNames) {
    const std::vector<std::string> names = {"<sgfx preamble>", "blinn_phong.frag", "fog.colorCode"};
    EXPECT_EQ(ShaderComposer::translateLog("2:3(7): error: `x' undeclared", names),
              "fog.colorCode:3: error: `x' undeclared\n");
    EXPECT_EQ(ShaderComposer::translateLog("1(12) : error C1008: undefined variable", names),
              "blinn_phong.frag:12: error C1008: undefined variable\n");
    // Line numbers that carry the source (k * 10000 + n), for drivers that drop the source number.
    EXPECT_EQ(ShaderComposer::translateLog("0:20003(1): error: bad", names), "fog.colorCode:3: error: bad\n");
}

class ComposerGl : public ::testing::Test {
protected:
    void SetUp() override {
        viewer = orthoTopViewer(32, 2.0f);
        root = Group::create();
        viewer->setSceneData(root);
    }
    std::shared_ptr<Node> quad(glm::vec3 pos, float w, std::shared_ptr<ShaderProgram> program = nullptr) {
        auto t = Transform::create(glm::translate(glm::mat4(1.0f), pos));
        auto q = shapes::quad(w, 4.0f);
        auto m = Material::create();
        m->ambient = glm::vec3(0);
        m->diffuse = {0, 0, 0, 1};
        m->emissive = {0.8f, 0.4f, 0.1f};
        q->getOrCreateStateSet().material.set(m);
        if (program) {
            q->getOrCreateStateSet().program.set(program);
            q->getOrCreateStateSet().setUniform("appColor", glm::vec3(0.8f, 0.4f, 0.1f));
        }
        t->addChild(q);
        return t;
    }
    std::unique_ptr<Viewer> viewer;
    std::shared_ptr<Group> root;
};

TEST_F(ComposerGl, VariantsAreCachedAndTogglingCompilesNothingNew) {
    auto tint = DebugTintNode::create({0, 1, 0, 0.5f});
    tint->addChild(quad({-1, 0, 0}, 2.0f));
    root->addChild(tint);
    root->addChild(quad({1, 0, 0}, 2.0f));
    ShaderComposer& c = viewer->renderer().composer();
    viewer->frame();
    EXPECT_EQ(c.misses(), 2u); // plain + tinted
    EXPECT_EQ(c.size(), 2u);
    const std::size_t hits = c.hits();
    viewer->frame();
    EXPECT_EQ(c.misses(), 2u);
    EXPECT_GT(c.hits(), hits);
    tint->enabled = false;
    viewer->frame();
    tint->enabled = true;
    viewer->frame();
    EXPECT_EQ(c.misses(), 2u); // both variants already existed
    // Two tint nodes with the same snippet share one program.
    auto tint2 = DebugTintNode::create({1, 0, 0, 0.1f});
    tint2->addChild(quad({0, 1, 0.5f}, 1.0f));
    root->addChild(tint2);
    viewer->frame();
    EXPECT_EQ(c.misses(), 2u);
}

TEST_F(ComposerGl, ForeignShaderGetsEffectsLikeTheBuiltInMaterial) {
    auto prog = ShaderProgram::create("app", kForeignVert, kForeignFrag);
    auto tint = DebugTintNode::create({0, 0.5f, 1, 0.4f});
    tint->addChild(quad({-1, 0, 0}, 2.0f, prog)); // foreign, left half
    tint->addChild(quad({1, 0, 0}, 2.0f));        // built-in, right half
    root->addChild(tint);
    viewer->frame();
    const Image img = viewer->capture();
    const glm::dvec3 expected = glm::mix(glm::dvec3(0.8, 0.4, 0.1), glm::dvec3(0, 0.5, 1), 0.4);
    for (int x : {4, 27}) {
        const glm::ivec4 p = pixelAt(img, x, 16);
        for (int ch = 0; ch < 3; ++ch)
            EXPECT_NEAR(p[ch], srgbByte(expected[ch]), 2) << "x=" << x << " ch " << ch;
    }
    for (const auto& e : viewer->renderer().takeGlErrors())
        ADD_FAILURE() << e;
}

TEST_F(ComposerGl, ForeignWrapReconstructsTheWorldPosition) {
    // An effect that writes the world position as colour: built-in (interpolated) and foreign
    // (reconstructed from gl_FragCoord and depth) must agree.
    auto show = std::make_shared<SnippetEffect>(
        snippet("show_world", "", "sgfx_color = vec4(fract(sgfx_worldPos * 0.5 + 0.25), 1.0);"));
    auto prog = ShaderProgram::create("app", kForeignVert, kForeignFrag);
    viewer->camera()->setLookAt({3, -4, 6}, {0, 0, 0});
    viewer->camera()->setPerspective(50.0f, 0.5f, 50.0f);
    auto left = quad({-1, 0, 0.3f}, 2.0f, prog);
    auto right = quad({-1, 0, 0.3f}, 2.0f);
    show->addChild(left);
    root->addChild(show);
    viewer->frame();
    const Image foreignImg = viewer->capture();
    show->replaceChild(0, right);
    viewer->frame();
    const Image builtinImg = viewer->capture();
    int compared = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const glm::ivec4 a = pixelAt(foreignImg, x, y), b = pixelAt(builtinImg, x, y);
            if (b == glm::ivec4(0, 0, 0, 255)) continue; // background
            ++compared;
            for (int ch = 0; ch < 3; ++ch)
                ASSERT_NEAR(a[ch], b[ch], 3) << x << "," << y;
        }
    EXPECT_GT(compared, 50);
}

TEST_F(ComposerGl, StatementCodeMayOpenWithADirective) {
    // A statement hook's code is scoped by braces; it may still begin with a preprocessor line,
    // on the built-in material (left) and in a foreign shader's wrap (right).
    auto fx = std::make_shared<SnippetEffect>(
        snippet("directive_fx", "", "#ifndef SGFX_BLEND\nsgfx_color = vec4(0.0, 1.0, 0.0, 1.0);\n#endif"));
    fx->addChild(quad({-1, 0, 0}, 2.0f));
    fx->addChild(quad({1, 0, 0}, 2.0f, ShaderProgram::create("app", kForeignVert, kForeignFrag)));
    root->addChild(fx);
    ASSERT_NO_THROW(viewer->frame());
    const Image img = viewer->capture();
    for (int x : {4, 27})
        EXPECT_EQ(pixelAt(img, x, 16), glm::ivec4(0, 255, 0, 255)) << "x=" << x;
}

TEST_F(ComposerGl, CompileErrorsNameShaderSnippetAndLine) {
    // Error on line 5 of the application's fragment shader.
    const char* broken = "#version 450 core\nuniform vec3 appColor;\nlayout(location = 0) out vec4 fragOut;\n"
                         "void main() {\n    fragOut = vec4(undefinedThing, 1.0);\n}\n";
    auto prog = ShaderProgram::create("cockpit_glass", kForeignVert, broken);
    auto tint = DebugTintNode::create();
    tint->addChild(quad({0, 0, 0}, 2.0f, prog));
    root->addChild(tint);
    try {
        viewer->frame();
        FAIL() << "broken shader accepted";
    } catch (const ShaderError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("cockpit_glass + [debug_tint]"), std::string::npos) << msg;
        EXPECT_NE(msg.find("cockpit_glass.frag:5:"), std::string::npos) << msg;
    }
    // A broken snippet: the error names the snippet's chunk and its own line 2.
    root->removeChildren();
    auto bad =
        std::make_shared<SnippetEffect>(snippet("bad_fx", "", "sgfx_color.rgb *= 2.0;\nsgfx_color += nope;"));
    bad->addChild(quad({0, 0, 0}, 2.0f));
    root->addChild(bad);
    try {
        viewer->frame();
        FAIL() << "broken snippet accepted";
    } catch (const ShaderError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("blinn_phong + [bad_fx]"), std::string::npos) << msg;
        EXPECT_NE(msg.find("bad_fx.colorCode:2:"), std::string::npos) << msg;
    }
    // The viewer keeps working once the bad content is gone.
    root->removeChildren();
    root->addChild(quad({0, 0, 0}, 2.0f));
    EXPECT_NO_THROW(viewer->frame());
}

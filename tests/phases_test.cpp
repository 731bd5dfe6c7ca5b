// Cull and frame setup make no GL calls and change no node (issue 22 item 5): every effect of the
// kit is culled and set up while GL entry points that create, bind, draw or query are stubs that
// count their calls. glad keeps the entry points in global pointers, so the stubs replace them.
#include "TestUtil.h"

#include <sgfx/CullVisitor.h>
#include <sgfx/FrameSetup.h>
#include <sgfx/Group.h>
#include <sgfx/Shapes.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/debugtint/DebugTintNode.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>
#include <sgfx/nodes/sky/SkyNode.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>
#include <sgfx/nodes/volume/VolumeNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <sgfx_glad/gl.h>

using namespace sgfx;
using namespace sgfx::test;

namespace {

int g_calls = 0;
std::vector<std::string> g_names;

void count(const char* name) {
    ++g_calls;
    g_names.emplace_back(name);
}

void GLAPIENTRY stubGetIntegerv(GLenum, GLint* v) {
    count("glGetIntegerv");
    if (v) *v = 0;
}
void GLAPIENTRY stubBindFramebuffer(GLenum, GLuint) {
    count("glBindFramebuffer");
}
void GLAPIENTRY stubCreateTextures(GLenum, GLsizei, GLuint*) {
    count("glCreateTextures");
}
void GLAPIENTRY stubCreateBuffers(GLsizei, GLuint*) {
    count("glCreateBuffers");
}
void GLAPIENTRY stubBindTextureUnit(GLuint, GLuint) {
    count("glBindTextureUnit");
}
void GLAPIENTRY stubUseProgram(GLuint) {
    count("glUseProgram");
}
void GLAPIENTRY stubDrawArrays(GLenum, GLint, GLsizei) {
    count("glDrawArrays");
}
void GLAPIENTRY stubNamedBufferData(GLuint, GLsizeiptr, const void*, GLenum) {
    count("glNamedBufferData");
}
void GLAPIENTRY stubCreateFramebuffers(GLsizei, GLuint*) {
    count("glCreateFramebuffers");
}
void GLAPIENTRY stubEnable(GLenum) {
    count("glEnable");
}

// Swaps the entry points for the stubs while alive.
class GlStubs {
public:
    GlStubs() {
        g_calls = 0;
        g_names.clear();
        swap();
    }
    ~GlStubs() { swap(); }

private:
    void swap() {
        std::swap(sgfx_glad_glGetIntegerv, getIntegerv_);
        std::swap(sgfx_glad_glBindFramebuffer, bindFramebuffer_);
        std::swap(sgfx_glad_glCreateTextures, createTextures_);
        std::swap(sgfx_glad_glCreateBuffers, createBuffers_);
        std::swap(sgfx_glad_glBindTextureUnit, bindTextureUnit_);
        std::swap(sgfx_glad_glUseProgram, useProgram_);
        std::swap(sgfx_glad_glDrawArrays, drawArrays_);
        std::swap(sgfx_glad_glNamedBufferData, namedBufferData_);
        std::swap(sgfx_glad_glCreateFramebuffers, createFramebuffers_);
        std::swap(sgfx_glad_glEnable, enable_);
    }
    PFNGLGETINTEGERVPROC getIntegerv_ = stubGetIntegerv;
    PFNGLBINDFRAMEBUFFERPROC bindFramebuffer_ = stubBindFramebuffer;
    PFNGLCREATETEXTURESPROC createTextures_ = stubCreateTextures;
    PFNGLCREATEBUFFERSPROC createBuffers_ = stubCreateBuffers;
    PFNGLBINDTEXTUREUNITPROC bindTextureUnit_ = stubBindTextureUnit;
    PFNGLUSEPROGRAMPROC useProgram_ = stubUseProgram;
    PFNGLDRAWARRAYSPROC drawArrays_ = stubDrawArrays;
    PFNGLNAMEDBUFFERDATAPROC namedBufferData_ = stubNamedBufferData;
    PFNGLCREATEFRAMEBUFFERSPROC createFramebuffers_ = stubCreateFramebuffers;
    PFNGLENABLEPROC enable_ = stubEnable;
};

std::shared_ptr<Node> quadAt(glm::vec3 at, float alpha) {
    auto t =
        Transform::create(glm::rotate(glm::translate(glm::mat4(1.0f), at), glm::radians(90.0f), {1, 0, 0}));
    auto q = shapes::quad(4, 4);
    auto m = Material::create();
    m->diffuse = glm::vec4(0.5f, 0.5f, 0.5f, alpha);
    q->getOrCreateStateSet().material.set(m);
    if (alpha < 1.0f) q->getOrCreateStateSet().blend.set(BlendMode::Alpha);
    t->addChild(q);
    return t;
}

// Every effect of the kit, each over something in view.
std::shared_ptr<Group> everyEffect() {
    auto root = Group::create();
    auto fog = FogNode::create(FogParameters::ground(), FogMode::ForwardSplit);
    auto ao = AmbientOcclusionNode::create();
    auto oit = TransparencyBin::create(TransparencyMode::WeightedBlended);
    auto tint = DebugTintNode::create({1, 0, 0, 0.2f});
    root->addChild(fog);
    fog->addChild(ao);
    ao->addChild(quadAt({0, 10, 0}, 1.0f));
    ao->addChild(oit);
    oit->addChild(quadAt({1, 8, 0}, 0.5f));
    ao->addChild(tint);
    tint->addChild(quadAt({-2, 12, 0}, 1.0f));
    auto smoke = ParticleSystemNode::smoke(1.0f, 200);
    ParticleSettings soft = smoke->settings();
    soft.softness = 0.5f;
    smoke->setSettings(soft);
    fog->addChild(smoke);
    fog->addChild(ParticleSystemNode::rain({10.0f, 10.0f}, 500));
    fog->addChild(VolumeNode::create({}, VolumeGrid::sphere(8)));
    SkyParameters sky;
    sky.lookupTable = true;
    root->addChild(SkyNode::create(sky));
    return root;
}

// The setup of every pass the effects declared, against a blackboard that has the renderer's
// resources, as the renderer runs it.
void declareAll(const FrameSetup& setup) {
    FrameGraph g;
    const TextureDesc colour{format::Srgb8Alpha8, SizeRule::draw()},
        depth{format::Depth32F, SizeRule::draw()};
    for (std::string_view name : {resources::DrawColour, resources::ViewColour, resources::SceneNormals,
                                  resources::SceneLinearDepth, resources::ScenePositions})
        g.blackboard.put(std::string(name), g.import(std::string(name), colour, 1));
    for (std::string_view name : {resources::DrawDepth, resources::ViewDepth, resources::SceneDepth})
        g.blackboard.put(std::string(name), g.import(std::string(name), depth, 2));
    for (const FrameSetup::DeclaredPass& p : setup.passes())
        g.addPass(
            p.name,
            [&](FrameGraph::Builder& b) {
                PassBuilder pb(b, g.blackboard, &setup.queue());
                if (p.setup) p.setup(pb);
            },
            p.execute);
    g.compile({64, 64}, {64, 64});
}

} // namespace

TEST(Phases, CullAndSetupMakeNoGlCallsAndChangeNoNode) {
    auto v = Viewer::createHeadless(64, 64);
    v->camera()->setPerspective(60.0f, 0.5f, 500.0f);
    v->camera()->setLookAt({0, 0, 1}, {0, 10, 1}, {0, 0, 1});
    v->setSceneData(Group::create());
    v->frame(); // a context with GL loaded; the nodes below have never been drawn
    auto scene = everyEffect();
    v->setSceneData(scene);
    const auto* fog = dynamic_cast<const FogNode*>(scene->child(0).get());
    ASSERT_NE(fog, nullptr);
    const FogParameters before = fog->parameters();

    // Nodes never drawn (their first cull), then again after a frame drew them.
    for (int round = 0; round < 2; ++round) {
        if (round == 1) v->frame();
        RenderQueue queue;
        FramePlan plan;
        std::size_t passes = 0;
        {
            GlStubs stubs;
            CullVisitor cull(*v->camera(), queue, &plan);
            cull.run(*v->camera());
            queue.sort();
            FrameSetup setup(ViewInfo{{64, 64}, {64, 64}, 1, 0, 0}, queue);
            for (const EffectNode* e : plan.effects)
                e->setupFrame(setup);
            for (const Drawable* d : plan.drawables)
                d->setupFrame(setup);
            declareAll(setup);
            passes = setup.passes().size();
        }
        std::string calls;
        for (const std::string& n : g_names)
            calls += " " + n;
        EXPECT_EQ(g_calls, 0) << "GL calls during cull and setup:" << calls;
        EXPECT_GE(passes, 6u) << "the effects declared their passes";
        EXPECT_GE(plan.effects.size(), 4u);
        EXPECT_GE(plan.drawables.size(), 4u);
    }
    EXPECT_EQ(fog->parameters().density, before.density);
    v->frame(); // and the viewer still draws after the stubs are gone
    expectNoGlErrors(*v);
}

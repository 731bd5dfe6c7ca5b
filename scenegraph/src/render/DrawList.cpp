// Drawing a list of render items (Renderer::drawItems): per item its program, its state, its
// material and its faces through the state cache, then the draw itself (alone, as part of an
// automatic instance batch, with its triangles sorted back to front, or by its Drawable).
// Full-screen draws (Renderer::drawFullscreen) too.
#include "render/GpuUpload.h"
#include "render/RendererImpl.h"
#include "render/TextureUnits.h"
#include "sgfx/Drawable.h"
#include "sgfx/Effect.h"
#include "sgfx/FrameSetup.h"
#include "sgfx/Geometry.h"
#include "sgfx/Material.h"
#include "sgfx/TriangleSort.h"

#include <sgfx_glad/gl.h>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace sgfx {

namespace {

// Variant bits that only matter for shading: G-buffer variants leave them out.
constexpr FeatureMask kLightingFeatures = FeatureBlend | FeatureBlendKindMask | FeatureSpecular |
                                          FeatureVertexLighting | FeatureLightCountMask | FeaturePointLights |
                                          FeatureUnlit | FeatureClearcoat | FeatureSpecularExt |
                                          FeatureLightAttenuation | FeatureLightList;

// Enum values outside their range (a cast from bad data) would index GL tables out of bounds.
void validateEnums(const ResolvedState& st, const RenderItem& item) {
    const Node& n = item.node();
    auto bad = [&](const char* what, int v) {
        throw std::invalid_argument("sgfx: state of '" +
                                    (n.name.empty() ? std::string("<unnamed>") : n.name) +
                                    "' has an invalid " + what + " value " + std::to_string(v));
    };
    if (st.blend.value && std::uint8_t(*st.blend.value) > std::uint8_t(BlendMode::Multiply))
        bad("BlendMode", int(*st.blend.value));
    if (st.cullFace.value && std::uint8_t(*st.cullFace.value) > std::uint8_t(CullFace::Front))
        bad("CullFace", int(*st.cullFace.value));
    if (st.depth.value && std::uint8_t(st.depth.value->func) > std::uint8_t(CompareFunc::Always))
        bad("CompareFunc", int(st.depth.value->func));
    if (item.geometry && std::uint8_t(item.geometry->mode) > std::uint8_t(PrimitiveMode::TriangleFan))
        bad("PrimitiveMode", int(item.geometry->mode));
}

// The maps of KHR_materials_clearcoat, _specular, _transmission and _volume, with their MaterialMap.
std::array<std::pair<const Texture*, MaterialMap>, 7> extensionMaps(const Material& m) {
    return {{{m.clearcoatTexture.get(), MaterialMap::Clearcoat},
             {m.clearcoatRoughnessTexture.get(), MaterialMap::ClearcoatRoughness},
             {m.clearcoatNormalTexture.get(), MaterialMap::ClearcoatNormal},
             {m.specularTexture.get(), MaterialMap::Specular},
             {m.specularColorTexture.get(), MaterialMap::SpecularColor},
             {m.transmissionTexture.get(), MaterialMap::Transmission},
             {m.thicknessTexture.get(), MaterialMap::Thickness}}};
}

} // namespace

/// One call of Renderer::drawItems: what the list last set (program, state, material, effect
/// set), so each item changes only what differs from the item before it.
class Renderer::DrawList {
public:
    DrawList(Renderer& renderer, gl::Program* overrideProgram, DrawMode drawMode)
        : r(renderer)
        , s(*renderer.impl_)
        , override(overrideProgram)
        , mode(drawMode)
        , depthOnly(drawMode == DrawMode::DepthOnly || drawMode == DrawMode::GBuffer)
        , program(overrideProgram) {}

    void draw(std::span<const RenderItem> items);

private:
    void begin(std::span<const RenderItem> items);
    void finish();
    /// Items at the front of `items` that one instanced draw can take (1: draw it alone).
    std::size_t batchLength(std::span<const RenderItem> items) const;
    void submitIfDue();
    /// The item's program, made current; true when the program changed (the cached state,
    /// material and effect set are then unknown).
    bool selectProgram(const RenderItem& item, std::uint32_t extra);
    bool selectDrawableProgram(const RenderItem& item);
    bool selectComposedProgram(const RenderItem& item, std::uint32_t extra);
    bool selectDepthProgram(const RenderItem& item, std::uint32_t extra);
    void applyEffects(const RenderItem& item);
    void applyItemState(const RenderItem& item);
    void applyMaterial(const RenderItem& item);
    void setMaterialUniforms(const Material& m, const RenderItem& item);
    void bindMaterialTextures(const Material& m);
    void applyFaces(const RenderItem& item);
    void drawDrawable(const RenderItem& item);
    void drawGeometry(const RenderItem& item, std::size_t run);
    void drawBatch(const gl::GeometryBuffers& b, std::size_t count);
    void drawSortedTriangles(const RenderItem& item, const gl::GeometryBuffers& b,
                             const TransparencyDetails& details);
    /// One draw of `b`; `mirrored`: the item's matrix mirrors (its instances' own signs flip it again).
    void issueDraw(const gl::GeometryBuffers& b, bool mirrored);

    Renderer& r;
    Impl& s;
    gl::Program* const override;
    const DrawMode mode;
    // Geometry-only passes: no effects, no blending, depth test and write for every item.
    const bool depthOnly;
    gl::Program* program;
    ProgramKey programKey = ProgramKey::none();
    const ResolvedState* state = nullptr;
    const Material* material = nullptr;
    std::uint32_t effectSet = ~0u;
    FeatureMask programExtra = 0; // FeatureBatched when the current program draws batches
    bool batchesBound = true;     // the batch matrices are bound at kBatchBinding
    std::size_t batchBase = 0;    // the next batch's first matrix
    bool posesBound = false;      // a posed mesh's buffers are bound (unbound by finish)
    std::vector<const ShaderSnippet*> snippets;
};

void Renderer::drawItems(std::span<const RenderItem> items, gl::Program* override, DrawMode mode) {
    if (std::uint8_t(mode) > std::uint8_t(DrawMode::GBuffer))
        throw std::invalid_argument("sgfx: Renderer::drawItems: invalid DrawMode " +
                                    std::to_string(int(mode)));
    DrawList(*this, override, mode).draw(items);
}

void Renderer::DrawList::draw(std::span<const RenderItem> items) {
    begin(items);
    for (std::size_t i = 0, run = 1; i < items.size(); i += run) {
        submitIfDue();
        const RenderItem& item = items[i];
        s.log.item = &item;
        // Repeated meshes: neighbours in the sorted list that differ only in their matrix are
        // drawn as one instanced batch (the trees and buildings of a simulator scene).
        run = batchLength(items.subspan(i));
        const FeatureMask extra = run > 1 ? FeatureMask(FeatureBatched) : 0u;
        if (selectProgram(item, extra)) {
            state = nullptr;
            material = nullptr;
            effectSet = ~0u;
        }
        applyEffects(item);
        applyItemState(item);
        applyMaterial(item);
        applyFaces(item);
        if (item.drawable)
            drawDrawable(item);
        else
            drawGeometry(item, run);
    }
    finish();
}

void Renderer::DrawList::begin(std::span<const RenderItem> items) {
    s.cache.setColourMask(mode != DrawMode::DepthOnly);
    if (depthOnly) {
        s.cache.setBlend(BlendMode::Off);
        s.cache.setDepth(DepthState{});
        s.firstResourceUnit = render::kFirstFrameResourceUnit; // no effect samplers: drawables bind from here
    }
    // The copy of the opaque scene transmissive materials sample, on its own unit
    // (TextureUnits.h), when the frame made one: for the main pass's items and for an effect's
    // pass that draws blended items with their material (OIT).
    if (!depthOnly && s.graph && s.graph->blackboard.has(resources::TransmissionColour))
        s.cache.bindTexture(render::kTransmissionUnit,
                            s.graph->texture(s.graph->blackboard.get(resources::TransmissionColour)));
    // The model matrices of every batch of this list, uploaded at once (one buffer write per
    // list: writing per batch, or changing vertex layouts per batch, stalls llvmpipe).
    s.batchScratch.clear();
    for (std::size_t i = 0, run = 1; i < items.size(); i += run)
        if ((run = batchLength(items.subspan(i))) > 1)
            for (const RenderItem& it : items.subspan(i, run))
                s.batchScratch.push_back(it.model);
    batchesBound = s.batchScratch.empty();
    if (!s.batchScratch.empty()) {
        if (!s.batchModels) s.batchModels = gl::createBuffer();
        glNamedBufferData(s.batchModels.get(), GLsizeiptr(s.batchScratch.size() * sizeof(glm::mat4)),
                          s.batchScratch.data(), GL_STREAM_DRAW);
    }
}

void Renderer::DrawList::finish() {
    glBindVertexArray(0);
    // Leave no buffer bound to the batch binding: Mesa leaks a buffer still bound to an indexed
    // storage binding when the context is destroyed (LeakSanitizer).
    if (!s.batchScratch.empty()) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBatchBinding, 0);
    if (posesBound)
        for (const unsigned binding : {kJointsBinding, kMorphBinding, kMorphWeightsBinding})
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, 0);
    s.cache.setColourMask(true);
    s.log.item = nullptr;
    s.log.program = nullptr;
}

std::size_t Renderer::DrawList::batchLength(std::span<const RenderItem> items) const {
    const RendererOptions& options = r.options_;
    const RenderItem& first = items.front();
    // Built-in materials only (a program of the user's does not read instance matrices); blended
    // items keep their one-by-one path (triangle sorting).
    if (!options.autoInstancing || first.drawable || first.program() || !first.geometry->instances.empty() ||
        (first.features & (FeatureBlend | FeaturePoseMask)))
        return 1;
    std::size_t n = 1;
    while (n < items.size()) {
        const RenderItem& it = items[n];
        if (it.geometry != first.geometry || it.state != first.state || it.effectSet != first.effectSet ||
            it.faces != first.faces || it.mirrored != first.mirrored || it.programKey != first.programKey ||
            it.features != first.features)
            break;
        ++n;
    }
    return n >= options.minInstanceBatch ? n : 1;
}

void Renderer::DrawList::submitIfDue() {
    const std::uint64_t every = s.submitEvery;
    if (every && r.stats_.triangles - s.submittedTriangles >= every) {
        glFlush(); // llvmpipe's threads rasterise what is binned while this thread goes on
        s.submittedTriangles = r.stats_.triangles;
        ++r.stats_.submissions;
    }
}

bool Renderer::DrawList::selectProgram(const RenderItem& item, std::uint32_t extra) {
    bool programChanged = false;
    if (item.drawable)
        programChanged = selectDrawableProgram(item);
    else if (!override && (item.programKey != programKey || extra != programExtra))
        programChanged = selectComposedProgram(item, extra);
    else if (depthOnly && override)
        programChanged = selectDepthProgram(item, extra);
    s.log.program = program;
    if (s.cache.useProgram(program->get())) {
        ++r.stats_.programChanges;
        programChanged = true;
    }
    return programChanged;
}

// A Drawable's own base shader: composed with the effects in the main pass; in depth and G-buffer
// passes its plain or G-buffer variant.
bool Renderer::DrawList::selectDrawableProgram(const RenderItem& item) {
    const ProgramKey key =
        depthOnly ? item.programKey.with(ProgramKey::Mode, std::uint64_t(mode)) : item.programKey;
    if (key == programKey) return false;
    snippets.clear();
    if (!depthOnly)
        for (const EffectNode* e : r.current_->effectSets[item.effectSet].effects)
            snippets.push_back(&e->snippet());
    const FeatureMask features = mode == DrawMode::GBuffer
                                     ? (item.features & ~kLightingFeatures) | FeatureGBuffer
                                 : mode == DrawMode::DepthOnly ? item.features & ~FeatureBlend
                                                               : item.features | r.viewFeatures_;
    program = &r.composer_.program(item.drawable->baseShader(), snippets, features | FeatureWorldPosition);
    programKey = key;
    return true;
}

// A built-in material's variant (or a foreign program's wrap) composed with the item's effects.
bool Renderer::DrawList::selectComposedProgram(const RenderItem& item, std::uint32_t extra) {
    const EffectSet& set = r.current_->effectSets[item.effectSet];
    snippets.clear();
    for (const EffectNode* e : set.effects)
        snippets.push_back(&e->snippet());
    const FeatureMask features =
        // A foreign wrap uses the blend bits, and the pose bits to pose its vertex inputs.
        item.program() ? (snippets.empty() ? item.features & FeaturePoseMask : item.features)
                       : ShaderComposer::withWorldPosition(
                             item.features | r.viewFeatures_ | extra,
                             std::any_of(snippets.begin(), snippets.end(), [](const ShaderSnippet* sn) {
                                 // Declared functions too: the material calls the environment light's with
                                 // the view direction.
                                 return !sn->vertexCode.empty() || !sn->ambientCode.empty() ||
                                        !sn->colorCode.empty() || !sn->fragmentDecl.empty();
                             }));
    program = &r.composer_.program(item.program(), snippets, features);
    programKey = item.programKey;
    programExtra = extra;
    return true;
}

// Depth and G-buffer passes with an override program: alpha-masked and instanced built-in
// materials keep their cut-outs and instances in depth passes (their own variant, no effects, with
// colour writes off); everything else takes the override. G-buffer passes: every built-in
// material's G-buffer variant (normal maps, cut-outs).
bool Renderer::DrawList::selectDepthProgram(const RenderItem& item, std::uint32_t extra) {
    const bool builtin = !item.program();
    // Posed meshes too, foreign or not: the override programs read unposed positions.
    const bool own = (builtin && (mode == DrawMode::GBuffer || extra ||
                                  (item.features & (FeatureAlphaMask | FeatureInstanced)))) ||
                     (item.features & FeaturePoseMask);
    const FeatureMask features =
        mode == DrawMode::GBuffer
            ? (item.features & ~kLightingFeatures) | extra | FeatureGBuffer | FeatureWorldPosition
            : ShaderComposer::withWorldPosition((item.features & ~FeatureBlend) | extra | r.viewFeatures_,
                                                false);
    // The item's own built-in variant, or none() for the override program.
    const ProgramKey key =
        own ? ProgramKey::make(ProgramSource::Builtin, 0, 0, features, mode) : ProgramKey::none();
    if (key == programKey) return false;
    program = own ? &r.composer_.program(nullptr, {}, features) : override;
    programKey = key;
    return true;
}

void Renderer::DrawList::applyEffects(const RenderItem& item) {
    if (depthOnly || item.effectSet == effectSet) return;
    effectSet = item.effectSet;
    const DrawContext ctx{r.frame_, item};
    unsigned unit = render::kFirstFrameResourceUnit;
    s.firstResourceUnit = unit;
    for (const EffectNode* e : r.current_->effectSets[effectSet].effects) {
        e->applyUniforms(*program, ctx);
        // Frame resources the snippet samples, on units the renderer picks in snippet order.
        for (const SnippetSampler& sampler : e->snippet().samplers) {
            if (unit >= gl::StateCache::kUnits)
                throw std::runtime_error(
                    "sgfx: the effects above '" + item.node().name + "' sample more than " +
                    std::to_string(gl::StateCache::kUnits - render::kFirstFrameResourceUnit) +
                    " frame resources");
            const unsigned texture = sampler.nodeTexture ? e->texture(sampler.resource)
                                     : s.graph ? s.graph->texture(s.graph->blackboard.get(sampler.resource))
                                               : 0;
            // A comparison sampler reads through the renderer's sampler object; every other one
            // unbinds whatever sampler object the unit had (the texture's own state).
            s.cache.bindTexture(unit, texture, sampler.comparison ? s.comparisonSampler() : 0);
            program->set(sampler.uniform, int(unit++));
        }
    }
    s.firstResourceUnit = unit;
}

// The StateSet's blend and depth (main pass), user textures and uniforms.
void Renderer::DrawList::applyItemState(const RenderItem& item) {
    if (item.state == state) return;
    state = item.state;
    validateEnums(*state, item);
    if (mode == DrawMode::Main) {
        s.cache.setBlend(state->blendMode());
        DepthState d = state->depth.value.value_or(DepthState{});
        // Blended surfaces do not hide what is drawn after them, unless asked to.
        if (item.features & FeatureBlend)
            d.write = d.write && state->transparency.value && state->transparency.value->writeDepth;
        s.cache.setDepth(d);
    }
    unsigned unit = render::kFirstUserUnit;
    for (const auto& [name, tex] : state->textures) {
        if (!tex.value || !*tex.value || unit >= render::kFirstFrameResourceUnit) continue;
        s.cache.bindTexture(unit, render::textureFor(**tex.value));
        program->set(name, int(unit++));
    }
    for (const auto& [name, value] : state->uniforms)
        if (value.value) program->set(name, *value.value);
}

void Renderer::DrawList::applyMaterial(const RenderItem& item) {
    const Material* m = state->material.value ? state->material.value->get() : nullptr;
    if (m == material) return;
    material = m;
    if (m) {
        m->validate(); // NaN or negative colours would reach pixels
        setMaterialUniforms(*m, item);
        bindMaterialTextures(*m);
    }
    ++r.stats_.stateChanges;
}

void Renderer::DrawList::setMaterialUniforms(const Material& m, const RenderItem& item) {
    program->set("sgfx_matAmbient", m.ambient);
    program->set("sgfx_matDiffuse", m.diffuse);
    program->set("sgfx_matSpecular", m.specular);
    program->set("sgfx_matShininess", m.shininess);
    program->set("sgfx_matEmissive", m.emissive);
    program->set("sgfx_alphaCutoff", m.alphaCutoff.value_or(0.0f));
    // A blended item drawn as a caster (PassCommands::blendedCasters) cuts out what is too clear.
    if (mode == DrawMode::DepthOnly && (item.features & FeatureBlend) && s.blendedCutoff)
        program->set("sgfx_alphaCutoff", *s.blendedCutoff);
    if (m.model == ShadingModel::MetallicRoughness) {
        program->set("sgfx_matMetallicRoughness", glm::vec2(m.metallic, m.roughness));
        // The Gouraud option's specular lobe: the Blinn-Phong exponent of the same width.
        const float a = std::max(m.roughness * m.roughness, 0.03f);
        program->set("sgfx_matShininess", std::min(2.0f / (a * a) - 2.0f, 4096.0f));
        // KHR_materials_ior: the dielectric's reflectance at normal incidence.
        const float f = (m.ior - 1.0f) / (m.ior + 1.0f);
        program->set("sgfx_dielectricF0", f * f);
    }
    program->set("sgfx_normalScale", m.normalScale);
    program->set("sgfx_occlusionStrength", m.occlusionStrength);
    if (item.features & (FeatureClearcoat | FeatureSpecularExt | FeatureTransmission)) {
        // Which extension maps are read (bit = MaterialMap index): those the material has whose
        // coordinates the geometry has (as ShaderComposer::featuresFor); the others read as 1.
        int maps = 0;
        for (const auto& [tex, map] : extensionMaps(m))
            if (tex && item.geometry &&
                !(m.mapping(map).texCoord == 1 ? item.geometry->texcoords1 : item.geometry->texcoords)
                     .empty())
                maps |= 1 << int(map);
        program->set("sgfx_extensionMaps", maps);
    }
    if (item.features & FeatureClearcoat)
        program->set("sgfx_clearcoat", glm::vec3(m.clearcoat, m.clearcoatRoughness, m.clearcoatNormalScale));
    if (item.features & FeatureSpecularExt)
        program->set("sgfx_specularExt", glm::vec4(m.specularColorFactor, m.specularFactor));
    if (item.features & FeatureTransmission) {
        program->set("sgfx_transmission",
                     glm::vec4(m.transmission, m.ior, m.thickness,
                               std::isinf(m.attenuationDistance) ? 0.0f : m.attenuationDistance));
        program->set("sgfx_attenuationColor", m.attenuationColor);
    }
    if (item.features & FeatureUvTransform)
        for (std::size_t k = 0; k < kMaterialMapCount; ++k) {
            const std::string index = "[" + std::to_string(k) + "]";
            program->set("sgfx_uvTransform" + index, m.mappings[k].matrix());
            program->set("sgfx_uvSet" + index, m.mappings[k].texCoord);
        }
}

void Renderer::DrawList::bindMaterialTextures(const Material& m) {
    const std::pair<const std::shared_ptr<Texture>*, MaterialMap> maps[] = {
        {&m.baseColorTexture, MaterialMap::BaseColor},
        {&m.alphaTexture, MaterialMap::Alpha},
        {&m.normalTexture, MaterialMap::Normal},
        {&m.metallicRoughnessTexture, MaterialMap::MetallicRoughness},
        {&m.occlusionTexture, MaterialMap::Occlusion},
        {&m.emissiveTexture, MaterialMap::Emissive}};
    for (const auto& [tex, map] : maps)
        if (*tex) s.cache.bindTexture(render::materialUnit(map), render::textureFor(**tex));
    for (const auto& [tex, map] : extensionMaps(m))
        if (tex) s.cache.bindTexture(render::materialUnit(map), render::textureFor(*tex));
}

void Renderer::DrawList::applyFaces(const RenderItem& item) {
    switch (item.faces) {
    case RenderItem::Faces::Back:
        s.cache.setCull(CullFace::Front, item.mirrored);
        break;
    case RenderItem::Faces::Front:
        s.cache.setCull(CullFace::Back, item.mirrored);
        break;
    case RenderItem::Faces::AsState:
        s.cache.setCull(state->cullFace.value.value_or(CullFace::Back), item.mirrored);
        break;
    }
}

void Renderer::DrawList::drawDrawable(const RenderItem& item) {
    program->set("sgfx_model", item.model);
    s.nextResourceUnit = s.firstResourceUnit;
    item.drawable->draw(r, *program, item); // binds its own vertex arrays and units
    batchesBound = false;                   // and maybe buffers
    ++r.stats_.drawCalls;
    r.stats_.triangles += item.drawable->triangleCount();
}

void Renderer::DrawList::drawGeometry(const RenderItem& item, std::size_t run) {
    const Geometry& g = *item.geometry;
    gl::GeometryBuffers& b = render::buffersFor(g);
    if (run > 1) {
        if (!batchesBound) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBatchBinding, s.batchModels.get());
            batchesBound = true;
        }
        drawBatch(b, run);
        batchBase += run;
        r.stats_.triangles += g.triangleCount() * run;
        return;
    }
    program->set("sgfx_model", item.model);
    program->set("sgfx_normalMatrix", glm::mat3(glm::transpose(glm::inverse(item.model))));
    if (g.posed()) {
        render::bindPose(g, b);
        program->setInt4("sgfx_morphLayout", glm::make_vec4(b.morphLayout));
        posesBound = true;
    }
    glBindVertexArray(b.vao.get());
    const TransparencyDetails* details = state->transparency.value ? &*state->transparency.value : nullptr;
    if (details && details->sortTriangles && (item.features & FeatureBlend) && !depthOnly &&
        g.triangleCount() > 0 && g.instances.empty())
        drawSortedTriangles(item, b, *details);
    else
        issueDraw(b, item.mirrored);
    ++r.stats_.drawCalls;
    r.stats_.triangles += g.triangleCount();
}

void Renderer::DrawList::drawBatch(const gl::GeometryBuffers& b, std::size_t count) {
    program->set("sgfx_batchBase", int(batchBase));
    glBindVertexArray(b.vao.get());
    if (b.indexed)
        glDrawElementsInstanced(b.mode, GLsizei(b.count), GL_UNSIGNED_INT, nullptr, GLsizei(count));
    else
        glDrawArraysInstanced(b.mode, 0, GLsizei(b.count), GLsizei(count));
    ++r.stats_.drawCalls;
    ++r.stats_.instanceBatches;
}

// A self-overlapping mesh: its triangles back to front, from an index buffer of this view.
void Renderer::DrawList::drawSortedTriangles(const RenderItem& item, const gl::GeometryBuffers& b,
                                             const TransparencyDetails& details) {
    const Geometry& g = *item.geometry;
    Impl::SortedMesh& mesh = s.sortedMeshes[{&g, s.camera}];
    if (!mesh.sort || mesh.revision != g.revision() || mesh.owner.expired()) {
        mesh.owner = g.weak_from_this();
        mesh.view = s.camera->weak_from_this();
        mesh.viewTracked = !mesh.view.expired();
        mesh.revision = g.revision();
        mesh.sort = std::make_unique<TriangleDepthSort>(g);
        mesh.indices = gl::createBuffer();
        glNamedBufferData(mesh.indices.get(), GLsizeiptr(mesh.sort->indices().size_bytes()), nullptr,
                          GL_STREAM_DRAW);
    }
    mesh.lastUse = s.frames;
    if (mesh.sort->update(r.frame_.view * item.model, details.resortAngle)) {
        glNamedBufferSubData(mesh.indices.get(), 0, GLsizeiptr(mesh.sort->indices().size_bytes()),
                             mesh.sort->indices().data());
        ++r.stats_.triangleSorts;
    }
    glVertexArrayElementBuffer(b.vao.get(), mesh.indices.get());
    glDrawElements(GL_TRIANGLES, GLsizei(mesh.sort->indices().size()), GL_UNSIGNED_INT, nullptr);
    glVertexArrayElementBuffer(b.vao.get(), b.indexed ? b.indices.get() : 0);
}

void Renderer::DrawList::issueDraw(const gl::GeometryBuffers& b, bool mirrored) {
    if (b.instances) {
        // Instances whose own matrix mirrors come last and flip the winding once more.
        struct Range {
            std::uint32_t first, count;
            bool flip;
        };
        const std::uint32_t plain = b.instances - b.mirroredInstances;
        const Range ranges[2] = {{0u, plain, false}, {plain, b.mirroredInstances, true}};
        for (const Range& range : ranges) {
            if (range.count == 0) continue;
            s.cache.setFrontFace(mirrored != range.flip);
            if (b.indexed)
                glDrawElementsInstancedBaseInstance(b.mode, GLsizei(b.count), GL_UNSIGNED_INT, nullptr,
                                                    GLsizei(range.count), range.first);
            else
                glDrawArraysInstancedBaseInstance(b.mode, 0, GLsizei(b.count), GLsizei(range.count),
                                                  range.first);
        }
    } else if (b.indexed) {
        glDrawElements(b.mode, GLsizei(b.count), GL_UNSIGNED_INT, nullptr);
    } else {
        glDrawArrays(b.mode, 0, GLsizei(b.count));
    }
}

void Renderer::drawFullscreen(gl::Program& program, const DepthState& depth) {
    Impl& s = *impl_;
    s.cache.setDepth(depth);
    s.cache.setCull(CullFace::None);
    if (s.cache.useProgram(program.get())) ++stats_.programChanges;
    glBindVertexArray(s.emptyVao.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    ++stats_.drawCalls;
}

unsigned Renderer::frameResourceTexture(std::string_view resource) const {
    const Impl& s = *impl_;
    if (!s.graph || !s.graph->blackboard.has(resource)) return 0;
    // 0 when not alive in this pass: a depth pre-pass that draws the item before it is made.
    return s.graph->texture(s.graph->blackboard.get(resource));
}

bool Renderer::bindFrameResource(gl::Program& program, std::string_view uniform, std::string_view resource) {
    Impl& s = *impl_;
    const unsigned texture = frameResourceTexture(resource);
    if (!texture) return false;
    if (s.nextResourceUnit >= gl::StateCache::kUnits)
        throw std::runtime_error("sgfx: bindFrameResource: no texture unit left for '" +
                                 std::string(resource) + "'");
    s.cache.bindTexture(s.nextResourceUnit, texture);
    program.set(uniform, int(s.nextResourceUnit++));
    return true;
}

bool Renderer::beginOffscreen(std::initializer_list<std::string_view> colourResources) {
    Impl& s = *impl_;
    std::vector<std::pair<unsigned, unsigned>> attachments;
    glm::ivec2 size{0};
    unsigned point = GL_COLOR_ATTACHMENT0;
    for (const std::string_view resource : colourResources) {
        const unsigned texture = frameResourceTexture(resource);
        if (!texture) return false;
        attachments.emplace_back(point++, texture);
        const ResolvedDesc& d = s.graph->resolved(s.graph->blackboard.get(resource));
        size = {d.width, d.height};
    }
    if (attachments.empty())
        throw std::logic_error("sgfx: Renderer::beginOffscreen: no frame resources to draw into");
    s.cache.beginOffscreen(s.pool.framebuffer(attachments, s.log.stage), size);
    return true;
}

} // namespace sgfx

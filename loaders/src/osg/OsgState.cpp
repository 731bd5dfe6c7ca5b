// osg::StateSet → sgfx StateSet (pipeline state, uniforms, programs) plus the fixed-function
// state each Geometry's material is made from (FixedState); textures and images.
#include "OsgConvert.h"

#include <osg/AlphaFunc>
#include <osg/BlendFunc>
#include <osg/CullFace>
#include <osg/Depth>
#include <osg/Image>
#include <osg/LightModel>
#include <osg/PolygonMode>
#include <osg/ShadeModel>
#include <osg/TexEnv>
#include <osg/TexGen>
#include <osg/Texture2D>
#include <osg/TextureCubeMap>
#include <osg/Uniform>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>

namespace sgfx::osgbridge {

namespace {

/// OSG's OVERRIDE and PROTECTED bits → sgfx's StateFlags.
std::uint8_t flagsOf(osg::StateAttribute::GLModeValue v) {
    return std::uint8_t(((v & osg::StateAttribute::OVERRIDE) ? Override : 0) |
                        ((v & osg::StateAttribute::PROTECTED) ? Protected : 0));
}

/// The image's texels as an sgfx Image, rows in OSG's order (row 0 at t = 0), so the file's
/// texture coordinates sample what OSG samples. Null (with a warning) for what cannot be read.
std::shared_ptr<Image> convertImage(Context& cx, const osg::Image& in) {
    if (in.s() <= 0 || in.t() <= 0 || !in.data()) return nullptr;
    if (in.isCompressed()) {
        cx.warn("compressed osg::Image (" + in.getFileName() + "): texture not converted");
        return nullptr;
    }
    const GLenum f = in.getPixelFormat();
    const int channels = (f == GL_LUMINANCE || f == GL_ALPHA || f == GL_RED) ? 1
                         : (f == GL_LUMINANCE_ALPHA || f == GL_RG)           ? 2
                         : (f == GL_RGB || f == GL_BGR)                      ? 3
                                                                             : 4;
    cx.charge(std::size_t(in.s()) * std::size_t(in.t()) * 4, "osg::Image");
    auto image = Image::create(in.s(), in.t(), channels == 2 ? 4 : channels);
    for (int y = 0; y < in.t(); ++y)
        for (int x = 0; x < in.s(); ++x) {
            const osg::Vec4 c = in.getColor(unsigned(x), unsigned(y)); // any data type, normalised
            std::uint8_t* p = image->pixel(x, y);
            const auto byte = [](float v) {
                return std::uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
            };
            if (channels == 1)
                p[0] = byte(f == GL_ALPHA ? c.a() : c.r());
            else if (channels == 2)
                p[0] = p[1] = p[2] = byte(c.r()), p[3] = byte(c.a());
            else {
                p[0] = byte(c.r()), p[1] = byte(c.g()), p[2] = byte(c.b());
                if (channels == 4) p[3] = byte(c.a());
            }
        }
    return image;
}

Wrap wrapOf(osg::Texture::WrapMode w) {
    switch (w) {
    case osg::Texture::REPEAT:
        return Wrap::Repeat;
    case osg::Texture::MIRROR:
        return Wrap::MirroredRepeat;
    default:
        return Wrap::ClampToEdge; // CLAMP, CLAMP_TO_EDGE, CLAMP_TO_BORDER
    }
}

Filter filterOf(osg::Texture::FilterMode f) {
    switch (f) {
    case osg::Texture::NEAREST:
        return Filter::Nearest;
    case osg::Texture::LINEAR:
        return Filter::Linear;
    default:
        return Filter::LinearMipmapLinear;
    }
}

/// A cube map's six faces resampled into one equirectangular panorama (sgfx textures are 2D): the
/// texel for direction d is the one OpenGL's cube-map lookup picks (OpenGL 2.1 table 3.21: the
/// major axis chooses the face, (sc/|ma| + 1)/2 and (tc/|ma| + 1)/2 the texel). Column u is the
/// azimuth atan2(y, x) from -π, row v the polar angle acos(z) from 0: osg_fixed_function's
/// panoramaUv() inverts it.
std::shared_ptr<Image> cubeToPanorama(Context& cx, const osg::TextureCubeMap& cube) {
    const osg::Image* faces[6];
    int n = 0;
    for (unsigned f = 0; f < 6; ++f) {
        faces[f] = cube.getImage(f);
        if (!faces[f] || faces[f]->s() <= 0 || faces[f]->isCompressed()) return nullptr;
        n = std::max(n, faces[f]->s());
    }
    n = std::min(n, 512);
    cx.charge(std::size_t(8) * n * n * 4, "osg::TextureCubeMap");
    auto pano = Image::create(4 * n, 2 * n, 4);
    for (int j = 0; j < pano->height; ++j)
        for (int i = 0; i < pano->width; ++i) {
            const double phi = ((i + 0.5) / pano->width - 0.5) * 2.0 * M_PI,
                         theta = (j + 0.5) / pano->height * M_PI;
            const glm::dvec3 d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                               std::cos(theta));
            const glm::dvec3 a = glm::abs(d);
            int face;
            double sc, tc, ma;
            if (a.x >= a.y && a.x >= a.z)
                face = d.x > 0 ? 0 : 1, sc = d.x > 0 ? -d.z : d.z, tc = -d.y, ma = a.x;
            else if (a.y >= a.z)
                face = d.y > 0 ? 2 : 3, sc = d.x, tc = d.y > 0 ? d.z : -d.z, ma = a.y;
            else
                face = d.z > 0 ? 4 : 5, sc = d.z > 0 ? d.x : -d.x, tc = -d.y, ma = a.z;
            const osg::Image& im = *faces[face];
            const auto clampTo = [](double v, int size) {
                return unsigned(std::clamp(int(v * size), 0, size - 1));
            };
            const osg::Vec4 c =
                im.getColor(clampTo((sc / ma + 1) / 2, im.s()), clampTo((tc / ma + 1) / 2, im.t()));
            std::uint8_t* p = pano->pixel(i, j);
            for (int k = 0; k < 4; ++k)
                p[k] = std::uint8_t(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
        }
    return pano;
}

std::shared_ptr<Texture> convertTexture(Context& cx, const osg::Texture& t) {
    if (auto it = cx.textures.find(&t); it != cx.textures.end()) return it->second;
    std::shared_ptr<Texture> out;
    if (const auto* t2 = dynamic_cast<const osg::Texture2D*>(&t); t2 && t2->getImage()) {
        if (auto image = convertImage(cx, *t2->getImage())) {
            out = Texture::create(std::move(image), true); // colour maps: display values
            out->wrapS = wrapOf(t.getWrap(osg::Texture::WRAP_S));
            out->wrapT = wrapOf(t.getWrap(osg::Texture::WRAP_T));
            out->minFilter = filterOf(t.getFilter(osg::Texture::MIN_FILTER));
            out->magFilter = t.getFilter(osg::Texture::MAG_FILTER) == osg::Texture::NEAREST ? Filter::Nearest
                                                                                            : Filter::Linear;
        }
    } else if (const auto* cube = dynamic_cast<const osg::TextureCubeMap*>(&t)) {
        if (auto pano = cubeToPanorama(cx, *cube)) {
            out = Texture::create(std::move(pano), true);
            out->minFilter = Filter::Linear; // no mip chain: the azimuth's seam would pick a tiny level
            out->wrapT = Wrap::ClampToEdge;
        } else {
            cx.warn("osg::TextureCubeMap without six readable images: not converted");
        }
    } else if (!dynamic_cast<const osg::Texture2D*>(&t)) {
        cx.warn(std::string(t.libraryName()) + "::" + t.className() + ": not converted");
    } else {
        cx.warn("osg::Texture2D without an image (not found on the database path or OSG_FILE_PATH)");
    }
    cx.textures[&t] = out;
    return out;
}

BlendMode blendOf(Context& cx, const osg::BlendFunc* b) {
    if (!b) return BlendMode::Alpha;
    const GLenum s = b->getSource(), d = b->getDestination();
    if (s == GL_SRC_ALPHA && d == GL_ONE_MINUS_SRC_ALPHA) return BlendMode::Alpha;
    if (s == GL_ONE && d == GL_ONE_MINUS_SRC_ALPHA) return BlendMode::Premultiplied;
    if ((s == GL_ONE || s == GL_SRC_ALPHA) && d == GL_ONE) return BlendMode::Additive;
    if ((s == GL_DST_COLOR && d == GL_ZERO) || (s == GL_ZERO && d == GL_SRC_COLOR))
        return BlendMode::Multiply;
    cx.warn("osg::BlendFunc (" + std::to_string(s) + ", " + std::to_string(d) + "): drawn as straight alpha");
    return BlendMode::Alpha;
}

void convertBlend(Context& cx, const osg::StateSet& s, StateSet& out) {
    const auto mode = s.getMode(GL_BLEND);
    const auto* func = dynamic_cast<const osg::BlendFunc*>(s.getAttribute(osg::StateAttribute::BLENDFUNC));
    if (mode & osg::StateAttribute::INHERIT || !(mode & osg::StateAttribute::ON)) {
        if (!(mode & osg::StateAttribute::INHERIT))
            out.blend.set(BlendMode::Off, flagsOf(mode));
        else if (func && s.getRenderingHint() == osg::StateSet::TRANSPARENT_BIN)
            out.blend.set(blendOf(cx, func));
    } else {
        out.blend.set(blendOf(cx, func), flagsOf(mode));
    }
    const bool transparentBin =
        s.getRenderingHint() == osg::StateSet::TRANSPARENT_BIN || s.getBinName() == "DepthSortedBin";
    if (transparentBin) out.renderBin.set(RenderBin::Transparent);
    if (s.getRenderBinMode() != osg::StateSet::INHERIT_RENDERBIN_DETAILS && transparentBin) {
        TransparencyDetails d;
        d.order = s.getBinNumber();
        out.transparency.set(d);
    } else if (s.getRenderBinMode() != osg::StateSet::INHERIT_RENDERBIN_DETAILS && s.getBinNumber() != 0 &&
               !transparentBin) {
        cx.warn("render bin number on an opaque bin: sgfx orders opaque items by state, not by bin");
    }
}

void convertRasterState(Context& cx, const osg::StateSet& s, StateSet& out, FixedState& state) {
    const auto cullMode = s.getMode(GL_CULL_FACE);
    if (!(cullMode & osg::StateAttribute::INHERIT)) {
        const auto* cf = dynamic_cast<const osg::CullFace*>(s.getAttribute(osg::StateAttribute::CULLFACE));
        const bool on = cullMode & osg::StateAttribute::ON;
        if (on && cf && cf->getMode() == osg::CullFace::FRONT_AND_BACK)
            cx.warn("osg::CullFace FRONT_AND_BACK (draws nothing in OpenGL): culled as BACK");
        out.cullFace.set(!on                                             ? CullFace::None
                         : (cf && cf->getMode() == osg::CullFace::FRONT) ? CullFace::Front
                                                                         : CullFace::Back,
                         flagsOf(cullMode));
    }
    if (const auto* d = dynamic_cast<const osg::Depth*>(s.getAttribute(osg::StateAttribute::DEPTH))) {
        DepthState ds;
        ds.write = d->getWriteMask();
        ds.func = CompareFunc(int(d->getFunction()) - GL_NEVER);
        out.depth.set(ds);
    }
    if (const auto dm = s.getMode(GL_DEPTH_TEST);
        !(dm & osg::StateAttribute::INHERIT) && !(dm & osg::StateAttribute::ON)) {
        DepthState ds = out.depth.value.value_or(DepthState{});
        ds.test = false;
        out.depth.set(ds, flagsOf(dm));
    }
    if (const auto* a = dynamic_cast<const osg::AlphaFunc*>(s.getAttribute(osg::StateAttribute::ALPHAFUNC))) {
        const auto m = a->getFunction();
        if (m == osg::AlphaFunc::GREATER || m == osg::AlphaFunc::GEQUAL)
            state.alphaCutoff = a->getReferenceValue();
        else if (m != osg::AlphaFunc::ALWAYS)
            cx.warn("osg::AlphaFunc other than GREATER/GEQUAL: not converted");
    }
    if (const auto am = s.getMode(GL_ALPHA_TEST);
        !(am & osg::StateAttribute::INHERIT) && !(am & osg::StateAttribute::ON))
        state.alphaCutoff.reset();
    if (const auto* lm =
            dynamic_cast<const osg::LightModel*>(s.getAttribute(osg::StateAttribute::LIGHTMODEL)))
        state.twoSided = lm->getTwoSided();
    if (const auto* sm =
            dynamic_cast<const osg::ShadeModel*>(s.getAttribute(osg::StateAttribute::SHADEMODEL)))
        state.flat = sm->getMode() == osg::ShadeModel::FLAT;
    if (const auto* pm =
            dynamic_cast<const osg::PolygonMode*>(s.getAttribute(osg::StateAttribute::POLYGONMODE))) {
        const auto m = pm->getMode(osg::PolygonMode::FRONT);
        state.polygonMode = m == osg::PolygonMode::LINE    ? GL_LINE
                            : m == osg::PolygonMode::POINT ? GL_POINT
                                                           : 0;
        if (pm->getMode(osg::PolygonMode::BACK) != m)
            cx.warn("osg::PolygonMode with different faces: the front face's mode used");
    }
}

void convertTextures(Context& cx, const osg::StateSet& s, FixedState& state) {
    for (unsigned unit = 0; unit < s.getTextureAttributeList().size(); ++unit) {
        const auto* t =
            dynamic_cast<const osg::Texture*>(s.getTextureAttribute(unit, osg::StateAttribute::TEXTURE));
        const auto mode2d = s.getTextureMode(unit, GL_TEXTURE_2D);
        if (t) {
            state.textures[int(unit)] = t;
            convertTexture(cx, *t);
            if (unit == 0) state.texture0 = t; // units above 0 reach programs through their samplers only
        } else if (unit == 0 && !(mode2d & osg::StateAttribute::INHERIT) &&
                   !(mode2d & osg::StateAttribute::ON)) {
            state.texture0 = nullptr;
        }
        if (unit != 0) continue;
        const auto* envAttr = s.getTextureAttribute(0, osg::StateAttribute::TEXENV);
        if (const auto* env = dynamic_cast<const osg::TexEnv*>(envAttr))
            state.texEnv = int(env->getMode());
        else if (envAttr)
            cx.warn(std::string(envAttr->libraryName()) + "::" + envAttr->className() +
                    ": drawn as MODULATE");
        if (const auto* gen =
                dynamic_cast<const osg::TexGen*>(s.getTextureAttribute(0, osg::StateAttribute::TEXGEN))) {
            const auto m = gen->getMode();
            if (m == osg::TexGen::SPHERE_MAP)
                state.texGen = int(m);
            else
                cx.warn("osg::TexGen other than SPHERE_MAP: not converted");
        }
    }
}

bool allFinite(int) {
    return true;
}
/// Every float of a value (a float, a vector or a matrix) is finite.
template <class V> bool allFinite(const V& v) {
    const auto* p = reinterpret_cast<const float*>(&v);
    for (std::size_t i = 0; i < sizeof(V) / sizeof(float); ++i)
        if (!std::isfinite(p[i])) return false;
    return true;
}

std::optional<UniformValue> uniformValue(const osg::Uniform& u) {
    switch (u.getType()) {
    case osg::Uniform::FLOAT: {
        float f;
        if (u.get(f)) return f;
        break;
    }
    case osg::Uniform::INT: {
        int i;
        if (u.get(i)) return i;
        break;
    }
    case osg::Uniform::BOOL: {
        bool b;
        if (u.get(b)) return int(b);
        break;
    }
    case osg::Uniform::FLOAT_VEC2: {
        osg::Vec2 v;
        if (u.get(v)) return glm::vec2(v.x(), v.y());
        break;
    }
    case osg::Uniform::FLOAT_VEC3: {
        osg::Vec3 v;
        if (u.get(v)) return glm::vec3(v.x(), v.y(), v.z());
        break;
    }
    case osg::Uniform::FLOAT_VEC4: {
        osg::Vec4 v;
        if (u.get(v)) return glm::vec4(v.x(), v.y(), v.z(), v.w());
        break;
    }
    case osg::Uniform::FLOAT_MAT4: {
        osg::Matrixf m;
        if (u.get(m)) return glm::make_mat4(m.ptr());
        break;
    }
    case osg::Uniform::FLOAT_MAT3: {
        osg::Matrix3 m;
        if (u.get(m)) return glm::make_mat3(m.ptr());
        break;
    }
    default:
        break;
    }
    return std::nullopt;
}

void convertUniforms(Context& cx, const osg::StateSet& s, StateSet& out, FixedState& state) {
    for (const auto& [name, entry] : s.getUniformList()) {
        const osg::Uniform* u = entry.first.get();
        if (!u) continue;
        const bool sampler =
            std::find(cx.samplerNames.begin(), cx.samplerNames.end(), name) != cx.samplerNames.end();
        int unit = 0;
        if (sampler ||
            (u->getType() >= osg::Uniform::SAMPLER_1D && u->getType() <= osg::Uniform::SAMPLER_2D_SHADOW)) {
            if (u->get(unit)) state.samplerUnits[name] = unit; // sgfx binds the unit's texture by this name
            continue;
        }
        auto v = uniformValue(*u);
        if (v && !std::visit([](const auto& x) { return allFinite(x); }, *v))
            cx.warn("osg::Uniform '" + name + "' with a non-finite value: not converted");
        else if (v)
            out.setUniform(name, *v, flagsOf(entry.second));
        else
            cx.warn("osg::Uniform '" + name + "' of type " + osg::Uniform::getTypename(u->getType()) +
                    ": not converted");
    }
}

} // namespace

/// Attributes the converter reads; any other gets one warning per class.
void warnUnknownAttributes(Context& cx, const osg::StateSet& s) {
    using A = osg::StateAttribute;
    static const A::Type known[] = {A::MATERIAL, A::BLENDFUNC,  A::ALPHAFUNC,  A::CULLFACE,
                                    A::DEPTH,    A::LIGHTMODEL, A::SHADEMODEL, A::POLYGONMODE,
                                    A::PROGRAM,  A::TEXTURE,    A::TEXENV,     A::TEXGEN};
    const auto check = [&](const A* a) {
        if (a && std::find(std::begin(known), std::end(known), a->getType()) == std::end(known))
            cx.warn(std::string(a->libraryName()) + "::" + a->className() +
                    " state attribute: not converted");
    };
    for (const auto& [key, value] : s.getAttributeList())
        check(value.first.get());
    for (const auto& unit : s.getTextureAttributeList())
        for (const auto& [key, value] : unit)
            check(value.first.get());
}

std::shared_ptr<StateSet> convertStateSet(Context& cx, const osg::StateSet& s, FixedState& state) {
    auto out = StateSet::create();
    warnUnknownAttributes(cx, s);
    if (const auto lm = s.getMode(GL_LIGHTING); !(lm & osg::StateAttribute::INHERIT))
        state.lighting = lm & osg::StateAttribute::ON;
    if (const auto* m = dynamic_cast<const osg::Material*>(s.getAttribute(osg::StateAttribute::MATERIAL)))
        state.material = m;
    convertBlend(cx, s, *out);
    convertRasterState(cx, s, *out, state);
    convertTextures(cx, s, state);
    convertUniforms(cx, s, *out, state);
    if (const auto* p = dynamic_cast<const osg::Program*>(s.getAttribute(osg::StateAttribute::PROGRAM))) {
        const auto it = cx.programs.find(p);
        if (it != cx.programs.end() && it->second) {
            state.program = p;
            out->program.set(it->second->program);
        }
    }
    return out;
}

bool usesVertexColors(const FixedState& state) {
    if (state.program) return true;
    if (state.texture0 && state.texEnv == GL_REPLACE) return false;
    if (!state.lighting || !state.material) return true;
    const auto m = state.material->getColorMode();
    return m == osg::Material::AMBIENT_AND_DIFFUSE || m == osg::Material::DIFFUSE;
}

namespace {

/// The built-in material for a fixed-function state (OpenGL 1.x lighting with osg::Material's
/// front face; colour mode AMBIENT_AND_DIFFUSE: the vertex colour is the ambient and diffuse).
std::shared_ptr<Material> materialFor(Context& cx, const FixedState& state,
                                      osg::Material::Face face = osg::Material::FRONT) {
    std::shared_ptr<Material> back;
    auto& m = face == osg::Material::FRONT ? cx.materials[state] : back;
    if (m) return m;
    m = Material::create();
    // TexEnv REPLACE: the texture is the colour, whatever the lighting (OpenGL 1.x table 3.22).
    const bool replace = state.texture0 && state.texEnv == GL_REPLACE;
    m->model = state.lighting && !replace ? ShadingModel::BlinnPhong : ShadingModel::Unlit;
    const bool colorDrives = usesVertexColors(state);
    if (const auto* om = state.material) {
        const auto F = face;
        m->ambient = glm::vec3(linearColor(om->getAmbient(F)));
        m->diffuse = linearColor(om->getDiffuse(F));
        m->specular = glm::vec3(linearColor(om->getSpecular(F)));
        m->emissive = glm::vec3(linearColor(om->getEmission(F)));
        const float shininess = om->getShininess(F);
        m->shininess = std::isfinite(shininess) ? std::clamp(shininess, 1.0f, 1024.0f) : 1.0f;
    } else {
        m->ambient = glm::vec3(0.2f);
    }
    if (colorDrives || !state.lighting || replace) {
        m->diffuse = glm::vec4(1.0f, 1.0f, 1.0f, state.material && state.lighting ? m->diffuse.a : 1.0f);
        if (!state.material || state.material->getColorMode() == osg::Material::AMBIENT_AND_DIFFUSE)
            m->ambient = glm::vec3(1.0f);
    }
    if (state.texture0) m->baseColorTexture = convertTexture(cx, *state.texture0);
    m->alphaCutoff = state.alphaCutoff;
    return m;
}

} // namespace

void applyFixedState(Context& cx, const FixedState& state, StateSet& out, const Geometry& geometry) {
    if (state.program) {
        const auto& compat = *cx.programs.at(state.program);
        if (compat.usesMaterial) { // gl_FrontMaterial & co. read uniforms made from the osg::Material
            const auto face = [&](osg::Material::Face f) {
                CompatMaterial m;
                if (const auto* om = state.material) {
                    m.ambient = linearColor(om->getAmbient(f)), m.diffuse = linearColor(om->getDiffuse(f));
                    m.specular = linearColor(om->getSpecular(f)),
                    m.emission = linearColor(om->getEmission(f));
                    m.shininess = om->getShininess(f);
                }
                return m;
            };
            for (auto& [name, value] :
                 compatMaterialUniforms(face(osg::Material::FRONT), face(osg::Material::BACK)))
                out.setUniform(name, value);
        }
        for (const auto& s : compat.samplers) {
            const auto unit = state.samplerUnits.count(s.name) ? state.samplerUnits.at(s.name) : 0;
            const auto it = state.textures.find(unit);
            if (it != state.textures.end())
                if (auto t = convertTexture(cx, *it->second)) out.setTexture(s.name, std::move(t));
        }
        return;
    }
    if (needsFixedFunctionProgram(state)) {
        if (isCube(state) && state.texGen != osg::TexGen::REFLECTION_MAP &&
            state.texGen != osg::TexGen::NORMAL_MAP)
            cx.warn(
                "osg::TextureCubeMap read with the geometry's own (s, t, r): sampled by reflection instead");
        auto& p = cx.fixedPrograms[state];
        if (!p) p = fixedFunctionProgram(state);
        out.program.set(p);
        const auto material = materialFor(cx, state);
        out.setUniform("osgff_ambient", material->ambient);
        out.setUniform("osgff_diffuse", material->diffuse);
        out.setUniform("osgff_specular", material->specular);
        out.setUniform("osgff_emission", material->emissive);
        out.setUniform("osgff_shininess", material->shininess);
        const auto back = materialFor(cx, state, osg::Material::BACK);
        out.setUniform("osgff_backAmbient", back->ambient);
        out.setUniform("osgff_backDiffuse", back->diffuse);
        out.setUniform("osgff_backSpecular", back->specular);
        out.setUniform("osgff_backEmission", back->emissive);
        out.setUniform("osgff_backShininess", back->shininess);
        out.setUniform("osgff_hasColors", int(!geometry.colors.empty()));
        if (state.texture0)
            if (auto t = convertTexture(cx, *state.texture0)) out.setTexture("osgff_texture0", std::move(t));
        return;
    }
    out.material.set(materialFor(cx, state));
}

} // namespace sgfx::osgbridge

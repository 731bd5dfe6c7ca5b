// osg nodes → sgfx nodes: groups, transforms, LOD, Switch, Sequence, Billboard, DOFTransform,
// AnimationPathCallback; the Geode's drawables through the geometry and state converters.
#include "OsgConvert.h"

#include <sgfx/Billboard.h>
#include <sgfx/Camera.h>
#include <sgfx/DOFTransform.h>
#include <sgfx/LOD.h>
#include <sgfx/PagedLOD.h>
#include <sgfx/Sequence.h>
#include <sgfx/Switch.h>
#include <sgfx/Visitors.h>

#include <osg/AnimationPath>
#include <osg/Billboard>
#include <osg/Geode>
#include <osg/LOD>
#include <osg/LightSource>
#include <osg/MatrixTransform>
#include <osg/PagedLOD>
#include <osg/PositionAttitudeTransform>
#include <osg/Sequence>
#include <osg/Switch>
#include <osgSim/DOFTransform>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cfloat>

namespace sgfx::osgbridge {

namespace {

glm::mat4 toGlm(const osg::Matrixd& m) {
    return glm::mat4(glm::make_mat4(m.ptr()));
}
glm::vec3 toGlm(const osg::Vec3d& v) {
    return {float(v.x()), float(v.y()), float(v.z())};
}

/// The drawables of a Geode (or a Billboard's one drawable), each with its own StateSet merged.
void addDrawable(Context& cx, Group& parent, const osg::Drawable& d, const FixedState& state) {
    const auto* g = d.asGeometry();
    if (!g) {
        cx.warn(std::string(d.libraryName()) + "::" + d.className() + ": not converted");
        return;
    }
    FixedState own = state;
    std::shared_ptr<StateSet> pipeline;
    if (d.getStateSet()) pipeline = convertStateSet(cx, *d.getStateSet(), own);
    const GeometryShape shape{usesVertexColors(own), own.flat, own.polygonMode};
    auto& made = cx.geometries[{g, shape.colors, shape.flat, shape.polygonMode}];
    if (made.empty()) made = convertGeometry(cx, *g, shape);
    for (const auto& geometry : made) {
        // A Geometry converted under two different states (shared by two Geodes) is wrapped, not
        // copied: the state goes on a Group above the shared arrays.
        auto holder = Group::create();
        holder->name = g->getName();
        auto s = pipeline ? std::make_shared<StateSet>(*pipeline) : StateSet::create();
        applyFixedState(cx, own, *s, *geometry);
        holder->setStateSet(std::move(s));
        holder->addChild(geometry);
        parent.addChild(std::move(holder));
    }
}

std::shared_ptr<Group> convertBillboard(Context& cx, const osg::Billboard& b, const FixedState& state) {
    auto group = Group::create();
    for (unsigned i = 0; i < b.getNumDrawables(); ++i) {
        auto place = Transform::create(glm::translate(glm::mat4(1.0f), toGlm(osg::Vec3d(b.getPosition(i)))));
        auto board =
            Billboard::create(b.getMode() == osg::Billboard::AXIAL_ROT ? Billboard::Mode::AxialRotation
                                                                       : Billboard::Mode::PointRotEye);
        const glm::vec3 axis = toGlm(osg::Vec3d(b.getAxis())), normal = toGlm(osg::Vec3d(b.getNormal()));
        const float la = glm::length(axis), ln = glm::length(normal);
        // A zero, non-finite or non-perpendicular pair (a corrupt file) would fail at every cull.
        if (std::isfinite(la) && std::isfinite(ln) && la > 0.0f && ln > 0.0f &&
            std::abs(glm::dot(axis / la, normal / ln)) < 1e-3f) {
            board->axis = axis / la;
            board->normal = normal / ln;
        } else {
            cx.warn("osg::Billboard axis and normal not perpendicular unit vectors: OSG's defaults used");
        }
        if (b.getMode() == osg::Billboard::POINT_ROT_WORLD)
            cx.warn("osg::Billboard POINT_ROT_WORLD: turned as POINT_ROT_EYE");
        addDrawable(cx, *board, *b.getDrawable(i), state);
        place->addChild(std::move(board));
        group->addChild(std::move(place));
    }
    return group;
}

std::shared_ptr<Group> convertLod(Context& cx, const osg::LOD& l) {
    std::shared_ptr<LOD> lod;
    if (const auto* paged = dynamic_cast<const osg::PagedLOD*>(&l)) {
        auto p = PagedLOD::create();
        // Child files resolve against the PagedLOD's database path, or the file's own folder;
        // they load through loadOsg on the pager's thread, with this load's options.
        const std::string db = paged->getDatabasePath();
        p->setDatabasePath(db.empty() ? cx.file.parent_path() : std::filesystem::path(db));
        p->setLoader([options = cx.options](const std::filesystem::path& f) -> NodePtr {
            OsgStats quiet; // warnings of a streamed tile are not the application's business per frame
            return loadOsg(f, options, &quiet);
        });
        lod = p;
    } else {
        lod = LOD::create();
    }
    if (l.getRangeMode() == osg::LOD::DISTANCE_FROM_EYE_POINT)
        lod->setRangeMode(LOD::RangeMode::DistanceFromEye);
    if (l.getCenterMode() != osg::LOD::USE_BOUNDING_SPHERE_CENTER && l.getRadius() > 0.0f)
        lod->setUserSphere(toGlm(osg::Vec3d(l.getCenter())), l.getRadius());
    (void)cx;
    return lod;
}

/// OSG's PositionAttitudeTransform: T(position) · R(attitude) · S(scale) · T(-pivot).
glm::mat4 patMatrix(const osg::PositionAttitudeTransform& p) {
    osg::Matrixd m;
    p.computeLocalToWorldMatrix(m, nullptr);
    return toGlm(m);
}

std::shared_ptr<DOFTransform> convertDof(Context& cx, const osgSim::DOFTransform& d) {
    auto dof = DOFTransform::create();
    // osgSim's matrix is Put · current · InversePut in OSG's row-vector order, i.e. InversePut ·
    // current · Put on column vectors: sgfx's frame (frame → parent) is OSG's inverse put matrix.
    dof->setFrame(toGlm(d.getInversePutMatrix()));
    using K = DOFTransform::Kind;
    const auto axis = [&](const char* name, K kind, float mn, float mx, float current) {
        if (!(mx > mn) && current == (kind >= K::ScaleX ? 1.0f : 0.0f)) return; // a fixed axis at rest
        dof->addAxis(name, kind, std::min(mn, current), std::max(mx, current), DOFTransform::Limit::Clamp,
                     current);
    };
    // osgSim keeps HPR as (heading, pitch, roll): heading about Z, pitch about X, roll about Y.
    axis("heading", K::RotateZ, d.getMinHPR()[0], d.getMaxHPR()[0], d.getCurrentHPR()[0]);
    axis("pitch", K::RotateX, d.getMinHPR()[1], d.getMaxHPR()[1], d.getCurrentHPR()[1]);
    axis("roll", K::RotateY, d.getMinHPR()[2], d.getMaxHPR()[2], d.getCurrentHPR()[2]);
    const char* tn[] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
        axis(tn[i], K(int(K::TranslateX) + i), d.getMinTranslate()[i], d.getMaxTranslate()[i],
             d.getCurrentTranslate()[i]);
        axis((std::string("scale_") + tn[i]).c_str(), K(int(K::ScaleX) + i), d.getMinScale()[i],
             d.getMaxScale()[i], d.getCurrentScale()[i]);
    }
    if (d.getAnimationOn())
        cx.warn(
            "osgSim::DOFTransform animation (AnimationOn): the axes are left for the application to drive");
    return dof;
}

/// AnimationPathCallback → an update callback that moves the transform the same way: OSG's
/// animation time ((now - first) - offset) · multiplier, OSG's own interpolation and loop modes.
void attachAnimationPath(Context& cx, const osg::AnimationPathCallback& cb, Node& target,
                         const osg::Node& source) {
    osg::ref_ptr<const osg::AnimationPath> path = cb.getAnimationPath();
    if (!path || path->empty()) return;
    // Every control point finite, so every interpolated matrix is (a NaN would throw per frame).
    for (const auto& [time, cp] : path->getTimeControlPointMap()) {
        const osg::Vec3d p = cp.getPosition(), sc = cp.getScale();
        const osg::Quat q = cp.getRotation();
        if (!std::isfinite(time) || !p.valid() || !sc.valid() || !q.asVec4().valid() || q.length2() == 0.0) {
            cx.warn("osg::AnimationPath with a non-finite or zero control point: not converted");
            return;
        }
    }
    if (!std::isfinite(cb.getTimeOffset()) || !std::isfinite(cb.getTimeMultiplier())) {
        cx.warn("osg::AnimationPathCallback with a non-finite time offset or multiplier: not converted");
        return;
    }
    auto* t = dynamic_cast<Transform*>(&target);
    if (!t) {
        cx.warn("osg::AnimationPathCallback on a node that is not a transform: not converted");
        return;
    }
    const bool pat = dynamic_cast<const osg::PositionAttitudeTransform*>(&source) != nullptr;
    const osg::Vec3d pivot = cb.getPivotPoint();
    const bool inverse = cb.getUseInverseMatrix();
    const double offset = cb.getTimeOffset(), multiplier = cb.getTimeMultiplier();
    auto first = std::make_shared<double>(DBL_MAX);
    t->updateCallback = [path, pivot, inverse, offset, multiplier, first, pat](Node& n, UpdateVisitor& uv) {
        if (*first == DBL_MAX) *first = uv.simulationTime;
        osg::AnimationPath::ControlPoint cp;
        if (!path->getInterpolatedControlPoint(((uv.simulationTime - *first) - offset) * multiplier, cp))
            return;
        osg::Matrixd m;
        if (pat) {
            // OSG sets the PAT's position, attitude, scale and pivot: T(p) R S T(-pivot).
            m = osg::Matrixd::translate(-pivot) * osg::Matrixd::scale(cp.getScale()) *
                osg::Matrixd::rotate(cp.getRotation()) * osg::Matrixd::translate(cp.getPosition());
        } else if (inverse) {
            cp.getInverse(m);
            m = m * osg::Matrixd::translate(-pivot);
        } else {
            cp.getMatrix(m);
            m = osg::Matrixd::translate(-pivot) * m;
        }
        static_cast<Transform&>(n).setMatrix(toGlm(m));
    };
}

/// osg::LightSource → sgfx lights: w = 0 a directional light shining from `position`, else a
/// point light there, or a spot when its cutoff is under 90°; the light's ambient becomes an
/// ambient light. Colours are OSG's display values, decoded to linear.
std::shared_ptr<Group> convertLightSource(Context& cx, const osg::LightSource& ls) {
    auto group = Group::create();
    const osg::Light* l = ls.getLight();
    if (!l) return group;
    if (ls.getReferenceFrame() == osg::LightSource::ABSOLUTE_RF)
        cx.warn("osg::LightSource ABSOLUTE_RF: placed in its parent's frame");
    const osg::Vec4 p = l->getPosition();
    auto light = Light::create(p.w() == 0.0f                ? LightType::Directional
                               : l->getSpotCutoff() < 90.0f ? LightType::Spot
                                                            : LightType::Point);
    light->name = ls.getName();
    light->color = glm::vec3(linearColor(l->getDiffuse()));
    if (!p.valid() || !l->getDirection().valid() || !std::isfinite(l->getSpotCutoff())) {
        cx.warn("osg::LightSource with a non-finite position, direction or cutoff: not converted");
        return group;
    }
    if (p.w() == 0.0f) {
        const glm::vec3 towards(p.x(), p.y(), p.z());
        light->direction = glm::length(towards) > 0.0f ? -glm::normalize(towards) : glm::vec3(0, 0, -1);
    } else {
        light->position = glm::vec3(p.x(), p.y(), p.z()) / p.w();
        const osg::Vec3 d = l->getDirection();
        if (d.length() > 0.0f) light->direction = glm::normalize(glm::vec3(d.x(), d.y(), d.z()));
        light->outerConeAngle = glm::radians(std::clamp(l->getSpotCutoff(), 0.1f, 89.9f));
        if (l->getLinearAttenuation() != 0.0f || l->getQuadraticAttenuation() != 0.0f)
            cx.warn("osg::Light attenuation: lit without falloff");
    }
    group->addChild(light);
    const glm::vec3 ambient(linearColor(l->getAmbient()));
    if (ambient != glm::vec3(0.0f)) {
        auto a = Light::create(LightType::Ambient);
        a->color = ambient;
        group->addChild(a);
    }
    return group;
}

std::shared_ptr<Group> makeGroupFor(Context& cx, const osg::Node& node, const FixedState& state) {
    if (const auto* b = dynamic_cast<const osg::Billboard*>(&node)) return convertBillboard(cx, *b, state);
    if (const auto* d = dynamic_cast<const osgSim::DOFTransform*>(&node)) return convertDof(cx, *d);
    if (const auto* m = dynamic_cast<const osg::MatrixTransform*>(&node))
        return Transform::create(toGlm(m->getMatrix()));
    if (const auto* p = dynamic_cast<const osg::PositionAttitudeTransform*>(&node))
        return Transform::create(patMatrix(*p));
    if (const auto* l = dynamic_cast<const osg::LOD*>(&node)) return convertLod(cx, *l);
    if (const auto* ls = dynamic_cast<const osg::LightSource*>(&node)) return convertLightSource(cx, *ls);
    const std::string cls = std::string(node.libraryName()) + "::" + node.className();
    if (const auto* sw = dynamic_cast<const osg::Switch*>(&node)) {
        auto out = Switch::create();
        out->setNewChildDefault(sw->getNewChildDefaultValue());
        return out;
    }
    if (dynamic_cast<const osg::Sequence*>(&node)) return Sequence::create(); // timing set with its children
    if (cls != "osg::Group" && cls != "osg::Geode") cx.warn(cls + ": converted as a plain group");
    return Group::create();
}

void convertCallbacks(Context& cx, const osg::Node& node, Node& out) {
    for (const osg::Callback* cb = node.getUpdateCallback(); cb; cb = cb->getNestedCallback()) {
        if (const auto* apc = dynamic_cast<const osg::AnimationPathCallback*>(cb))
            attachAnimationPath(cx, *apc, out, node);
        else if (std::string(cb->className()) != "NodeCallback" && std::string(cb->className()) != "Callback")
            cx.warn(std::string(cb->libraryName()) + "::" + cb->className() +
                    " update callback: not converted");
    }
}

/// osg::Sequence's timing, interval, duration and mode (OSG's names and meanings).
void copySequence(const osg::Sequence& in, Sequence& out) {
    osg::Sequence::LoopMode loop;
    int begin = 0, end = -1, repeats = -1;
    float speed = 1.0f;
    in.getInterval(loop, begin, end);
    in.getDuration(speed, repeats);
    out.setInterval(loop == osg::Sequence::SWING ? Sequence::LoopMode::Swing : Sequence::LoopMode::Loop,
                    begin, end);
    out.setDuration(speed, repeats);
    const auto m = in.getMode();
    out.setMode(m == osg::Sequence::START    ? Sequence::Mode::Start
                : m == osg::Sequence::PAUSE  ? Sequence::Mode::Pause
                : m == osg::Sequence::RESUME ? Sequence::Mode::Resume
                                             : Sequence::Mode::Stop);
}

/// A PagedLOD's ranges: children present in the file, and files loaded on demand.
void addPagedChildren(Context& cx, const osg::PagedLOD& in, PagedLOD& out, const FixedState& state) {
    for (unsigned i = 0; i < in.getNumRanges(); ++i) {
        const float mn = in.getMinRange(i), mx = in.getMaxRange(i);
        if (i < in.getNumChildren())
            out.addChild(convertNode(cx, *in.getChild(i), state), mn, mx);
        else if (i < in.getNumFileNames() && !in.getFileName(i).empty())
            out.addChild(std::filesystem::path(in.getFileName(i)), mn, mx);
    }
}

/// Switch, Sequence and LOD children keep their per-child data; others are added in order.
void addChildren(Context& cx, const osg::Group& in, Group& out, const FixedState& state) {
    const auto* paged = dynamic_cast<const osg::PagedLOD*>(&in);
    if (auto* p = dynamic_cast<PagedLOD*>(&out); p && paged) return addPagedChildren(cx, *paged, *p, state);
    const auto* lod = dynamic_cast<const osg::LOD*>(&in);
    const auto* sw = dynamic_cast<const osg::Switch*>(&in);
    const auto* seq = dynamic_cast<const osg::Sequence*>(&in);
    for (unsigned i = 0; i < in.getNumChildren(); ++i) {
        auto child = convertNode(cx, *in.getChild(i), state);
        if (auto* l = dynamic_cast<LOD*>(&out); l && lod && i < lod->getNumRanges())
            l->addChild(std::move(child), lod->getMinRange(i), lod->getMaxRange(i));
        else if (auto* s = dynamic_cast<Switch*>(&out); s && sw)
            s->addChild(std::move(child), sw->getValue(i));
        else if (auto* q = dynamic_cast<Sequence*>(&out); q && seq)
            q->addChild(std::move(child), std::max(seq->getTime(i), 0.0));
        else
            out.addChild(std::move(child));
    }
    if (auto* q = dynamic_cast<Sequence*>(&out); q && seq && in.getNumChildren() > 0) copySequence(*seq, *q);
}

} // namespace

NodePtr convertNode(Context& cx, const osg::Node& node, const FixedState& parent) {
    // A node shared by parents of different fixed-function state converts once per state.
    const auto key = std::make_pair(&node, parent);
    if (auto it = cx.nodes.find(key); it != cx.nodes.end()) return it->second;
    cx.path.push_back(node.getName().empty() ? node.className() : node.getName());
    FixedState state = parent;
    std::shared_ptr<StateSet> stateSet;
    if (node.getStateSet()) stateSet = convertStateSet(cx, *node.getStateSet(), state);

    auto out = makeGroupFor(cx, node, state);
    out->name = node.getName();
    out->nodeMask = node.getNodeMask();
    if (stateSet) out->setStateSet(std::move(stateSet));
    if (const auto* geode = node.asGeode(); geode && !dynamic_cast<const osg::Billboard*>(geode))
        for (unsigned i = 0; i < geode->getNumDrawables(); ++i)
            addDrawable(cx, *out, *geode->getDrawable(i), state);
    // A Geode's children are its drawables (a Group since OSG 3.4), converted above.
    if (const auto* group = node.asGroup(); group && !node.asGeode()) addChildren(cx, *group, *out, state);
    convertCallbacks(cx, node, *out);
    cx.path.pop_back();
    cx.nodes[key] = out;
    return out;
}

} // namespace sgfx::osgbridge

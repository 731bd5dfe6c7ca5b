// DOFTransform (named axes with limits in a local frame, osgSim's PRH order) and findNode, checked
// against matrices written out here with cos and sin; then the proving ground's vehicle, whose
// wheels roll with the distance and whose turret and gun slew towards a target.
#include <sgfx/DOFTransform.h>
#include <sgfx/FindNode.h>
#include <sgfx/Group.h>
#include <sgfx/Shapes.h>
#include <sgfx/Visitors.h>

#include <gtest/gtest.h>

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

#ifdef SGFX_TEST_POLYGON_SCENE
#include "PolygonScene.h"
#include "VehicleDrive.h"
#endif

namespace {

using sgfx::DOFTransform;
using Kind = DOFTransform::Kind;
using Limit = DOFTransform::Limit;

constexpr double kPi = glm::pi<double>();

// Column-major (glm): m[column][row]. Right-handed rotations about the axes.
glm::dmat4 rotX(double a) {
    const double c = std::cos(a), s = std::sin(a);
    return glm::dmat4({1, 0, 0, 0}, {0, c, s, 0}, {0, -s, c, 0}, {0, 0, 0, 1});
}
glm::dmat4 rotY(double a) {
    const double c = std::cos(a), s = std::sin(a);
    return glm::dmat4({c, 0, -s, 0}, {0, 1, 0, 0}, {s, 0, c, 0}, {0, 0, 0, 1});
}
glm::dmat4 rotZ(double a) {
    const double c = std::cos(a), s = std::sin(a);
    return glm::dmat4({c, s, 0, 0}, {-s, c, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1});
}
glm::dmat4 shift(glm::dvec3 t) {
    glm::dmat4 m(1.0);
    m[3] = glm::dvec4(t, 1.0);
    return m;
}
glm::dmat4 scaling(glm::dvec3 s) {
    return glm::dmat4({s.x, 0, 0, 0}, {0, s.y, 0, 0}, {0, 0, s.z, 0}, {0, 0, 0, 1});
}

void expectMatrix(const glm::mat4& got, const glm::dmat4& want, double tol = 1e-5) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            EXPECT_NEAR(got[c][r], want[c][r], tol) << "column " << c << " row " << r;
}

// The angle a - b wrapped into [-pi, pi).
double angleBetween(double a, double b) {
    const double d = a - b;
    return d - 2.0 * kPi * std::floor((d + kPi) / (2.0 * kPi));
}

std::string thrownBy(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "(nothing thrown)";
}

} // namespace

TEST(DOFTransform, EachAxisKindMatchesItsClosedForm) {
    struct Case {
        Kind kind;
        double value;
        glm::dmat4 want;
    };
    const double a = 0.7, t = 1.5, s = 2.0;
    const Case cases[] = {
        {Kind::RotateX, a, rotX(a)},
        {Kind::RotateY, a, rotY(a)},
        {Kind::RotateZ, a, rotZ(a)},
        {Kind::TranslateX, t, shift({t, 0, 0})},
        {Kind::TranslateY, t, shift({0, t, 0})},
        {Kind::TranslateZ, t, shift({0, 0, t})},
        {Kind::ScaleX, s, scaling({s, 1, 1})},
        {Kind::ScaleY, s, scaling({1, s, 1})},
        {Kind::ScaleZ, s, scaling({1, 1, s})},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(int(c.kind));
        auto dof = DOFTransform::create();
        dof->addAxis("q", c.kind, -3.0, 3.0);
        expectMatrix(dof->matrix(), glm::dmat4(1.0)); // at rest: 0, or 1 for a scale
        EXPECT_EQ(dof->set("q", c.value), c.value);
        EXPECT_EQ(dof->value("q"), c.value);
        expectMatrix(dof->matrix(), c.want);
    }
    // A right-handed quarter turn about Z takes +X to +Y (sgfx is Z up: a heading).
    auto dof = DOFTransform::create();
    dof->addAxis("heading", Kind::RotateZ, -kPi, kPi, Limit::Clamp, kPi / 2);
    const glm::vec4 x = dof->matrix() * glm::vec4(1, 0, 0, 1);
    EXPECT_NEAR(x.x, 0.0f, 1e-6f);
    EXPECT_NEAR(x.y, 1.0f, 1e-6f);
}

TEST(DOFTransform, CombinedAxesFollowOsgSimsPrhOrder) {
    auto dof = DOFTransform::create();
    // Added in another order than the product's: the order is the kinds', not the list's.
    dof->addAxis("sx", Kind::ScaleX, 0.1, 4.0, Limit::Clamp, 2.0);
    dof->addAxis("heading", Kind::RotateZ, -kPi, kPi, Limit::Clamp, 0.5);
    dof->addAxis("ty", Kind::TranslateY, -5, 5, Limit::Clamp, -1.0);
    dof->addAxis("roll", Kind::RotateY, -kPi, kPi, Limit::Clamp, -0.3);
    dof->addAxis("pitch", Kind::RotateX, -kPi, kPi, Limit::Clamp, 0.9);
    dof->addAxis("tz", Kind::TranslateZ, -5, 5, Limit::Clamp, 2.0);
    dof->addAxis("sz", Kind::ScaleZ, 0.1, 4.0, Limit::Clamp, 0.5);
    ASSERT_EQ(dof->axes().size(), 7u);
    // Scale first, then heading (Z), roll (Y), pitch (X), then the translation.
    const glm::dmat4 want = shift({0, -1, 2}) * rotX(0.9) * rotY(-0.3) * rotZ(0.5) * scaling({2, 1, 0.5});
    expectMatrix(dof->matrix(), want);
    // The order matters: heading outermost would give another matrix.
    const glm::dmat4 other = shift({0, -1, 2}) * rotZ(0.5) * rotX(0.9) * rotY(-0.3) * scaling({2, 1, 0.5});
    double apart = 0.0;
    for (int c = 0; c < 3; ++c)
        apart = std::max(apart, glm::length(want[c] - other[c]));
    EXPECT_GT(apart, 0.1);
}

TEST(DOFTransform, TheFrameConjugatesTheMotionAndTheBaseComesFirst) {
    auto dof = DOFTransform::create();
    const glm::dvec3 origin(3, -2, 1);
    // A frame whose Z axis is the parent's (1, 1, 0) / sqrt 2.
    const double h = std::sqrt(0.5);
    const glm::dmat3 axes(glm::dvec3(0, 0, 1), glm::dvec3(h, -h, 0), glm::dvec3(h, h, 0));
    dof->setFrame(glm::vec3(origin), glm::mat3(axes));
    dof->addAxis("spin", Kind::RotateZ, 0.0, 2.0 * kPi, Limit::Wrap);
    const double theta = 1.1;
    dof->set("spin", theta);
    const glm::dmat4 m(dof->matrix());
    // A point on the frame's Z axis stays where it is.
    for (double t : {-2.0, 0.0, 3.5}) {
        const glm::dvec3 p = origin + t * axes[2];
        const glm::dvec3 q(m * glm::dvec4(p, 1.0));
        EXPECT_NEAR(glm::length(q - p), 0.0, 1e-5) << "t " << t;
    }
    // Any other turns about that axis: origin + R Rz R^T (p - origin).
    const glm::dvec3 p(4, 0, 2);
    const glm::dvec3 want = origin + axes * glm::dmat3(rotZ(theta)) * glm::transpose(axes) * (p - origin);
    EXPECT_NEAR(glm::length(glm::dvec3(m * glm::dvec4(p, 1.0)) - want), 0.0, 1e-5);
    // put · motion · put⁻¹ · base: the children rest at the base, the motion acts about the frame.
    glm::dmat4 put(axes);
    put[3] = glm::dvec4(origin, 1.0);
    const glm::dmat4 base = shift({0.5, 0.25, -1}) * rotX(0.4);
    dof->setBase(glm::mat4(base));
    expectMatrix(dof->matrix(), put * rotZ(theta) * glm::inverse(put) * base);
    EXPECT_THROW(dof->setFrame(glm::mat4(0.0f)), std::invalid_argument);
    EXPECT_THROW(dof->setBase(glm::mat4(std::numeric_limits<float>::infinity())), std::invalid_argument);
}

TEST(DOFTransform, ClampAndWrapLimits) {
    auto dof = DOFTransform::create();
    dof->addAxis("gear", Kind::TranslateZ, -1.0, 0.0);
    dof->addAxis("rotor", Kind::RotateZ, 0.0, 2.0 * kPi, Limit::Wrap);
    dof->addAxis("yaw", Kind::RotateX, -kPi, kPi, Limit::Wrap);
    EXPECT_EQ(dof->set("gear", -3.0), -1.0);
    EXPECT_EQ(dof->value("gear"), -1.0);
    EXPECT_EQ(dof->set("gear", 0.5), 0.0);
    EXPECT_EQ(dof->set("gear", -0.25), -0.25);
    EXPECT_NEAR(dof->set("rotor", 7.0), 7.0 - 2.0 * kPi, 1e-12);
    EXPECT_NEAR(dof->set("rotor", -0.5), 2.0 * kPi - 0.5, 1e-12);
    EXPECT_NEAR(dof->set("rotor", 1000.0 * kPi + 0.25), 0.25, 1e-9);
    EXPECT_EQ(dof->set("yaw", kPi), -kPi); // [min, max): max wraps to min
    EXPECT_NEAR(dof->set("yaw", 3.5), 3.5 - 2.0 * kPi, 1e-12);
    // The initial value is limited too.
    dof->addAxis("sx", Kind::ScaleX, 0.5, 2.0); // rest 1
    EXPECT_EQ(dof->value("sx"), 1.0);
    dof->addAxis("sy", Kind::ScaleY, 2.0, 3.0, Limit::Clamp, 10.0);
    EXPECT_EQ(dof->value("sy"), 3.0);
    expectMatrix(dof->matrix(),
                 shift({0, 0, -0.25}) * rotX(3.5 - 2.0 * kPi) * rotZ(0.25) * scaling({1, 3, 1}));
}

TEST(DOFTransform, ErrorsNameTheNodeAndAxisAndKeepTheOldState) {
    auto dof = DOFTransform::create();
    dof->name = "aileron";
    dof->addAxis("deflection", Kind::RotateX, -0.4, 0.4, Limit::Clamp, 0.1);
    dof->addAxis("droop", Kind::TranslateZ, -0.1, 0.0);
    const glm::mat4 before = dof->matrix();
    const auto unchanged = [&] {
        EXPECT_EQ(dof->value("deflection"), 0.1);
        EXPECT_EQ(dof->axes().size(), 2u);
        expectMatrix(dof->matrix(), glm::dmat4(before), 0.0);
    };
    std::string m = thrownBy([&] { dof->set("deflectoin", 0.2); });
    EXPECT_NE(m.find("'aileron'"), std::string::npos) << m;
    EXPECT_NE(m.find("'deflectoin'"), std::string::npos) << m;
    EXPECT_NE(m.find("'deflection', 'droop'"), std::string::npos) << m;
    EXPECT_NE(thrownBy([&] { (void)dof->value("x"); }).find("'deflection', 'droop'"), std::string::npos);
    for (double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
        m = thrownBy([&] { dof->set("deflection", bad); });
        EXPECT_NE(m.find("'aileron' axis 'deflection'"), std::string::npos) << m;
        unchanged();
    }
    m = thrownBy([&] { dof->addAxis("deflection", Kind::RotateY, 0, 1); });
    EXPECT_NE(m.find("'aileron' axis 'deflection'"), std::string::npos) << m;
    EXPECT_NE(m.find("taken"), std::string::npos) << m;
    m = thrownBy([&] { dof->addAxis("flap", Kind::RotateY, 1, 0); });
    EXPECT_NE(m.find("'aileron' axis 'flap': min > max"), std::string::npos) << m;
    m = thrownBy([&] { dof->addAxis("twist", Kind::RotateX, 0, 1); });
    EXPECT_NE(m.find("already has an axis of that kind ('deflection')"), std::string::npos) << m;
    EXPECT_NE(thrownBy([&] { dof->addAxis("", Kind::RotateY, 0, 1); }).find("'aileron'"), std::string::npos);
    EXPECT_NE(thrownBy([&] {
                  dof->addAxis("slide", Kind::TranslateX, 0, 1, Limit::Wrap);
              }).find("only rotations wrap"),
              std::string::npos);
    EXPECT_NE(thrownBy([&] { dof->addAxis("spin", Kind::RotateY, 1, 1, Limit::Wrap); }).find("min < max"),
              std::string::npos);
    EXPECT_NE(thrownBy([&] { dof->addAxis("nan", Kind::RotateY, std::nan(""), 1); }).find("finite"),
              std::string::npos);
    EXPECT_NE(thrownBy([&] {
                  dof->addAxis("nan", Kind::RotateY, 0, 1, Limit::Clamp, std::nan(""));
              }).find("finite"),
              std::string::npos);
    unchanged();
}

TEST(DOFTransform, SetMovesTheBoundsAbove) {
    auto root = sgfx::Group::create();
    auto dof = DOFTransform::create();
    dof->setBase(glm::mat4(shift({10, 0, 0})));
    dof->addAxis("lift", Kind::TranslateZ, 0.0, 10.0);
    dof->addChild(sgfx::shapes::box({1.0f, 1.0f, 1.0f}));
    root->addChild(dof);
    EXPECT_NEAR(glm::length(root->bound().center - glm::vec3(10, 0, 0)), 0.0f, 1e-4f);
    const auto changes = root->boundChanges();
    dof->set("lift", 5.0);
    EXPECT_GT(root->boundChanges(), changes);
    EXPECT_NEAR(glm::length(root->bound().center - glm::vec3(10, 0, 5)), 0.0f, 1e-4f);
    sgfx::ComputeBoundsVisitor cb;
    root->accept(cb);
    EXPECT_NEAR(cb.min.z, 4.5f, 1e-4f);
    EXPECT_NEAR(cb.max.z, 5.5f, 1e-4f);
}

TEST(FindNode, DepthFirstPreOrderByNameAndType) {
    auto root = sgfx::Group::create();
    root->name = "root";
    auto a = sgfx::Group::create();
    a->name = "a";
    auto plain = sgfx::Transform::create();
    plain->name = "x";
    auto dof = DOFTransform::create();
    dof->name = "x";
    auto shared = sgfx::Group::create();
    shared->name = "s";
    auto inner = sgfx::Group::create();
    inner->name = "x";
    shared->addChild(inner);
    auto hidden = sgfx::Group::create();
    hidden->name = "h";
    hidden->nodeMask = 0;
    // root -> a -> plain "x" -> shared "s" -> inner "x";  root -> dof "x" -> shared;  root -> hidden.
    root->addChild(a);
    a->addChild(plain);
    plain->addChild(shared);
    root->addChild(dof);
    dof->addChild(shared);
    root->addChild(hidden);

    EXPECT_EQ(sgfx::findNode(*root, "root"), root);
    EXPECT_EQ(sgfx::findNode(*root, "x"), plain);
    EXPECT_EQ(sgfx::findNode(*root, "h"), hidden); // every child, whatever its mask
    EXPECT_EQ(sgfx::findNode(*root, "nobody"), nullptr);
    EXPECT_EQ(sgfx::findNode(*a, "x"), plain);

    const auto xs = sgfx::findNodes(*root, "x");
    ASSERT_EQ(xs.size(), 3u); // pre-order; inner once though reached under plain and dof
    EXPECT_EQ(xs[0], plain);
    EXPECT_EQ(xs[1], inner);
    EXPECT_EQ(xs[2], dof);
    EXPECT_EQ(sgfx::findNodes(*root, "s").size(), 1u);
    EXPECT_TRUE(sgfx::findNodes(*root, "nobody").empty());

    EXPECT_EQ(sgfx::findNode<DOFTransform>(*root, "x"), dof);
    EXPECT_EQ(sgfx::findNode<sgfx::Transform>(*root, "x"), plain);
    EXPECT_EQ(sgfx::findNode<sgfx::Group>(*root, "x"), plain);
    EXPECT_EQ(sgfx::findNode<DOFTransform>(*root, "s"), nullptr);
    EXPECT_EQ(sgfx::findNode<DOFTransform>(*shared, "x"), nullptr);
}

#ifdef SGFX_TEST_POLYGON_SCENE

namespace {

// The proving ground driven by update traversals alone (no rendering), on the analytic ground.
struct DrivenScene {
    explicit DrivenScene(polygon::DriveOptions o = {}) {
        polygon::SceneOptions so;
        so.scale = 0.05f; // the geometry is not looked at
        scene = polygon::buildPolygonScene(so);
        const polygon::Terrain terrain(so.seed);
        o.ground = [terrain](double x, double y) {
            return std::optional<double>(terrain.height(float(x), float(y)));
        };
        options = o;
        state = polygon::driveVehicle(scene, polygon::provingGroundRoute(), o);
        turret = sgfx::findNode<DOFTransform>(*scene.root, polygon::kTurretNode);
        gun = sgfx::findNode<DOFTransform>(*scene.root, polygon::kGunNode);
    }
    void frame(double t) {
        sgfx::UpdateVisitor uv;
        uv.simulationTime = t;
        scene.root->accept(uv);
    }
    // The turret in the world (its children's frame: x along the gun at elevation 0).
    glm::dmat4 turretWorld() const {
        return glm::dmat4(scene.vehiclePose->matrix()) * glm::dmat4(turret->matrix());
    }
    polygon::PolygonScene scene;
    polygon::DriveOptions options;
    std::shared_ptr<const polygon::DriveState> state;
    std::shared_ptr<DOFTransform> turret, gun;
};

} // namespace

TEST(VehicleDof, AtRestTheVehicleStandsAsBefore) {
    const auto vehicle = polygon::buildVehicle();
    const auto turret = sgfx::findNode<DOFTransform>(*vehicle, polygon::kTurretNode);
    const auto gun = sgfx::findNode<DOFTransform>(*vehicle, polygon::kGunNode);
    ASSERT_TRUE(turret && gun);
    // The turret's and barrel's placements before they were DOFs.
    expectMatrix(turret->matrix(), shift({-0.4, 0, 1.84}) * rotZ(0.35));
    expectMatrix(gun->matrix(), shift({1.35, 0, 0.42}) * rotY(kPi / 2 - 0.04));
    const auto wheels = polygon::vehicleWheels();
    EXPECT_EQ(wheels.size(), 16u);
    for (const polygon::VehicleWheel& w : wheels) {
        const auto dof = sgfx::findNode<DOFTransform>(*vehicle, w.name);
        ASSERT_TRUE(dof) << w.name;
        EXPECT_EQ(dof->value("spin"), 0.0) << w.name;
        expectMatrix(dof->matrix(), shift(glm::dvec3(w.centre)) * rotX(-kPi / 2) * shift({0, 0, -0.125}));
    }
    EXPECT_EQ(sgfx::findNode<DOFTransform>(*vehicle, "vehicle.wheel.l1")->frame()[3].x, 2.2f); // front
}

TEST(VehicleDof, WheelsTurnByTheDistanceOverTheirRadius) {
    DrivenScene d;
    const auto wheels = polygon::vehicleWheels();
    for (int f = 0; f < 40; ++f) {
        d.frame(0.37 * f);
        ASSERT_NEAR(d.state->distance, d.options.speed * 0.37 * f, 1e-9);
        for (const polygon::VehicleWheel& w : wheels) {
            const auto dof = sgfx::findNode<DOFTransform>(*d.scene.root, w.name);
            const double spin = dof->value("spin");
            EXPECT_GE(spin, 0.0);
            EXPECT_LT(spin, 2.0 * kPi);
            EXPECT_NEAR(angleBetween(spin, d.state->distance / double(w.radius)), 0.0, 1e-9)
                << w.name << " frame " << f;
        }
    }
    // Rolling forward: a quarter turn takes the top of the rim to the front of the wheel.
    const auto& w = wheels.front();
    auto dof = sgfx::findNode<DOFTransform>(*d.scene.root, w.name);
    dof->set("spin", kPi / 2);
    const glm::dmat4 motion = glm::dmat4(dof->matrix()) * glm::inverse(glm::dmat4(dof->base()));
    const glm::dvec3 top = glm::dvec3(w.centre) + glm::dvec3(0, 0, w.radius);
    const glm::dvec3 moved(motion * glm::dvec4(top, 1.0));
    EXPECT_NEAR(moved.x - w.centre.x, w.radius, 1e-5);
    EXPECT_NEAR(moved.y - w.centre.y, 0.0, 1e-5);
    EXPECT_NEAR(moved.z - w.centre.z, 0.0, 1e-5);
}

TEST(VehicleDof, TheTurretAndGunSettleOnTheTarget) {
    DrivenScene d;
    const double dt = 0.1;
    int checked = 0, gunChecked = 0;
    for (int f = 0; f < 600; ++f) { // a minute: once round the loop and on
        d.frame(dt * f);
        if (f * dt < 8.0) continue; // slewing round from the rest pose
        ++checked;
        // The target in the turret's frame: dead ahead.
        const glm::dvec3 local(glm::inverse(d.turretWorld()) * glm::dvec4(d.options.target, 1.0));
        EXPECT_NEAR(std::atan2(local.y, local.x), 0.0, 2e-3) << "frame " << f;
        EXPECT_NEAR(d.state->turretYaw, d.turret->value("yaw"), 0.0);
        // The barrel (its shape's +z) points at the target unless the gun is at a limit.
        if (d.state->aimElevation <= polygon::kGunMinElevation ||
            d.state->aimElevation >= polygon::kGunMaxElevation)
            continue;
        ++gunChecked;
        const glm::dmat4 barrel = d.turretWorld() * glm::dmat4(d.gun->matrix());
        const glm::dvec3 breech(barrel * glm::dvec4(0, 0, 0, 1));
        const glm::dvec3 along = glm::normalize(glm::dvec3(barrel * glm::dvec4(0, 0, 1, 0)));
        const glm::dvec3 toTarget = glm::normalize(d.options.target - breech);
        EXPECT_LT(std::acos(std::min(1.0, glm::dot(along, toTarget))), 3e-3) << "frame " << f;
    }
    EXPECT_EQ(checked, 520);
    EXPECT_GT(gunChecked, 400);
}

TEST(VehicleDof, TheSlewRatesBoundEveryStep) {
    polygon::DriveOptions o;
    o.target = {0.0, -200.0, 30.0}; // away to the south and up: the turret turns a long way round
    o.turretSlewRate = 0.2;
    o.gunSlewRate = 0.05;
    DrivenScene d(o);
    d.frame(0.0);
    EXPECT_EQ(d.turret->value("yaw"), polygon::kTurretRestYaw); // the first frame has no time to turn
    EXPECT_EQ(d.gun->value("elevation"), polygon::kGunRestElevation);
    double yaw = d.turret->value("yaw"), elevation = d.gun->value("elevation");
    int limited = 0;
    bool reached = false;
    double t = 0.0;
    for (int f = 1; f < 400; ++f) {
        const double dt = f % 3 == 0 ? 0.25 : 0.05; // uneven frames
        t += dt;
        d.frame(t);
        const double dy = angleBetween(d.turret->value("yaw"), yaw);
        const double de = d.gun->value("elevation") - elevation;
        EXPECT_LE(std::abs(dy), o.turretSlewRate * dt + 1e-9) << "frame " << f;
        EXPECT_LE(std::abs(de), o.gunSlewRate * dt + 1e-9) << "frame " << f;
        limited += std::abs(dy) > o.turretSlewRate * dt - 1e-9;
        reached = reached || std::abs(angleBetween(d.state->aimYaw, d.turret->value("yaw"))) < 1e-9;
        yaw = d.turret->value("yaw");
        elevation = d.gun->value("elevation");
    }
    EXPECT_GT(limited, 10); // it did slew at its limit
    EXPECT_TRUE(reached);   // and caught up
    EXPECT_THROW(
        {
            polygon::DriveOptions bad;
            bad.turretSlewRate = -1.0;
            DrivenScene x(bad);
        },
        std::invalid_argument);
}

#endif

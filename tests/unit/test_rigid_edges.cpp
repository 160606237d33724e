// Rigid edges against soft edges (xpbd::BodyEdgeContact, rigid_edges.cpp),
// on hand-placed edges with closed-form answers.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "xpbd/rigid_solve.hpp"
#include "xpbd/xpbd.hpp"

namespace {

using xpbd::Real;
using xpbd::Vec3;

constexpr Real kH = Real(1) / 600;  // s, the substep
const double kTol = 1e3 * std::numeric_limits<Real>::epsilon();

// A soft edge of two 1 kg particles along z at height y, from z = -0.2 to
// 0.6, above (side +1: on +y of) a rigid edge along x at y = 0 through the
// origin, 5 mm thick. The closest points are at z = 0 on the soft edge
// (t = 1/4) and x = x0 on the rigid one. `body`: -1 for a static world
// edge from (-1, 0, 0) to (1, 0, 0), else a 1 kg body at the origin whose
// edge that is (in its frame, unrotated).
struct EdgeCase {
  xpbd::Model model;
  xpbd::State state;
};

EdgeCase make(Real y, Real x0, int body) {
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3(x0, y, Real(-0.2)), Real(1));
  scene.add_particle(Vec3(x0, y, Real(0.6)), Real(1));
  EdgeCase s{xpbd::compile(scene), {}};
  s.state = xpbd::make_state(s.model);
  if (body >= 0) {
    xpbd::RigidBody b;
    b.inv_mass = 1;
    b.inv_inertia = Vec3::Constant(1);
    s.state.bodies.push_back(b);
  }
  xpbd::BodyEdgeContact c;
  c.body = body;
  c.a = Vec3(-1, 0, 0);
  c.b = Vec3(1, 0, 0);
  c.p = {0, 1};
  // The soft edge belongs above (n = +-(b - a) x (x1 - x0), the sign that
  // leans towards out: +y).
  c.out = Vec3::UnitY();
  c.thickness = Real(0.005);
  s.state.edge_contacts.push_back(c);
  xpbd::rigid::begin_step(s.model, s.state);
  return s;
}

// 2 mm above a static edge with 5 mm thickness: C = -3 mm. The soft edge
// takes 3/4 and 1/4 of the push at t = 1/4 (inverse mass w_i^2 summed:
// 0.625), so the particles rise by 0.75 and 0.25 of 3 mm / 0.625, and the
// soft edge's closest point ends the thickness above the rigid edge.
TEST(RigidEdges, SoftEdgeIsPushedOutToTheThicknessByItsWeights) {
  EdgeCase s = make(Real(0.002), Real(0.2), -1);
  xpbd::rigid::solve_edge_contacts(s.model, s.state, kH);
  const double dl = 0.003 / 0.625;
  EXPECT_NEAR(double(s.state.x[0].y()), 0.002 + 0.75 * dl, kTol);
  EXPECT_NEAR(double(s.state.x[1].y()), 0.002 + 0.25 * dl, kTol);
  EXPECT_NEAR(double(0.75 * s.state.x[0].y() + 0.25 * s.state.x[1].y()), 0.005, kTol);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(s.state.x[std::size_t(i)].x(), Real(0.2));
    EXPECT_EQ(s.state.x[std::size_t(i)].z(), s.model.x0[std::size_t(i)].z());
  }
}

// The same against a free 1 kg body whose edge passes through its centre
// (lever arm 0 at x0 = 0): the body takes the push through its inverse mass
// (1 + 0.625 in the denominator) and the soft edge's opposite push; the
// momentum of the two is conserved.
TEST(RigidEdges, BodyTakesItsShareAndMomentumIsConserved) {
  EdgeCase s = make(Real(0.002), Real(0), 0);
  xpbd::rigid::solve_edge_contacts(s.model, s.state, kH);
  const double dl = 0.003 / 1.625;
  EXPECT_NEAR(double(s.state.x[0].y()), 0.002 + 0.75 * dl, kTol);
  EXPECT_NEAR(double(s.state.x[1].y()), 0.002 + 0.25 * dl, kTol);
  EXPECT_NEAR(double(s.state.bodies[0].x.y()), -dl, kTol);
  const double particles = double(s.state.x[0].y() + s.state.x[1].y()) - 0.004;  // 1 kg each
  EXPECT_NEAR(particles + double(s.state.bodies[0].x.y()), 0.0, kTol);
}

// Where the contact does not act, nothing moves: the closest point past the
// rigid edge's end (x0 = 1.5), the soft edge already the thickness away
// (6 mm), and 3 cm below (behind: the contact keeps it above) with a reach
// of 1 cm plus 6 m/s over the substep (2 cm). With 18 m/s (4 cm) it acts.
TEST(RigidEdges, NoPushPastAnEndOutsideTheThicknessOrBeyondTheReach) {
  for (const auto& [y, x0] : {std::pair{Real(0.002), Real(1.5)}, std::pair{Real(0.006), Real(0.2)}}) {
    EdgeCase s = make(y, x0, -1);
    xpbd::rigid::solve_edge_contacts(s.model, s.state, kH);
    EXPECT_EQ(s.state.x, s.model.x0) << "y " << y << ", x0 " << x0;
  }
  for (const Real speed : {Real(6), Real(18)}) {
    EdgeCase s = make(Real(-0.03), Real(0.2), -1);
    s.state.edge_contacts[0].reach = Real(0.01);
    s.state.edge_contacts[0].closing_speed = speed;
    xpbd::rigid::solve_edge_contacts(s.model, s.state, kH);
    if (speed < 10)
      EXPECT_EQ(s.state.x, s.model.x0);
    else
      EXPECT_NEAR(double(0.75 * s.state.x[0].y() + 0.25 * s.state.x[1].y()), 0.005, kTol);
  }
}

// Parallel edges have no normal: the soft edge along x over the rigid one
// is left alone (its particles' own contacts answer there).
TEST(RigidEdges, ParallelEdgesAreLeftAlone) {
  EdgeCase s = make(Real(0.002), Real(0.2), -1);
  s.state.x[1] = Vec3(Real(0.6), Real(0.002), Real(-0.2));
  const std::vector<Vec3> before = s.state.x;
  xpbd::rigid::solve_edge_contacts(s.model, s.state, kH);
  EXPECT_EQ(s.state.x, before);
}

// The soft edge turned through parallel with the rigid edge after the
// contact was made: e_r x e_s turns over, and the push must not. The soft
// edge, 2 mm above a static edge along x, at 10 degrees either side of z
// (its closest point at t = 1/4 either way): pushed up to the thickness
// both times (the closed form of the first test: the weights 3/4 and 1/4).
// With the sign of e_r x e_s kept from one side, the other was pushed
// down, through the rigid edge (a cloth over a spinning blade's edge).
TEST(RigidEdges, SoftEdgeTurnedThroughParallelIsStillPushedOut) {
  for (const Real deg : {Real(80), Real(100)}) {
    EdgeCase s = make(Real(0.002), Real(0.2), -1);
    const Real a = deg * Real(3.14159265358979) / 180;
    const Vec3 dir(std::cos(a), 0, std::sin(a));  // from x; 90 degrees is the make() edge along z
    s.state.x[0] = Vec3(Real(0.2), Real(0.002), 0) - Real(0.2) * dir;
    s.state.x[1] = s.state.x[0] + Real(0.8) * dir;
    xpbd::rigid::solve_edge_contacts(s.model, s.state, kH);
    EXPECT_GT(s.state.x[0].y(), Real(0.002)) << deg << " degrees";
    EXPECT_NEAR(double(0.75 * s.state.x[0].y() + 0.25 * s.state.x[1].y()), 0.005, kTol) << deg << " degrees";
  }
}

// A soft edge pointing along `out` has no outside on the rigid edge: left
// alone. The soft edge in the plane x = 0.2, from 1 mm below to 5 mm above
// the rigid edge, leaning 10 degrees from +y (n leans about 0.17 towards
// out, under kEdgeLean).
TEST(RigidEdges, SoftEdgeAlongTheOutsideIsLeftAlone) {
  EdgeCase s = make(Real(0.002), Real(0.2), -1);
  const Real a = Real(10) * Real(3.14159265358979) / 180;
  s.state.x[0] = Vec3(Real(0.2), Real(-0.001), Real(-0.001) * std::tan(a));
  s.state.x[1] = Vec3(Real(0.2), Real(0.005), Real(0.005) * std::tan(a));
  const std::vector<Vec3> before = s.state.x;
  xpbd::rigid::solve_edge_contacts(s.model, s.state, kH);
  EXPECT_EQ(s.state.x, before);
}

// Bad contacts are named by field and index.
TEST(RigidEdges, BadContactsAreNamed) {
  const auto expect_named = [](const auto& spoil, const std::string& what) {
    EdgeCase s = make(Real(0.002), Real(0.2), -1);
    spoil(s.state.edge_contacts[0]);
    try {
      xpbd::rigid::begin_step(s.model, s.state);
      ADD_FAILURE() << what << " accepted";
    } catch (const xpbd::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("edge_contacts[0]"), std::string::npos) << what << ": " << e.what();
    }
  };
  expect_named([](xpbd::BodyEdgeContact& c) { c.p[1] = 7; }, "particle 7 of 2");
  expect_named([](xpbd::BodyEdgeContact& c) { c.out = Vec3::Zero(); }, "out zero");
  expect_named([](xpbd::BodyEdgeContact& c) { c.out = Vec3(0, 2, 0); }, "out of length 2");
  expect_named([](xpbd::BodyEdgeContact& c) { c.a.x() = std::numeric_limits<Real>::quiet_NaN(); }, "a NaN end");
  expect_named([](xpbd::BodyEdgeContact& c) { c.reach = -1; }, "reach -1");
  expect_named([](xpbd::BodyEdgeContact& c) { c.closing_speed = std::numeric_limits<Real>::infinity(); },
               "an infinite closing speed");
  expect_named([](xpbd::BodyEdgeContact& c) { c.thickness = -1; }, "thickness -1");
  expect_named([](xpbd::BodyEdgeContact& c) { c.static_friction = std::numeric_limits<Real>::quiet_NaN(); },
               "a NaN static friction");
}

// Friction (BodyEdgeContact::static_friction, dynamic_friction): a soft
// edge of two particles along z resting across a static world edge along
// x, the thickness above it, both particles sliding along x at v0. Only
// the edge contact holds them up (at t = 1/2, so the pair does not tip),
// and Coulomb's law stops them after v0^2 / (2 mu g): with mu_s = mu_d at
// the position level, and with mu_s = 0 in the velocity pass alone
// (edge_contact_velocities).
struct Slide {
  xpbd::Model model;
  xpbd::State state;
};

Slide sliding_edge(Real v0, Real mu, Real slope, Real mu_s) {
  const Real t = Real(0.005);
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3(0, t, Real(-0.4)), Real(0.5));
  scene.add_particle(Vec3(0, t, Real(0.4)), Real(0.5));
  Slide s{xpbd::compile(scene), {}};
  s.state = xpbd::make_state(s.model);
  for (Vec3& v : s.state.v) v = Vec3(v0, 0, 0);
  xpbd::BodyEdgeContact c;
  c.body = -1;
  // The rigid edge rises along x at `slope` (rad).
  c.a = Vec3(-2 * std::cos(slope), -2 * std::sin(slope), 0);
  c.b = -c.a;
  c.p = {0, 1};
  c.out = Vec3(-std::sin(slope), std::cos(slope), 0);
  c.thickness = t;
  c.static_friction = mu_s;
  c.dynamic_friction = mu;
  s.state.edge_contacts.push_back(c);
  return s;
}

TEST(RigidEdges, SoftEdgeSlidingAcrossAStaticEdgeStopsAtTheCoulombDistance) {
  const Real v0 = 1, mu = Real(0.5), g = Real(9.81);
  for (const Real mu_s : {mu, Real(0)}) {
    Slide s = sliding_edge(v0, mu, 0, mu_s);
    xpbd::StepConfig cfg;
    cfg.gravity = Vec3(0, -g, 0);
    cfg.substeps = 20;
    for (int k = 0; k < 40; ++k) xpbd::step(s.model, s.state, cfg);
    const double expected = double(v0 * v0 / (2 * mu * g));  // 0.102 m, in 0.2 s
    for (int i = 0; i < 2; ++i) {
      // Discretisation: of the order of a substep's travel, v0 h ~ 0.8 mm.
      EXPECT_NEAR(double(s.state.x[std::size_t(i)].x()), expected, 0.02 * expected) << "mu_s " << mu_s;
      EXPECT_LT(double(s.state.v[std::size_t(i)].norm()), 1e-3) << "mu_s " << mu_s;
      EXPECT_NEAR(double(s.state.x[std::size_t(i)].y()), 0.005, 1e-4);  // held up by the edge
    }
  }
}

// On a static edge rising at 0.2 rad, below the friction angle atan(0.5)
// = 0.46 rad, the resting soft edge stays where it is; at 0.6 rad it
// slides down with acceleration g (sin a - mu cos a) along the edge.
TEST(RigidEdges, SoftEdgeOnASlopingEdgeHoldsBelowTheFrictionAngleAndSlidesAbove) {
  const Real mu = Real(0.5), g = Real(9.81);
  xpbd::StepConfig cfg;
  cfg.gravity = Vec3(0, -g, 0);
  cfg.substeps = 20;
  for (const Real slope : {Real(0.2), Real(0.6)}) {
    Slide s = sliding_edge(0, mu, slope, mu);
    // Start on the sloping edge at the thickness: along its normal.
    for (Vec3& x : s.state.x) x = Vec3(-std::sin(slope), std::cos(slope), 0) * Real(0.005) + Vec3(0, 0, x.z());
    const int steps = 30;  // 0.5 s
    for (int k = 0; k < steps; ++k) xpbd::step(s.model, s.state, cfg);
    const Vec3 along(std::cos(slope), std::sin(slope), 0);
    const double moved = double(s.state.x[0].dot(along));
    const double time = double(steps) * double(cfg.dt);
    const double a = double(g * (std::sin(slope) - mu * std::cos(slope)));
    if (a < 0) {
      EXPECT_NEAR(moved, 0.0, 1e-4) << slope;
    } else {
      // Downhill: -a t^2 / 2 = -0.171 m at 0.6 rad; within 3 %.
      EXPECT_NEAR(moved, -0.5 * a * time * time, 0.03 * 0.5 * a * time * time) << slope;
    }
  }
}

}  // namespace

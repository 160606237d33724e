// Rigid shadow bodies, body contacts and attachments (xpbd/src/rigid_solve.cpp),
// without Bullet: conservation laws and closed-form Coulomb friction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "xpbd/rigid_solve.hpp"
#include "xpbd/xpbd.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

namespace {

using xpbd::Real;
using xpbd::Vec3;

// Linear and angular momentum (about the origin) of particles and bodies.
struct Momenta {
  Vec3 linear = Vec3::Zero();
  Vec3 angular = Vec3::Zero();
};
Momenta momenta(const xpbd::Model& m, const xpbd::State& s) {
  Momenta p;
  for (xpbd::Index i = 0; i < m.num_particles(); ++i) {
    if (m.inv_mass[i] == Real(0)) continue;
    const Vec3 mv = s.v[i] / m.inv_mass[i];
    p.linear += mv;
    p.angular += s.x[i].cross(mv);
  }
  for (const xpbd::RigidBody& b : s.bodies) {
    if (b.inv_mass == Real(0)) continue;
    const Vec3 mv = b.v / b.inv_mass;
    p.linear += mv;
    // I_world w with I = R diag(1/inv_inertia) R^T.
    const Vec3 wl = b.q.conjugate() * b.w;
    const Vec3 lw = b.q * Vec3(wl.array() / b.inv_inertia.array());
    p.angular += b.x.cross(mv) + lw;
  }
  return p;
}

// A 0.5 kg particle at x moving at 3 m/s along -y hits a 2 kg body at
// (0, -0.1, 0) turned by q, with inverse inertia inv_inertia (principal
// axes of its frame); the contact was found at world point r_world, normal
// +y. 20 substeps x 2 iterations, no gravity. Checks that the contact
// acted (the particle was stopped) and that momentum is exchanged, not
// created. Linear: equal and opposite position corrections, so round-off.
// Angular: the body's rotation is updated with the first-order quaternion
// step q += h/2 [w, 0] q and w is recovered from the quaternion change,
// which are exact only to O((w h)^2) per substep (here w h ~ 1e-3): allow
// 1e-5 relative. A wrong lever arm or sign gives an O(1) error. Round-off
// allowance 1e4 eps covers the float build (label unit runs there).
void expect_hit_keeps_momentum(const Vec3& x, const xpbd::Quat& q, const Vec3& inv_inertia, const Vec3& r_world) {
  xpbd::SceneDesc scene;
  scene.add_particle(x, Real(0.5), 0, Vec3(0, -3, 0));
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  xpbd::RigidBody b;
  b.x = Vec3(0, -0.1, 0);
  b.inv_mass = Real(0.5);
  b.inv_inertia = inv_inertia;
  b.q = q;
  s.bodies.push_back(b);
  xpbd::BodyContact c;
  c.particle = 0;
  c.body = 0;
  c.r = b.q.conjugate() * (r_world - b.x);  // body frame
  c.n = b.q.conjugate() * Vec3(0, 1, 0);
  s.contacts.push_back(c);
  xpbd::StepConfig cfg;
  cfg.gravity.setZero();
  cfg.substeps = 20;
  cfg.iterations = 2;
  const Momenta before = momenta(m, s);
  xpbd::step(m, s, cfg);
  const Momenta after = momenta(m, s);
  EXPECT_GT(s.v[0].y(), Real(-2.5));
  EXPECT_GT(s.bodies[0].w.norm(), Real(0.1));
  const Real roundoff = Real(1e4) * xpbd::kEpsilon;
  EXPECT_LT((after.linear - before.linear).norm(), roundoff * before.linear.norm());
  const Real scale = before.angular.norm() + Real(0.3) * before.linear.norm();
  EXPECT_LT((after.angular - before.angular).norm(), std::max(Real(1e-5), roundoff) * scale);
}

// Off the body's centre of mass: the contact point 0.3 m from the centre
// along x, under the particle.
TEST(RigidSolve, OffCentreHitConservesLinearAndAngularMomentum) {
  expect_hit_keeps_momentum(Vec3(0.3, 0.02, 0), xpbd::Quat(Eigen::AngleAxis<Real>(Real(0.3), Vec3::UnitZ())),
                            Vec3(6, 4, 5), Vec3(0.3, 0, 0));
}

// The same hit, with the particle 0.25 m along the contact's plane from
// the point c.r the contact was found at (it slid there after the host
// found the contact). The body is pushed where the particle touches its
// plane, not at c.r: the two pushes act along one line, and angular
// momentum is conserved as above. With the push at c.r the angular
// momentum changes by (x - p) x (push), an O(1) error here. (The particle
// moves along the normal only: a tangential relative velocity adds an
// O(h) term to this measure, x_end x v_end, whichever the lever arm. The
// body is isotropic: predict_bodies has no gyroscopic term, so a free spin
// keeps its angular momentum only then.)
TEST(RigidSolve, HitFarAlongThePlaneFromWhereTheContactWasFoundConservesMomentum) {
  const xpbd::Quat q(Eigen::AngleAxis<Real>(Real(0.3), Vec3(1, 2, 3).normalized()));
  expect_hit_keeps_momentum(Vec3(0.3, 0.02, 0.1), q, Vec3(5, 5, 5), Vec3(0.05, 0, -0.1));
}

// A particle held by the ground under an edge contact's plane (its normal
// between a box's bottom and side faces), 0.2 m along that plane
// from the edge, 1 mm inside its band; the body is light about the edge's
// axis (a long thin bar). The ground holds the particle (joint solve), so
// the body takes the correction, mostly as a turn about its long axis. The
// turn moves the plane under the particle through the normal's rotation as
// well as the edge point's: C's gradient is (x - X) x n, the particle's
// own lever arm. One projection then leaves C at second order in the turn
// (measured: -1.7e-6 m after a turn of 8.5e-4 rad). With the lever arm to
// the edge point the solve misjudges how the turn moves the plane 0.2 m
// from the edge: C ended at -1.8e-5 m after a tenth of that turn. In the
// squeeze at 200 substeps, with hundreds of such contacts 1-15 mm deep,
// that error grew over a substep's sweep until one sweep turned the bar by
// 0.25 rad (docs/squeeze-history.md).
TEST(RigidSolve, SpacerFarAlongAnEdgePlaneIsMetAfterOneProjection) {
  const Real t = Real(0.005);
  const Vec3 n = Vec3(0, -0.92, 0.38).normalized();    // an edge's normal, body frame = world
  const Vec3 edge(0, -0.03, 0.03);                     // the edge point, body frame
  const Vec3 along = Vec3(0, 0.38, 0.92).normalized(); // in the plane, across the edge
  const Vec3 x = edge + (t - Real(0.001)) * n - Real(0.2) * along;  // 1 mm inside the band
  xpbd::SceneDesc scene;
  scene.add_particle(x, Real(1e-3));
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  xpbd::RigidBody b;  // 2 kg, light about x
  b.inv_mass = Real(0.5);
  b.inv_inertia = Vec3(800, 4, 4);
  s.bodies.push_back(b);
  xpbd::BodyContact ground;  // the world plane through the particle's band, normal +y
  ground.particle = 0;
  ground.body = -1;
  ground.r = x - t * Vec3::UnitY();
  ground.n = Vec3::UnitY();
  ground.thickness = t;
  xpbd::BodyContact face;
  face.particle = 0;
  face.body = 0;
  face.r = edge;
  face.n = n;
  face.thickness = t;
  s.contacts = {ground, face};
  xpbd::StepConfig cfg;
  cfg.gravity.setZero();
  cfg.substeps = 1;
  cfg.iterations = 1;
  xpbd::step(m, s, cfg);
  const xpbd::RigidBody& a = s.bodies[0];
  const Real C = (a.q * n).dot(s.x[0] - (a.x + a.q * edge)) - t;
  const double roundoff = 64 * 0.1 * std::numeric_limits<Real>::epsilon();
  EXPECT_NEAR(double(s.x[0].y()), double(x.y()), roundoff);  // held by the ground
  EXPECT_GT(a.q.angularDistance(xpbd::Quat::Identity()), Real(1e-4));  // the body turned
  EXPECT_NEAR(double(C), 0.0, 5e-6);
}

TEST(RigidSolve, SlidingOnStaticGroundStopsAtTheCoulombDistance) {
  // A particle sliding at v0 on the static ground (world contact, normal +y)
  // with dynamic friction mu decelerates at mu g: it stops after
  // v0^2 / (2 mu g). Static friction equals dynamic friction, so once
  // stopped it stays.
  const Real v0 = 2, mu = 0.4, g = 9.81;
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3(0, 0, 0), 1, 0, Vec3(v0, 0, 0));
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  xpbd::BodyContact c;
  c.particle = 0;
  c.body = -1;
  c.r = Vec3::Zero();
  c.n = Vec3::UnitY();
  c.static_friction = mu;
  c.dynamic_friction = mu;
  s.contacts.push_back(c);
  xpbd::StepConfig cfg;
  cfg.gravity = Vec3(0, -g, 0);
  cfg.substeps = 20;
  for (int k = 0; k < 120; ++k) xpbd::step(m, s, cfg);
  const Real expected = v0 * v0 / (2 * mu * g);
  // Discretisation: the friction impulse per substep is exact Coulomb, so the
  // error is of the order of one substep's travel, v0 h ~ 1.7 mm.
  EXPECT_NEAR(s.x[0].x(), expected, Real(0.01) * expected);
  EXPECT_NEAR(s.v[0].norm(), Real(0), Real(1e-6));  // stopped (sliding would be ~m/s)
  EXPECT_NEAR(s.x[0].y(), Real(0), Real(1e-6));     // rests on the ground
}

TEST(RigidSolve, BadContactIndexIsAConfigErrorNamingIt) {
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3::Zero(), 1);
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  xpbd::BodyContact c;
  c.particle = 0;
  c.body = 3;  // no bodies
  s.contacts.push_back(c);
  try {
    xpbd::step(m, s, xpbd::StepConfig{});
    FAIL() << "expected ConfigError";
  } catch (const xpbd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("contacts[0].body: index 3"), std::string::npos) << e.what();
  }
}

// A body's own acceleration enters every substep before the move, as the
// particles' gravity does: after n substeps of h from (x0, v0),
//   v_n = v0 + n h a,  x_n = x0 + n h v0 + h^2 a n (n+1)/2  (symplectic Euler).
// Angular: w_n = w0 + n h alpha. A static body (inv_mass 0) ignores both.
TEST(RigidSolve, BodyAccelerationFollowsSymplecticEulerPerSubstep) {
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3(5, 5, 5), 1);  // far away: no interaction
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  xpbd::RigidBody b;
  b.x = Vec3(0, 1, 0);
  b.v = Vec3(0.5, 0, 0);
  b.inv_mass = Real(0.25);
  b.inv_inertia = Vec3(1, 1, 1);
  b.accel = Vec3(0, -9.81, 2);
  b.ang_accel = Vec3(0, 0, 3);
  s.bodies.push_back(b);
  xpbd::RigidBody fixed = b;
  fixed.inv_mass = 0;
  fixed.inv_inertia = Vec3::Zero();
  s.bodies.push_back(fixed);
  xpbd::StepConfig cfg;
  cfg.gravity = Vec3::Zero();
  cfg.substeps = 7;
  xpbd::step(m, s, cfg);
  const int n = cfg.substeps;
  const Real h = cfg.dt / Real(n);
  const Vec3 v = b.v + Real(n) * h * b.accel;
  const Vec3 x = b.x + Real(n) * h * b.v + h * h * b.accel * Real(n * (n + 1)) / 2;
  const Real tol = Real(1e3) * std::numeric_limits<Real>::epsilon();
  // v is read back as (x - x_prev)/h: round-off of |x|/h.
  EXPECT_LT((s.bodies[0].v - v).norm(), tol * x.norm() / h);
  EXPECT_LT((s.bodies[0].x - x).norm(), tol * x.norm());
  // w is read back from the rotation of the last substep as the exact
  // inverse of its step (update_body_velocities): what is left is the
  // round-off of the rotation's small vector part, w h / 2 ~ 4e-4 here.
  const Real w = Real(n) * h * Real(3);
  EXPECT_NEAR(s.bodies[0].w.z(), w, Real(1e-6) * w);
  EXPECT_LT((s.bodies[1].x - (b.x + cfg.dt * b.v)).norm(), tol);  // moves with v only
  EXPECT_LT((s.bodies[1].v - b.v).norm(), tol);
  EXPECT_EQ(s.bodies[1].w, Vec3::Zero());
}

TEST(RigidSolve, NonFiniteBodyAccelerationIsAConfigError) {
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3::Zero(), 1);
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  xpbd::RigidBody b;
  b.inv_mass = 1;
  b.accel = Vec3(0, std::numeric_limits<Real>::quiet_NaN(), 0);
  s.bodies.push_back(b);
  try {
    xpbd::step(m, s, xpbd::StepConfig{});
    FAIL() << "expected ConfigError";
  } catch (const xpbd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("state.bodies[0]"), std::string::npos) << e.what();
  }
}

}  // namespace

namespace {

// The contact violation measures (rigid_solve.hpp), on hand-placed
// contacts with known geometry: a particle 2 mm above the ground with a
// 5 mm thickness is 3 mm inside its band; one 7 mm above a rotated,
// translated body's face at 5 mm is not inside it; a rigid feature 1 mm
// from a cloth triangle's plane, on its side, with 5 mm is 4 mm inside.
TEST(RigidSolve, ContactViolationsAreTheDepthsInsideTheBand) {
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3(0.1, 0.002, 0), Real(1));  // 0: above the ground
  scene.add_particle(Vec3(0, 0, 0), Real(1));        // 1: beside the body, set below
  scene.add_particle(Vec3(0, 1, 0), Real(1));        // 2-4: a triangle in the plane y = 1
  scene.add_particle(Vec3(1, 1, 0), Real(1));
  scene.add_particle(Vec3(0, 1, 1), Real(1));
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  const Real h = Real(1) / 600;  // the substep (a triangle contact's reach grows with it)
  EXPECT_EQ(xpbd::rigid::deepest_contact_violation(s, h), Real(0));  // no contacts

  xpbd::BodyContact ground;  // the world plane y = 0, normal +y
  ground.particle = 0;
  ground.body = -1;
  ground.thickness = Real(0.005);
  s.contacts.push_back(ground);

  xpbd::RigidBody b;  // a body turned 90 degrees about z: its local +x face normal is world +y
  b.x = Vec3(0, -0.5, 0);
  b.q = xpbd::Quat(Eigen::AngleAxis<Real>(Real(1.5707963267948966), Vec3::UnitZ()));
  s.bodies.push_back(b);
  xpbd::BodyContact face;
  face.particle = 1;
  face.body = 0;
  face.r = Vec3(0.5, 0, 0);  // world (0, 0, 0)
  face.n = Vec3(1, 0, 0);    // world +y
  face.thickness = Real(0.005);
  s.x[1] = Vec3(0.2, 0.007, 0);
  s.contacts.push_back(face);

  xpbd::BodyTriangleContact tri;  // a world feature point 1 mm above the triangle, on its upper side
  tri.tri = {2, 4, 3};             // (x4 - x2) x (x3 - x2) = (0, 0, 1) x (1, 0, 0) = +y
  tri.body = -1;
  tri.r = Vec3(0.2, 1.001, 0.2);
  tri.side = 1;
  tri.thickness = Real(0.005);
  s.triangle_contacts.push_back(tri);

  const double tol = 1e3 * std::numeric_limits<Real>::epsilon();
  EXPECT_NEAR(double(xpbd::rigid::deepest_contact_violation(s, h)), 0.004, tol);
  EXPECT_NEAR(double(xpbd::rigid::worst_contact_violation(m, s, h)), 0.004 / 0.005, 2 * tol / 0.005);
  // The feature 3 cm behind the plane: 3.5 cm inside the band, within a
  // reach of 1 cm plus 18 m/s over the substep (4 cm), not within 1 cm
  // plus 6 m/s (2 cm), where the solve leaves the contact alone.
  s.triangle_contacts[0].r.y() = Real(0.97);
  s.triangle_contacts[0].reach = Real(0.01);
  s.triangle_contacts[0].closing_speed = 18;
  EXPECT_NEAR(double(xpbd::rigid::deepest_contact_violation(s, h)), 0.035, tol);
  EXPECT_NEAR(double(xpbd::rigid::worst_contact_violation(m, s, h)), 0.035 / 0.005, 2 * tol / 0.005);
  s.triangle_contacts[0].closing_speed = 6;  // beyond its reach: the ground's 3 mm is the deepest
  EXPECT_NEAR(double(xpbd::rigid::deepest_contact_violation(s, h)), 0.003, tol);
  EXPECT_NEAR(double(xpbd::rigid::worst_contact_violation(m, s, h)), 0.003 / 0.005, 2 * tol / 0.005);
  s.triangle_contacts.clear();
  EXPECT_NEAR(double(xpbd::rigid::deepest_contact_violation(s, h)), 0.003, tol);
  EXPECT_NEAR(double(xpbd::rigid::worst_contact_violation(m, s, h)), 0.003 / 0.005, 2 * tol / 0.005);
  s.x[0].y() = Real(0.01);  // out of its band: nothing inside any more
  EXPECT_EQ(xpbd::rigid::deepest_contact_violation(s, h), Real(0));
  EXPECT_EQ(xpbd::rigid::worst_contact_violation(m, s, h), Real(0));
}

// A rigid feature 3 cm behind a cloth triangle's plane (5 mm thickness),
// over the triangle at barycentric weights (0.6, 0.2, 0.2), particles of
// 1 kg, a static world point: within its reach the solve moves the
// triangle by C / sum w_i^2 along the normal, weighted w_i, so that the
// plane under the feature ends the thickness away (particle 2 moves by
// 0.6 * 0.035 / 0.44); beyond it (a reach of 1 cm plus 6 m/s over the
// 1/600 s substep, 2 cm) the triangle is left where it is.
TEST(RigidSolve, TriangleContactActsWithinItsReachOnly) {
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3(0, 1, 0), Real(1));
  scene.add_particle(Vec3(0, 1, 1), Real(1));
  scene.add_particle(Vec3(1, 1, 0), Real(1));
  const xpbd::Model m = xpbd::compile(scene);
  const Real h = Real(1) / 600;
  const auto solve = [&](Real reach, Real closing_speed) {
    xpbd::State s = xpbd::make_state(m);
    xpbd::BodyTriangleContact c;
    c.tri = {0, 1, 2};  // (x1 - x0) x (x2 - x0) = (0, 0, 1) x (1, 0, 0) = +y
    c.body = -1;
    c.r = Vec3(0.2, 0.97, 0.2);
    c.side = 1;
    c.thickness = Real(0.005);
    c.reach = reach;
    c.closing_speed = closing_speed;
    s.triangle_contacts.push_back(c);
    xpbd::rigid::begin_step(m, s);
    xpbd::rigid::solve_triangle_contacts(m, s, h);
    return s.x;
  };
  const double tol = 1e3 * std::numeric_limits<Real>::epsilon();
  for (const auto& [reach, speed] : {std::pair{std::numeric_limits<Real>::infinity(), Real(0)},
                                     std::pair{Real(0.01), Real(18)}}) {
    const std::vector<Vec3> x = solve(reach, speed);
    const double w[3] = {0.6, 0.2, 0.2};
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(double(x[std::size_t(i)].y()), 1 - w[i] * 0.035 / 0.44, tol) << "particle " << i;
      EXPECT_EQ(x[std::size_t(i)].x(), m.x0[std::size_t(i)].x());
    }
  }
  EXPECT_EQ(solve(Real(0.01), Real(6)), m.x0);
  // A reach or closing speed that is not a length or speed is named.
  for (const auto& [reach, speed] : {std::pair{std::numeric_limits<Real>::quiet_NaN(), Real(0)},
                                     std::pair{Real(-1), Real(0)}, std::pair{Real(0), Real(-1)},
                                     std::pair{Real(0), std::numeric_limits<Real>::infinity()}}) {
    try {
      solve(reach, speed);
      ADD_FAILURE() << "reach " << reach << ", closing_speed " << speed << " accepted";
    } catch (const xpbd::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("triangle_contacts[0]"), std::string::npos) << e.what();
    }
  }
}

}  // namespace

namespace {

// A light particle pressed between the static ground and a body 1e7 times
// heavier (a cloth under a heavy box): its two contacts are solved jointly,
// so the particle is a rigid spacer held by the ground and the body takes
// the whole correction. The body's face starts 1 mm inside the particle's
// band; after one substep without gravity the body has risen by exactly
// that 1 mm and the particle has not moved. In every build: the float
// build's joint solve once lost the mass ratio to cancellation (the
// body then rose by 1e-7 mm and the particle went into the ground).
TEST(RigidSolve, ParticleBetweenGroundAndAHeavyBodyIsARigidSpacer) {
  const Real t = Real(0.005);  // m, thickness of both contacts
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3(0, t, 0), Real(1e-3));  // resting on the ground's band
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  xpbd::RigidBody b;  // 1e4 kg, its bottom face 0.05 m below its centre, 1 mm inside the band
  b.x = Vec3(0, 2 * t - Real(0.001) + Real(0.05), 0);
  b.inv_mass = Real(1e-4);
  b.inv_inertia = Vec3(1e-3, 1e-3, 1e-3);
  s.bodies.push_back(b);
  xpbd::BodyContact ground;  // the world plane y = 0, normal +y
  ground.particle = 0;
  ground.body = -1;
  ground.thickness = t;
  xpbd::BodyContact face;  // the body's bottom face, normal -y, straight under the centre
  face.particle = 0;
  face.body = 0;
  face.r = Vec3(0, -0.05, 0);
  face.n = Vec3(0, -1, 0);
  face.thickness = t;
  s.contacts = {ground, face};
  xpbd::StepConfig cfg;
  cfg.gravity.setZero();
  cfg.substeps = 1;
  cfg.dt = Real(1) / 60;
  xpbd::step(m, s, cfg);
  // Round-off: the positions (about 0.06 m) in the build's scalar, and the
  // joint solve's cancellation, in double: about the mass ratio (1e7) times
  // double's epsilon, relative to the 1 mm correction. A solve that loses
  // the ratio is off by up to the whole millimetre.
  const double tol = 64 * 0.06 * std::numeric_limits<Real>::epsilon() +
                     16 * 1e-3 * 1e7 * std::numeric_limits<double>::epsilon();
  EXPECT_NEAR(double(s.x[0].y()), double(t), tol);
  EXPECT_NEAR(double(s.bodies[0].x.y()), 2 * double(t) + 0.05, tol);
}

// A heavy body sliding at v0 on a light particle that lies on the static
// ground (a box sliding on a cloth), friction mu on both sides: Coulomb's
// law between the two bodies stops the body after v0^2 / (2 mu g), and the
// ground holds the particle (its cone, mu (M + m) g, is the wider). Solved
// one by one, the body's friction only brought the particle up to the
// body's speed and the ground's stopped it again: the body lost the
// particle's momentum per substep and slid on (contact_block.cpp).
TEST(RigidSolve, BodySlidingOnAParticleOnTheGroundStopsAtTheCoulombDistance) {
  const Real t = Real(0.005), v0 = 1, mu = Real(0.4), g = Real(9.81);
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3(0, t, 0), Real(1e-3));
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  xpbd::RigidBody b;  // 100 kg, resting on the particle, not turning
  b.x = Vec3(0, 2 * t + Real(0.05), 0);
  b.v = Vec3(v0, 0, 0);
  b.inv_mass = Real(0.01);
  b.accel = Vec3(0, -g, 0);
  s.bodies.push_back(b);
  xpbd::BodyContact ground;
  ground.particle = 0;
  ground.body = -1;
  ground.thickness = t;
  ground.static_friction = ground.dynamic_friction = mu;
  xpbd::BodyContact face = ground;  // the body's bottom face
  face.body = 0;
  face.r = Vec3(0, -0.05, 0);
  face.n = Vec3(0, -1, 0);
  s.contacts = {ground, face};
  xpbd::StepConfig cfg;
  cfg.gravity = Vec3(0, -g, 0);
  cfg.substeps = 20;
  for (int k = 0; k < 40; ++k) xpbd::step(m, s, cfg);
  const Real expected = v0 * v0 / (2 * mu * g);  // 0.127 m, in 0.25 s
  // Discretisation: of the order of a substep's travel, v0 h ~ 0.8 mm.
  EXPECT_NEAR(double(s.bodies[0].x.x()), double(expected), 0.02 * double(expected));
  EXPECT_LT(double(s.bodies[0].v.norm()), 1e-3);
  EXPECT_NEAR(double(s.x[0].x()), 0.0, 1e-4);  // held by the ground
  EXPECT_NEAR(double(s.bodies[0].x.y()), 2 * double(t) + 0.05, 1e-4);
}

}  // namespace

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

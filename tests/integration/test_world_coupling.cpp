// Integration tests of the two-way coupling between XpbdWorld particle
// systems and dynamic Bullet rigid bodies: momentum exchange through
// contacts and through attachments, a heavy ball on a trampoline, and a
// rigid box on a rope (pendulum period).
//
// Momentum: contacts and attachments apply equal and opposite position
// impulses to the particle and to the body's shadow (rigid.hpp), and the
// bridge hands the shadow's velocity change to Bullet as an impulse. With no
// gravity and no other forces, ball + cloth momentum is conserved exactly in
// exact arithmetic; the 1% tolerance of the requirement is far above
// round-off, and far below what a one-way coupling would give (there the
// cloth gains momentum the body never loses: tens of percent here).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "fits.hpp"
#include "support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

// ---------------------------------------------------------------------------
// 2. Momentum exchange: in zero gravity, a 1 kg ball thrown at 5 m/s into a
// free 0.5 kg cloth. Ball + cloth linear momentum after the impact equals
// the ball's 5 kg m/s before.

TEST(WorldCoupling, BallThrownIntoFreeClothConservesLinearMomentum) {
  BulletWorld bw(Vec3::Zero());
  const Real M = 1, v0 = 5, r = Real(0.1);  // kg, m/s, m
  btRigidBody* ball = bw.add_body(new btSphereShape(r), M, BulletWorld::at(Vec3(0, 0, Real(-0.4))),
                                  Vec3(0, 0, v0));
  XpbdWorld xw(bw.world());

  // 0.6 m square cloth in the plane z = 0 (across the ball's path), 0.5 kg.
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc d;
  d.nx = d.ny = 16;
  d.size_u = d.size_v = Real(0.6);
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitY();
  d.origin = Vec3(Real(-0.3), Real(-0.3), 0);
  d.mass = Real(0.5);
  d.bend_mat.compliance = Real(1e-2);
  xpbd::add_cloth_grid(scene, d);
  System cloth = make_system(scene);
  SystemSettings set;
  set.iterations = 2;
  const auto id = xw.add_system(cloth.model, cloth.state, set);

  const Vec3 p0 = momentum(*ball);  // the cloth is at rest
  Real min_ball_v = v0;
  for (int k = 0; k < 45; ++k) {  // 0.75 s: impact at ~0.05 s, then ball and cloth travel together
    bw.step();
    min_ball_v = std::min(min_ball_v, Real(ball->getLinearVelocity().z()));
  }
  const Vec3 pb = momentum(*ball);
  const Vec3 pc = xpbd::linear_momentum(xw.model(id), xw.state(id));
  const Vec3 p1 = pb + pc;
  std::printf("before %.6g kg m/s; after: ball %.6g + cloth %.6g = %.6g (|dp|/|p| = %.3g), "
              "slowest ball speed %.4g m/s\n",
              p0.z(), pb.z(), pc.z(), p1.z(), (p1 - p0).norm() / p0.norm(), min_ball_v);
  EXPECT_LT((p1 - p0).norm(), Real(0.01) * p0.norm());
  // The exchange happened: the cloth carries a real share of the momentum.
  // A perfectly inelastic capture of the whole cloth would leave the ball
  // M/(M + m) = 2/3 of it; the cloth must have at least 10%.
  EXPECT_GT(pc.z(), Real(0.1) * p0.z());
}

// ---------------------------------------------------------------------------
// 10. Attachment to a dynamic body is two-way: a cloth attached by one edge
// to a free-floating 1 kg box in zero gravity, pulled away from it (its
// free particles start at 2 m/s away from the box). The box is dragged along
// and the total momentum stays at the cloth's initial momentum.

TEST(WorldCoupling, ClothAttachedToFreeBoxConservesLinearMomentumWhenPulled) {
  BulletWorld bw(Vec3::Zero());
  const Real M = 1, a = Real(0.1);  // kg, m (box half extent)
  btRigidBody* box = bw.add_body(new btBoxShape(btVector3(a, a, a)), M, BulletWorld::at(Vec3::Zero()));
  XpbdWorld xw(bw.world());

  // 0.4 m square cloth in the plane y = 0, its edge j = 0 on the box's +x
  // face (x = a, z in [-0.2, 0.2]), extending along +x. 0.5 kg.
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc d;
  d.nx = d.ny = 11;
  d.size_u = d.size_v = Real(0.4);
  d.u = Vec3::UnitZ();
  d.v = Vec3::UnitX();
  d.origin = Vec3(a, 0, Real(-0.2));
  d.mass = Real(0.5);
  d.bend_mat.compliance = Real(1e-2);
  const xpbd::ClothGrid g = xpbd::add_cloth_grid(scene, d);
  scene.velocities.assign(scene.positions.size(), Vec3::Zero());
  for (int j = 1; j < d.ny; ++j)
    for (int i = 0; i < d.nx; ++i) scene.velocities[g.at(i, j)] = Vec3(2, 0, 0);
  System cloth = make_system(scene);
  SystemSettings set;
  set.iterations = 2;
  set.contacts.enabled = false;  // the cloth is attached to the box's face: coupling only through the attachments
  const auto id = xw.add_system(cloth.model, cloth.state, set);
  for (int i = 0; i < d.nx; ++i) {
    const Vec3 x = scene.positions[g.at(i, 0)];  // box frame = world frame at the start
    xw.attach(id, g.at(i, 0), box, bt(x));
  }

  const Vec3 p0 = xpbd::linear_momentum(xw.model(id), xw.state(id)) + momentum(*box);
  for (int k = 0; k < 60; ++k) bw.step();  // 1 s
  const Vec3 pb = momentum(*box);
  const Vec3 pc = xpbd::linear_momentum(xw.model(id), xw.state(id));
  const Vec3 p1 = pb + pc;
  std::printf("before %.6g kg m/s; after: box %.6g + cloth %.6g = %.6g (|dp|/|p| = %.3g)\n", p0.x(),
              pb.x(), pc.x(), p1.x(), (p1 - p0).norm() / p0.norm());
  EXPECT_LT((p1 - p0).norm(), Real(0.01) * p0.norm());
  // Two-way: the box was dragged. Moving together, box and cloth would
  // share the momentum in the ratio of their masses: the box M/(M + m) = 2/3.
  // Require at least a third of the total.
  EXPECT_GT(pb.x(), p0.x() / 3);
  // The attachments held: every edge particle is still on its box point.
  const btTransform t = box->getCenterOfMassTransform();
  Real gap = 0;
  for (int i = 0; i < d.nx; ++i)
    gap = std::max(gap, (xw.state(id).x[g.at(i, 0)] - vec(t * bt(scene.positions[g.at(i, 0)]))).norm());
  std::printf("largest attachment gap %.3g m\n", gap);
  EXPECT_LT(gap, Real(0.01));
}

// ---------------------------------------------------------------------------
// 4. A rigid box hanging from a light rope: small-swing period.
//
// The rope is an xpbd chain of n particles, the first one kinematic (mass 0,
// pinned at the pivot); the last one is attached to the box's centre of mass
// with XpbdWorld::attach. The rope's pull then acts through the centre of
// mass, so it exerts no torque on the box: the box translates like a point
// mass at the end of the rope, and its moment of inertia plays no role.
//
// Reference: the rope's mass is not zero, so the system is a compound
// pendulum. For a straight (rigid) chain swinging about the pivot, with
// point masses m_k at distance r_k (the rope particles, and the box + last
// particle at L),
//   T0 = 2 pi sqrt(I / (g S)),  I = sum m_k r_k^2,  S = sum m_k r_k,
// which reduces to 2 pi sqrt(L/g) for a massless rope. Finite amplitude
// theta0 lengthens it by the factor 1 + theta0^2/16 (+ O(theta0^4)).

struct PendulumResult {
  Real period = 0;        // s, mean over the measured swings
  int swings = 0;
  Real mean_length = 0;   // m, mean distance pivot - box over the run
  Real max_spin = 0;      // rad/s, largest angular speed of the box
};

PendulumResult swing_box(int n, Real spacing, Real rope_mass, Real M, Real theta0, int substeps,
                         int iterations, Real seconds) {
  BulletWorld bw;
  const Vec3 pivot(0, 2, 0);
  const Vec3 dir(std::sin(theta0), -std::cos(theta0), 0);
  const Real L = spacing * Real(n - 1);
  const Real a = Real(0.05);  // m, box half extent
  btRigidBody* box = bw.add_body(new btBoxShape(btVector3(a, a, a)), M, BulletWorld::at(pivot + L * dir));
  XpbdWorld xw(bw.world());

  xpbd::SceneDesc scene;
  xpbd::RopeDesc r;
  r.n = n;
  r.start = pivot;
  r.dir = dir;
  r.spacing = spacing;
  r.mass = rope_mass / Real(n - 1);
  r.pin_first = true;
  const Index first = xpbd::add_rope(scene, r);
  System rope = make_system(scene);
  SystemSettings set;
  set.substeps = substeps;
  set.iterations = iterations;
  set.contacts.enabled = false;
  const auto id = xw.add_system(rope.model, rope.state, set);
  xw.attach(id, first + n - 1, box, btVector3(0, 0, 0));

  std::vector<Real> t, x;
  PendulumResult res;
  const int steps = static_cast<int>(std::lround(seconds / kDt));
  for (int k = 0; k < steps; ++k) {
    bw.step();
    const Vec3 c = vec(box->getCenterOfMassPosition());
    t.push_back(Real(k + 1) * kDt);
    x.push_back(c.x());
    res.mean_length += (c - pivot).norm() / Real(steps);
    res.max_spin = std::max(res.max_spin, Real(box->getAngularVelocity().length()));
  }
  const std::vector<Real> up = upward_crossings(t, x, 0);
  res.swings = static_cast<int>(up.size()) - 1;
  if (res.swings > 0) res.period = (up.back() - up.front()) / Real(res.swings);
  return res;
}

TEST(WorldCoupling, BoxOnRopeSwingsWithPendulumPeriod) {
  const int n = 11;              // rope particles, 10 segments
  const Real spacing = Real(0.1), L = spacing * Real(n - 1);  // m: a 1 m rope
  const Real rope_mass = Real(0.02), M = 1;                   // kg: the rope is 2% of the box
  const Real theta0 = Real(5) * kPi / 180;
  const PendulumResult r = swing_box(n, spacing, rope_mass, M, theta0, 20, 4, Real(12));

  // Compound-pendulum reference (see above). Rope particles k = 1..n-1 at
  // r_k = k spacing carry rope_mass/(n-1) each; the box sits at L.
  Real I = M * L * L, S = M * L;
  const Real mk = rope_mass / Real(n - 1);
  for (int k = 1; k < n; ++k) {
    const Real rk = spacing * Real(k);
    I += mk * rk * rk;
    S += mk * rk;
  }
  const Real T_point = 2 * kPi * std::sqrt(L / kG);
  const Real T_ref = 2 * kPi * std::sqrt(I / (kG * S)) * (1 + theta0 * theta0 / 16);
  std::printf("period %.6g s over %d swings; point-mass 2 pi sqrt(L/g) = %.6g s, corrected %.6g s "
              "(error %.3g%%); mean pivot-box distance %.6g m (rope %.3g m); max box spin %.3g rad/s\n",
              r.period, r.swings, T_point, T_ref, 100 * (r.period / T_ref - 1), r.mean_length, L,
              r.max_spin);
  ASSERT_GE(r.swings, 4);
  // 2%: the requirement. Known contributions, all smaller: the mass and
  // amplitude corrections are in T_ref (they are -0.3% and +0.05%); the
  // rope's stretch under the box's weight (printed as the mean pivot-box
  // distance) lengthens T by half its relative stretch; backward Euler's
  // phase error at h = 1/1200 s is (omega h)^2/3 ~ 3e-7. The rope's stretch
  // is Gauss-Seidel's unconverged stiffness at a 500:1 mass ratio (1 kg box,
  // 2 g particles): ~0.8% at 20 substeps x 4 iterations (T +0.4%), ~14% at
  // the default 10 x 1 (T +6%), hence the settings above.
  EXPECT_NEAR(r.period, T_ref, Real(0.02) * T_ref);
  // Pulled through its centre of mass, the box does not start spinning.
  EXPECT_LT(r.max_spin, Real(1e-6));
}

// ---------------------------------------------------------------------------
// 3. Trampoline: a ball of 100 times the cloth's mass dropped onto a cloth
// pinned at its four corners. It must not tunnel and must come to rest on
// the cloth.

// Height (m) of the cloth surface below the point (x, z): the triangle of
// the grid whose horizontal projection contains (x, z), interpolated
// barycentrically. Returns false if no triangle covers (x, z).
bool cloth_height_below(const xpbd::ClothGrid& g, const xpbd::State& s, Real x, Real z, Real& y) {
  for (const xpbd::Triangle& t : g.triangles) {
    const Vec3 &a = s.x[t[0]], &b = s.x[t[1]], &c = s.x[t[2]];
    // Barycentric coordinates in the xz plane.
    const Real d = (b.z() - c.z()) * (a.x() - c.x()) + (c.x() - b.x()) * (a.z() - c.z());
    if (std::abs(d) < Real(1e-12)) continue;
    const Real l0 = ((b.z() - c.z()) * (x - c.x()) + (c.x() - b.x()) * (z - c.z())) / d;
    const Real l1 = ((c.z() - a.z()) * (x - c.x()) + (a.x() - c.x()) * (z - c.z())) / d;
    const Real l2 = 1 - l0 - l1;
    if (l0 < 0 || l1 < 0 || l2 < 0) continue;
    y = l0 * a.y() + l1 * b.y() + l2 * c.y();
    return true;
  }
  return false;
}

// A 10 kg ball on 441 particles of 0.23 mg is a 43000:1 mass ratio per
// contact. What it takes (docs/bullet-bridge.md, "Heavy bodies on light
// cloth"): symmetric Gauss-Seidel (SystemSettings::alternate_sweeps; with a
// fixed order the ball walked towards the rows solved first and off the
// cloth within 2 s) and 200 sweeps per frame as 20 substeps x 10 iterations
// (at 10 x 1 and at 20 x 1 the cloth does not converge, stretches under the
// ball and lets it through).
TEST(WorldCoupling, HeavyBallOnTrampolineDoesNotTunnelAndComesToRest) {
  BulletWorld bw;
  const Real m_cloth = Real(0.1), M = 100 * m_cloth, R = Real(0.15);  // kg, kg, m
  const Real drop = Real(0.1);  // m, height of the ball's bottom above the cloth
  btRigidBody* ball = bw.add_body(new btSphereShape(R), M, BulletWorld::at(Vec3(0, drop + R, 0)));
  // Air drag on the ball (Bullet's damping: v *= (1 - 0.5)^t, t in s). The
  // cloth's constraint damping alone dissipates little of a heavy ball's
  // energy: with it only, the ball's centre still moved between y = -0.19 m
  // and 0 after 12 s (measured), far from rest.
  ball->setDamping(Real(0.5), Real(0.5));
  XpbdWorld xw(bw.world());

  // The trampoline: 1 m x 1 m, pinned at the corners, stretch and shear
  // compliance 1e-5 m/N with constraint damping 10 N s/m.
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc d;
  d.nx = d.ny = 21;
  d.size_u = d.size_v = 1;
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();
  d.origin = Vec3(Real(-0.5), 0, Real(-0.5));
  d.mass = m_cloth;
  d.pins = xpbd::ClothPins::all_corners;
  d.stretch = d.shear_mat = xpbd::Material{Real(1e-5), Real(10), 1};
  d.bend_mat.compliance = Real(1e-2);
  const xpbd::ClothGrid g = xpbd::add_cloth_grid(scene, d);
  System cloth = make_system(scene);
  SystemSettings set;
  set.substeps = 20;
  set.iterations = 10;
  set.alternate_sweeps = true;
  const auto id = xw.add_system(cloth.model, cloth.state, set);

  Real worst = 1e9;  // smallest (ball centre - cloth surface below it), m
  std::vector<Vec3> pos;
  const int steps = 15 * 60;
  for (int k = 0; k < steps; ++k) {
    bw.step();
    const Vec3 c = vec(ball->getCenterOfMassPosition());
    pos.push_back(c);
    Real y;
    // The ball stays over the cloth (a ball that walks off the edge has not
    // come to rest on it either).
    ASSERT_TRUE(cloth_height_below(g, xw.state(id), c.x(), c.z(), y)) << "ball left the cloth at step " << k;
    worst = std::min(worst, c.y() - y);
  }
  // Extent of the ball's centre over the last 2 s (largest of max - min
  // per axis), m.
  Vec3 lo = pos.back(), hi = pos.back();
  for (int k = steps - 120; k < steps; ++k) {
    lo = lo.cwiseMin(pos[k]);
    hi = hi.cwiseMax(pos[k]);
  }
  const Real extent = (hi - lo).maxCoeff();
  const xpbd::Strain strain = xpbd::distance_strain(xw.model(id), xw.state(id));
  std::printf("ball centre - cloth below: min %.4g m (radius %.3g); extent of its motion over the "
              "last 2 s %.3g m; final centre (%.4g %.4g %.4g); edge strain max %.3g mean %.3g\n",
              worst, R, extent, pos.back().x(), pos.back().y(), pos.back().z(), strain.max,
              strain.mean);
  // No tunnelling: the ball's centre never gets below the cloth surface
  // under it.
  EXPECT_GT(worst, 0);
  // At rest: over the last 2 s of 15 the centre stays inside a 1 cm box
  // (a mean speed below 0.5% of the impact speed sqrt(2 g drop) = 1.4 m/s).
  // Two seconds because the ball and the cloth settle through a slow
  // vertical oscillation (period ~3 s, measured) that one second samples at
  // an arbitrary phase: at 10 s the float build still moved 1.3 cm in the
  // last second, the double build 0.6 cm. (Bullet's
  // step-end velocity is not used: with gravity applied once per step and
  // the contact correcting it over the substeps, a resting body ends each
  // step with the velocity of the last substep, a fraction of g dt = 0.16
  // m/s; see docs/bullet-bridge.md.)
  EXPECT_LT(extent, Real(0.01));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

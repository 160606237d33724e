// The generic projection (solve.hpp), checked one projection at a time
// against hand-derived closed forms, and XPBD constraint damping.
//
// Every test here runs ONE step with ONE substep and zero gravity and zero
// initial velocity unless stated: the prediction then leaves x unchanged
// (x += h*0), and the step applies exactly `iterations` projections.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

StepConfig one_substep(Real dt, int iterations, Method method = Method::xpbd) {
  StepConfig c;
  c.dt = dt;
  c.substeps = 1;
  c.iterations = iterations;
  c.method = method;
  c.gravity.setZero();
  return c;
}

// Two particles at a and a + len*u (u unit, generic direction), masses m1, m2.
struct Pair {
  Vec3 a = Vec3(Real(0.1), Real(-0.2), Real(0.3));
  Vec3 u = Vec3(Real(2), Real(-1), Real(2)) / Real(3);  // unit
  Real len = Real(1.5);                                 // m
  Real m1 = 2, m2 = Real(0.5);                          // kg
};

// Round-off bound for positions of magnitude ~2 m after a handful of
// floating-point operations.
const Real kPosTol = 64 * kEps * 2;

// XPBD, one projection of a distance constraint (Macklin et al. 2016 eq. 18
// with lambda = 0 at the start of the substep):
//   dlambda = -C / (w1 + w2 + alpha/h^2),   dx_i = w_i * grad_i C * dlambda,
// grad_1 C = (x1 - x2)/|x1 - x2| = -u, grad_2 C = u. So particle 1 moves
// along +u by w1 C/(w1 + w2 + alpha/h^2), particle 2 along -u by w2 C/(...).
TEST(Projection, XpbdDistanceTwoMassesCompliant) {
  const Pair p;
  const Real rest = 1, alpha = Real(0.01), h = Real(0.05);  // m, m/N, s
  SceneDesc sd;
  sd.add_particle(p.a, p.m1);
  sd.add_particle(p.a + p.len * p.u, p.m2);
  sd.distances.push_back(DistanceDesc{0, 1, rest, Material{alpha, 0, 1}});
  const Model m = compile(sd);
  State s = make_state(m);
  step(m, s, one_substep(h, 1));

  const Real w1 = 1 / p.m1, w2 = 1 / p.m2, C = p.len - rest;
  const Real den = w1 + w2 + alpha / (h * h);  // 0.5 + 2 + 4 = 6.5
  EXPECT_LT((s.x[0] - (p.a + (w1 * C / den) * p.u)).norm(), kPosTol);
  EXPECT_LT((s.x[1] - (p.a + p.len * p.u - (w2 * C / den) * p.u)).norm(), kPosTol);
  // lambda = -C/den; force estimate lambda/h^2 (negative = tension).
  EXPECT_NEAR(s.lambdas<Distance>()[0], -C / den, 16 * kEps);
  EXPECT_NEAR(constraint_force<Distance>(s, 0), -C / den / (h * h), 16 * kEps / (h * h));
  // Velocity = displacement / h.
  EXPECT_LT((s.v[0] - (w1 * C / den / h) * p.u).norm(), kPosTol / h);
}

// XPBD with compliance: one more iteration must not move anything, because
// the two-particle distance constraint is linear along its own axis and the
// first projection already satisfies C + alpha/h^2 lambda = 0. This is the
// "converged XPBD" the validation tests rely on.
TEST(Projection, XpbdDistanceConvergesInOneIteration) {
  const Pair p;
  const Real rest = 1, alpha = Real(0.01), h = Real(0.05);
  SceneDesc sd;
  sd.add_particle(p.a, p.m1);
  sd.add_particle(p.a + p.len * p.u, p.m2);
  sd.distances.push_back(DistanceDesc{0, 1, rest, Material{alpha, 0, 1}});
  const Model m = compile(sd);
  State s1 = make_state(m), s5 = make_state(m);
  step(m, s1, one_substep(h, 1));
  step(m, s5, one_substep(h, 5));
  EXPECT_LT((s1.x[0] - s5.x[0]).norm(), kPosTol);
  EXPECT_LT((s1.x[1] - s5.x[1]).norm(), kPosTol);
  // Residual C + alpha/h^2 lambda = 0 after the iterations.
  const Real C = (s5.x[0] - s5.x[1]).norm() - rest;
  EXPECT_NEAR(C + alpha / (h * h) * s5.lambdas<Distance>()[0], 0, 64 * kEps);
}

// PBD, one projection with stiffness k (proper inverse-mass weighting):
//   dx_i = -k C w_i / (w1 + w2) * grad_i C,
// independent of h.
TEST(Projection, PbdDistanceStiffness) {
  const Pair p;
  const Real rest = 1, k = Real(0.3);
  SceneDesc sd;
  sd.add_particle(p.a, p.m1);
  sd.add_particle(p.a + p.len * p.u, p.m2);
  sd.distances.push_back(DistanceDesc{0, 1, rest, Material{0, 0, k}});
  const Model m = compile(sd);
  for (Real h : {Real(0.001), Real(0.1)}) {
    State s = make_state(m);
    step(m, s, one_substep(h, 1, Method::pbd));
    const Real w1 = 1 / p.m1, w2 = 1 / p.m2, C = p.len - rest;
    EXPECT_LT((s.x[0] - (p.a + (k * C * w1 / (w1 + w2)) * p.u)).norm(), kPosTol) << "h " << h;
    EXPECT_LT((s.x[1] - (p.a + p.len * p.u - (k * C * w2 / (w1 + w2)) * p.u)).norm(), kPosTol)
        << "h " << h;
  }
  // Two PBD iterations leave (1-k)^2 of the violation: the stiffness compounds
  // with the iteration count (what PBD mode exists to show).
  State s = make_state(m);
  step(m, s, one_substep(Real(0.01), 2, Method::pbd));
  const Real C2 = (s.x[1] - s.x[0]).norm() - rest;
  EXPECT_NEAR(C2, (1 - k) * (1 - k) * (p.len - rest), kPosTol);
}

// Inequality collision, compliance 0. Radii 0.3 and 0.2: contact distance 0.5.
SceneDesc collision_pair(Real separation) {
  SceneDesc sd;
  const Pair p;
  sd.add_particle(p.a, p.m1, Real(0.3));
  sd.add_particle(p.a + separation * p.u, p.m2, Real(0.2));
  sd.collisions.push_back(CollisionDesc{0, 1, {}});
  return sd;
}

TEST(Projection, CollisionSeparatedDoesNothing) {
  const Model m = compile(collision_pair(Real(0.6)));
  State s = make_state(m);
  step(m, s, one_substep(Real(0.01), 3));
  EXPECT_EQ(s.x[0], m.x0[0]);
  EXPECT_EQ(s.x[1], m.x0[1]);
  EXPECT_EQ(s.lambdas<Collision>()[0], Real(0));
}

// Overlap 0.15 m: C = 0.35 - 0.5 < 0. One projection with compliance 0:
// dlambda = -C/(w1 + w2) > 0 and C becomes exactly 0: the particles end at the
// contact distance, displaced in proportion to their inverse masses (so the
// centre of mass does not move).
TEST(Projection, CollisionOverlappingPushesToContactDistance) {
  const Pair p;
  const Model m = compile(collision_pair(Real(0.35)));
  State s = make_state(m);
  step(m, s, one_substep(Real(0.01), 1));
  EXPECT_NEAR((s.x[1] - s.x[0]).norm(), Real(0.5), kPosTol);
  const Real w1 = 1 / p.m1, w2 = 1 / p.m2, C = Real(0.35) - Real(0.5);
  EXPECT_LT((s.x[0] - (p.a + (w1 * C / (w1 + w2)) * p.u)).norm(), kPosTol);  // pushed along -u
  const Vec3 com0 = (p.m1 * m.x0[0] + p.m2 * m.x0[1]) / (p.m1 + p.m2);
  const Vec3 com1 = (p.m1 * s.x[0] + p.m2 * s.x[1]) / (p.m1 + p.m2);
  EXPECT_LT((com1 - com0).norm(), kPosTol);
  EXPECT_GT(s.lambdas<Collision>()[0], Real(0));  // pushes only
  // Further iterations keep it there (C = 0, lambda > 0: active, dlambda = 0).
  State s3 = make_state(m);
  step(m, s3, one_substep(Real(0.01), 3));
  EXPECT_NEAR((s3.x[1] - s3.x[0]).norm(), Real(0.5), kPosTol);
}

// Wall: plane with (non-unit) normal (1,2,2), i.e. unit n = (1,2,2)/3, offset
// 0.5, particle radius 0.1. A particle with n.x = 0.2 (penetrating) is pushed
// along n to n.x = offset + radius = 0.6; its tangential part is unchanged.
// A particle on the free side is not touched.
TEST(Projection, WallPushesToOffsetPlusRadius) {
  const Vec3 n = Vec3(1, 2, 2) / Real(3);
  const Vec3 t = Vec3(2, -2, 1) / Real(3);  // unit, orthogonal to n
  SceneDesc sd;
  sd.add_particle(Real(0.2) * n + Real(0.7) * t, 1, Real(0.1));
  sd.add_particle(Real(0.65) * n - Real(0.3) * t, 1, Real(0.1));
  sd.planes.push_back(PlaneDesc{Vec3(1, 2, 2), Real(0.5), {}});
  const Model m = compile(sd);
  State s = make_state(m);
  step(m, s, one_substep(Real(0.01), 1));
  EXPECT_NEAR(n.dot(s.x[0]), Real(0.6), kPosTol);
  EXPECT_NEAR(t.dot(s.x[0]), Real(0.7), kPosTol);
  EXPECT_EQ(s.x[1], m.x0[1]);
}

// Wall under gravity: a particle resting on the plane stays exactly at
// n.x = offset + radius (the projection removes the predicted h^2 g dip each
// substep), and a falling particle ends on the plane after impact.
TEST(Projection, WallHoldsParticleUnderGravity) {
  SceneDesc sd;
  sd.add_particle(Vec3(0, Real(-0.9), 0), 1, Real(0.1));         // resting: -1 + 0.1
  sd.add_particle(Vec3(Real(0.5), Real(0.2), 0), 1, Real(0.1));  // falls 1.1 m
  sd.planes.push_back(PlaneDesc{Vec3::UnitY(), Real(-1), {}});
  const Model m = compile(sd);
  State s = make_state(m);
  const StepConfig cfg;  // gravity -9.81 y, 10 substeps
  for (int n = 0; n < 120; ++n) {
    step(m, s, cfg);
    ASSERT_NEAR(s.x[0].y(), Real(-0.9), kPosTol) << "step " << n;
    ASSERT_GE(s.x[1].y(), Real(-0.9) - kPosTol) << "step " << n;
  }
  // After 2 s the second particle (impact at ~0.47 s, no restitution) rests too.
  EXPECT_NEAR(s.x[1].y(), Real(-0.9), kPosTol);
}

// ---------------------------------------------------------------------------
// XPBD damping (Macklin et al. 2016, eq. 26)

// The 1-D spring of test::Spring1D: m = 1 kg, rest 1 m, u0 = 0.5 m,
// alpha = 1e-3 m/N (k = 1000 N/m, omega = 31.6 rad/s). Returns u_n = x - rest
// and the energy E = m v^2/2 + C^2/(2 alpha) after every step.
struct SpringRun {
  std::vector<Real> u, energy;
};

SpringRun run_spring(Real damping, int steps, const StepConfig& cfg) {
  test::Spring1D sp;
  sp.mat = Material{Real(1e-3), damping, 1};
  const Model m = compile(test::spring_scene(sp));
  State s = make_state(m);
  SpringRun r;
  auto record = [&] {
    const Real C = s.x[1].x() - sp.rest;
    r.u.push_back(C);
    r.energy.push_back(Real(0.5) * sp.m * s.v[1].squaredNorm() +
                       C * C / (2 * sp.mat.compliance));
  };
  record();
  for (int n = 0; n < steps; ++n) {
    step(m, s, cfg);
    record();
  }
  return r;
}

Real max_abs_tail(const std::vector<Real>& u, std::size_t from) {
  Real a = 0;
  for (std::size_t i = from; i < u.size(); ++i) a = std::max(a, std::abs(u[i]));
  return a;
}

// Converged XPBD with damping beta is backward Euler for
//   m u'' = -k u - beta u'
// (the fixed point of eq. 26 is C + alpha/h^2 lambda + alpha beta/h dC = 0,
// i.e. the force lambda/h^2 = -C/alpha - beta dC/h). For that scheme, with
// u' = u_{n+1} - u_n = h v', v' = v_{n+1}:
//   m (v' - v) = -h k u' - h beta v'
// and multiplying by v' gives the exact energy balance
//   E_{n+1} - E_n = -m/2 (dv)^2 - k/2 (du)^2 - h beta v'^2 <= 0,
// so the energy never grows, and strictly more is lost with beta > 0.
TEST(Damping, DecaysFasterAndEnergyNeverGrows) {
  StepConfig cfg = one_substep(Real(1) / Real(600), 1);
  const int steps = 600;  // 1 s, about 5 periods
  const SpringRun free = run_spring(0, steps, cfg);
  const SpringRun damped = run_spring(Real(2), steps, cfg);  // N s/m, 3% of critical
  // Energy: non-increasing up to the round-off of E (a few eps * E0).
  const Real e_tol = 16 * kEps * free.energy[0];
  for (std::size_t n = 1; n < free.energy.size(); ++n) {
    ASSERT_LE(free.energy[n], free.energy[n - 1] + e_tol) << "undamped, step " << n;
    ASSERT_LE(damped.energy[n], damped.energy[n - 1] + e_tol) << "damped, step " << n;
  }
  // Amplitude over the last period: damped decays by exp(-beta/(2m) t) more.
  // With beta = 2, t = 1 s that is a factor e^-1; demand at least 0.5.
  const std::size_t last = free.u.size() - 120;
  EXPECT_LT(max_abs_tail(damped.u, last), Real(0.5) * max_abs_tail(free.u, last));
}

// The damped trajectory itself matches the backward-Euler recurrence above,
// evaluated independently in long double:
//   v' = (m v - h k u) / (m + h beta + h^2 k),  u' = u + h v'.
TEST(Damping, MatchesBackwardEulerWithViscousForce) {
  const Real beta = Real(2), k = Real(1000), mass = 1;
  const int substeps = 4;
  StepConfig cfg = one_substep(Real(1) / Real(150), 1);
  cfg.substeps = substeps;
  const SpringRun run = run_spring(beta, 300, cfg);
  const long double h = static_cast<long double>(cfg.dt) / substeps;
  long double u = 0.5L, v = 0;
  Real worst = 0;
  for (std::size_t n = 1; n < run.u.size(); ++n) {
    for (int j = 0; j < substeps; ++j) {
      v = (mass * v - h * k * u) / (mass + h * beta + h * h * k);
      u = u + h * v;
    }
    worst = std::max(worst, std::abs(run.u[n] - static_cast<Real>(u)));
  }
  // Round-off only: each substep rounds u (~eps * 1.5 m), and the map is a
  // contraction, so errors stay at ~steps * substeps * eps * 1.5.
  EXPECT_LT(worst, 1200 * kEps * Real(1.5)) << "worst |u - u_ref| " << worst;
}

// Damping on a zero-compliance constraint has no effect (gamma = alpha beta/h
// = 0), as documented on Material::damping.
TEST(Damping, NoEffectOnRigidConstraint) {
  SceneDesc a, b;
  for (SceneDesc* sd : {&a, &b}) {
    sd->add_particle(Vec3::Zero(), 0);
    sd->add_particle(Vec3(1, 0, 0), 1, 0, Vec3(0, 2, 0));
  }
  a.distances.push_back(DistanceDesc{0, 1, std::nullopt, Material{0, 0, 1}});
  b.distances.push_back(DistanceDesc{0, 1, std::nullopt, Material{0, Real(50), 1}});
  const Model ma = compile(a), mb = compile(b);
  State sa = make_state(ma), sb = make_state(mb);
  const StepConfig cfg;
  for (int n = 0; n < 30; ++n) {
    step(ma, sa, cfg);
    step(mb, sb, cfg);
  }
  EXPECT_EQ(sa.x[1], sb.x[1]);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd

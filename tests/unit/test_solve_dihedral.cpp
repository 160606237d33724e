// The dihedral bending kernel (solve_dihedral.hpp) against the generic,
// eval()-based projection of the same elements: they must agree to
// round-off on any input, with damping, PBD, kinematic particles, reversed
// sweeps and degenerate hinges. A closed-form check of the physics: a
// rigid hinge is brought to its rest angle by one projection.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <span>
#include <vector>

#include "support/xpbd_test.hpp"
#include "xpbd/solve.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

struct Hinges {
  std::vector<Vec3> x, x_prev;
  std::vector<Real> inv_mass;
  std::vector<DihedralBending> cs;
};

// The hinges of a 12 x 12 dihedral cloth grid, its particles moved at
// random by up to 0.3 of the spacing (hinges bent both ways), rest angles
// within 1 rad of the angle they start at (both signs of C, away from the
// wrap at +-pi), every 7th particle kinematic, and a degenerate hinge.
Hinges make_hinges(Method method, bool damped) {
  SceneDesc scene;
  ClothGridDesc d;
  d.nx = d.ny = 12;
  d.set_bending(ClothBending::dihedral, Material{Real(1e-2), damped ? Real(0.5) : Real(0), Real(0.7)});
  add_cloth_grid(scene, d);
  const Model m = compile(scene);
  std::mt19937 rng(4321);
  const Real spacing = Real(1) / Real(d.nx - 1);
  std::uniform_real_distribution<Real> jitter(-Real(0.3) * spacing, Real(0.3) * spacing);
  std::uniform_real_distribution<Real> turn(-1, 1);
  Hinges h;
  for (Index i = 0; i < m.num_particles(); ++i) {
    const Vec3 p = m.x0[std::size_t(i)] + Vec3(jitter(rng), jitter(rng), jitter(rng));
    h.x.push_back(p);
    h.x_prev.push_back(p - Real(0.1) * Vec3(jitter(rng), jitter(rng), jitter(rng)));
    h.inv_mass.push_back(i % 7 == 0 ? Real(0) : m.inv_mass[std::size_t(i)]);
  }
  // First, a degenerate hinge of four extra kinematic particles (they stay
  // put), its wing on its edge's line: skipped by both kernels, so its
  // multiplier stays 0 (a kernel that projected it would change lambda).
  const Index e = m.num_particles();
  for (const Vec3& p : {Vec3(2, 0, 0), Vec3(3, 0, 0), Vec3(Real(2.5), 0, 0), Vec3(Real(2.5), 1, 0)}) {
    h.x.push_back(p);
    h.x_prev.push_back(p);
    h.inv_mass.push_back(0);
  }
  DihedralBending degenerate = m.get<DihedralBending>().front();
  degenerate.p = {e, e + 1, e + 2, e + 3};
  h.cs.push_back(degenerate);
  for (const DihedralBending& c : m.get<DihedralBending>()) h.cs.push_back(c);
  for (DihedralBending& c : h.cs) {
    Real phi = 0;
    if (DihedralBending::angle(c.p, h.x.data(), phi)) c.rest_angle = phi + turn(rng);
    if (method == Method::pbd) c.mat.stiffness = Real(0.7);
  }
  return h;
}

SolveContext context(Hinges& h, Real step, Method method, bool reverse) {
  SolveContext sc;
  sc.x = h.x.data();
  sc.x_prev = h.x_prev.data();
  sc.inv_mass = h.inv_mass.data();
  sc.h = step;
  sc.method = method;
  sc.reverse = reverse;
  sc.eval.x = h.x.data();
  return sc;
}

void check_agrees_with_generic(Method method, bool damped, bool reverse) {
  const Hinges start = make_hinges(method, damped);
  Hinges fast = start, generic = start;
  std::vector<Real> l_fast(start.cs.size(), Real(0)), l_generic(start.cs.size(), Real(0));
  const Real step = Real(1) / Real(600);
  const SolveContext sc_fast = context(fast, step, method, reverse);
  const SolveContext sc_generic = context(generic, step, method, reverse);
  const std::span<const DihedralBending> cs(start.cs);
  for (int sweep = 0; sweep < 4; ++sweep) {
    if (damped) {
      project_all<DihedralBending, true>(cs, std::span<Real>(l_fast), sc_fast);
      project_all_generic<DihedralBending, true>(cs, std::span<Real>(l_generic), sc_generic);
    } else {
      project_all<DihedralBending, false>(cs, std::span<Real>(l_fast), sc_fast);
      project_all_generic<DihedralBending, false>(cs, std::span<Real>(l_generic), sc_generic);
    }
  }
  // Tolerance: the kernels differ in association (the sine's triple
  // product, |g|^2 from the areas), a few ulp per projection on
  // coordinates of O(1) m; Gauss-Seidel carries each difference into the
  // next projections (4 sweeps over 220 hinges). 1024 ulp of 1 m. A wrong
  // sign, gradient or weight moves particles by O(spacing) = O(0.01) m
  // here (the sweeps move them by more than 1e-3 m, checked below).
  const Real tol = Real(1024) * kEps;
  Real moved = 0, diff = 0;
  for (std::size_t i = 0; i < start.x.size(); ++i) {
    moved = std::max(moved, (generic.x[i] - start.x[i]).norm());
    diff = std::max(diff, (fast.x[i] - generic.x[i]).norm());
  }
  EXPECT_TRUE(test::all_finite(fast.x));
  EXPECT_GT(moved, Real(1e-3));
  EXPECT_LT(diff, tol) << "positions moved up to " << moved << " m";
  Real lmax = 0, ldiff = 0;
  for (std::size_t k = 0; k < cs.size(); ++k) {
    lmax = std::max(lmax, std::abs(l_generic[k]));
    ldiff = std::max(ldiff, std::abs(l_fast[k] - l_generic[k]));
  }
  EXPECT_GT(lmax, Real(0));
  EXPECT_LT(ldiff, tol * std::max(lmax, Real(1)));
  // The degenerate hinge is skipped by both.
  EXPECT_EQ(l_fast[0], Real(0));
  EXPECT_EQ(l_generic[0], Real(0));
}

TEST(DihedralKernel, AgreesWithGenericXpbd) { check_agrees_with_generic(Method::xpbd, false, false); }
TEST(DihedralKernel, AgreesWithGenericXpbdDamped) { check_agrees_with_generic(Method::xpbd, true, false); }
TEST(DihedralKernel, AgreesWithGenericPbd) { check_agrees_with_generic(Method::pbd, false, false); }
TEST(DihedralKernel, AgreesWithGenericReversed) { check_agrees_with_generic(Method::xpbd, false, true); }

// A rigid hinge (alpha = 0) folded by 0.3 rad from its rest angle, with
// kinematic edge particles and equal wing masses: the constraint is not
// linear, so one projection brings it close to rest, and a few more to rest
// (Newton-like convergence of the Gauss-Seidel steps on one element).
TEST(DihedralKernel, RigidHingeReachesItsRestAngle) {
  Hinges h;
  h.x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(Real(0.5), 1, 0), Vec3(Real(0.5), -std::cos(Real(0.3)), std::sin(Real(0.3)))};
  h.x_prev = h.x;
  h.inv_mass = {0, 0, 1, 1};
  DihedralBending c;
  c.p = {0, 1, 2, 3};
  c.rest_angle = 0;
  h.cs = {c};
  Real phi0 = 0;
  ASSERT_TRUE(DihedralBending::angle(c.p, h.x.data(), phi0));
  EXPECT_NEAR(std::abs(phi0), Real(0.3), 64 * kEps);
  std::vector<Real> lambda(1, Real(0));
  const SolveContext sc = context(h, Real(0.01), Method::xpbd, false);
  for (int it = 0; it < 5; ++it)
    project_all<DihedralBending, false>(std::span<const DihedralBending>(h.cs), std::span<Real>(lambda), sc);
  Real phi = 1;
  ASSERT_TRUE(DihedralBending::angle(c.p, h.x.data(), phi));
  EXPECT_NEAR(phi, Real(0), Real(1e-5));
  // The edge did not move; the wings stayed at their distances from it.
  EXPECT_EQ(h.x[0], Vec3::Zero());
  EXPECT_EQ(h.x[1], Vec3(1, 0, 0));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd

// The pair-distance kernel of solve.hpp (Distance, Collision, Tether).
//
// project_all() sends these types to a kernel written out for
// C = sign*(|x_a - x_b| - rest); every other type goes through the generic,
// eval()-based projection. The two must agree to round-off on any input,
// including inequalities with clamped multipliers, damping, PBD, kinematic
// particles and degenerate (coincident) pairs. Closed-form single
// projections check the physics directly (the generic kernel's own closed
// forms live in test_solve.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <vector>

#include "support/xpbd_test.hpp"
#include "xpbd/solve.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

template <class T>
T make_pair(Index a, Index b, Real rest, const Material& mat) {
  T c;
  c.p = {a, b};
  if constexpr (std::is_same_v<T, Tether>)
    c.length = rest;
  else
    c.rest = rest;
  c.mat = mat;
  return c;
}

// A random particle cloud with random pair constraints, projected by both
// kernels from the same start.
struct Cloud {
  std::vector<Vec3> x, x_prev;
  std::vector<Real> inv_mass;
};

Cloud make_cloud(std::mt19937& rng, int n) {
  std::uniform_real_distribution<Real> pos(Real(-0.5), Real(0.5));
  std::uniform_real_distribution<Real> vel(Real(-0.01), Real(0.01));
  std::uniform_real_distribution<Real> mass(Real(0.1), Real(2));
  Cloud c;
  for (int i = 0; i < n; ++i) {
    const Vec3 p(pos(rng), pos(rng), pos(rng));
    c.x.push_back(p);
    c.x_prev.push_back(p - Vec3(vel(rng), vel(rng), vel(rng)));
    c.inv_mass.push_back(i % 5 == 0 ? Real(0) : Real(1) / mass(rng));  // every 5th kinematic
  }
  // Two coincident kinematic particles: the pair between them has no
  // direction, and nothing else moves them apart.
  c.x[n - 1] = c.x[n - 2];
  c.x_prev[n - 1] = c.x_prev[n - 2];
  c.inv_mass[n - 1] = c.inv_mass[n - 2] = 0;
  return c;
}

template <class T>
std::vector<T> make_pairs(std::mt19937& rng, const Cloud& cloud, int m, bool damped) {
  const int n = static_cast<int>(cloud.x.size());
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::uniform_real_distribution<Real> ratio(Real(0.7), Real(1.3));
  std::uniform_real_distribution<Real> stiffness(Real(0.2), Real(1));
  const Real compliances[] = {0, Real(1e-6), Real(1e-3)};  // m/N
  std::vector<T> cs;
  // Coincident pair, compliant so that only the missing direction (not a
  // zero denominator) makes the kernels skip it.
  cs.push_back(make_pair<T>(n - 2, n - 1, Real(0.1), Material{Real(1e-3), 0, 1}));
  while (static_cast<int>(cs.size()) < m) {
    const int a = pick(rng), b = pick(rng);
    if (a == b || (a >= n - 2 && b >= n - 2)) continue;
    Material mat;
    mat.compliance = compliances[cs.size() % 3];
    mat.damping = damped ? Real(5) : Real(0);  // N*s/m
    mat.stiffness = stiffness(rng);
    // Rest 0.7..1.3 times the current distance: both signs of C, so the
    // inequalities are active for some elements and inactive for others.
    cs.push_back(make_pair<T>(a, b, ratio(rng) * (cloud.x[a] - cloud.x[b]).norm(), mat));
  }
  return cs;
}

SolveContext context(Cloud& c, Real h, Method method) {
  SolveContext sc;
  sc.x = c.x.data();
  sc.x_prev = c.x_prev.data();
  sc.inv_mass = c.inv_mass.data();
  sc.h = h;
  sc.method = method;
  sc.eval.x = c.x.data();
  return sc;
}

template <class T>
void check_agrees_with_generic(Method method, bool damped) {
  std::mt19937 rng(12345);
  const Cloud start = make_cloud(rng, 40);
  const std::vector<T> cs = make_pairs<T>(rng, start, 300, damped);
  const Real h = Real(1) / Real(600);  // s
  Cloud fast = start, generic = start;
  std::vector<Real> l_fast(cs.size(), Real(0)), l_generic(cs.size(), Real(0));
  const SolveContext sc_fast = context(fast, h, method);
  const SolveContext sc_generic = context(generic, h, method);
  // Several sweeps, so the second and later see lambda != 0 (the at*lambda
  // term, inequality clamps releasing a contact).
  for (int sweep = 0; sweep < 4; ++sweep) {
    if (damped) {
      project_all<T, true>(std::span<const T>(cs), std::span<Real>(l_fast), sc_fast);
      project_all_generic<T, true>(std::span<const T>(cs), std::span<Real>(l_generic), sc_generic);
    } else {
      project_all<T, false>(std::span<const T>(cs), std::span<Real>(l_fast), sc_fast);
      project_all_generic<T, false>(std::span<const T>(cs), std::span<Real>(l_generic), sc_generic);
    }
  }
  // Tolerance: the kernels evaluate the same formulas in a different
  // association, a few ulp apart per projection on coordinates of O(1) m.
  // Gauss-Seidel feeds each difference into the following projections, each
  // of which is a contraction towards the constraint manifold, so they do
  // not grow much (about 1 ulp after these 1200 projections in double).
  // Allow 256 ulp of 1 m. A wrong formula, sign, order or clamp moves
  // particles by O(0.1) m here (the sweeps move them by > 1e-2 m, checked
  // below), so the test can fail.
  const Real tol = Real(256) * kEps;
  Real moved = 0, diff = 0;
  for (std::size_t i = 0; i < start.x.size(); ++i) {
    moved = std::max(moved, (generic.x[i] - start.x[i]).norm());
    diff = std::max(diff, (fast.x[i] - generic.x[i]).norm());
  }
  EXPECT_TRUE(test::all_finite(fast.x));
  EXPECT_GT(moved, Real(1e-2));
  EXPECT_LT(diff, tol) << "positions moved up to " << moved << " m";
  // lambda in kg*m; |lambda| <~ |C|/(w_a + w_b) ~ 0.5 kg*m here: same scale.
  Real lmax = 0, ldiff = 0;
  for (std::size_t k = 0; k < cs.size(); ++k) {
    lmax = std::max(lmax, std::abs(l_generic[k]));
    ldiff = std::max(ldiff, std::abs(l_fast[k] - l_generic[k]));
  }
  EXPECT_GT(lmax, Real(0));
  EXPECT_LT(ldiff, tol * std::max(lmax, Real(1)));
  // Skipped elements keep lambda = 0 in both: the coincident pair.
  EXPECT_EQ(l_fast[0], Real(0));
  EXPECT_EQ(l_generic[0], Real(0));
}

TEST(PairDistanceKernel, DistanceAgreesWithGenericXpbd) {
  check_agrees_with_generic<Distance>(Method::xpbd, false);
}
TEST(PairDistanceKernel, DistanceAgreesWithGenericXpbdDamped) {
  check_agrees_with_generic<Distance>(Method::xpbd, true);
}
TEST(PairDistanceKernel, DistanceAgreesWithGenericPbd) {
  check_agrees_with_generic<Distance>(Method::pbd, false);
}
TEST(PairDistanceKernel, CollisionAgreesWithGenericXpbd) {
  check_agrees_with_generic<Collision>(Method::xpbd, false);
}
TEST(PairDistanceKernel, CollisionAgreesWithGenericXpbdDamped) {
  check_agrees_with_generic<Collision>(Method::xpbd, true);
}
TEST(PairDistanceKernel, CollisionAgreesWithGenericPbd) {
  check_agrees_with_generic<Collision>(Method::pbd, false);
}
TEST(PairDistanceKernel, TetherAgreesWithGenericXpbd) {
  check_agrees_with_generic<Tether>(Method::xpbd, false);
}
TEST(PairDistanceKernel, TetherAgreesWithGenericXpbdDamped) {
  check_agrees_with_generic<Tether>(Method::xpbd, true);
}
TEST(PairDistanceKernel, TetherAgreesWithGenericPbd) {
  check_agrees_with_generic<Tether>(Method::pbd, false);
}

// One XPBD projection of a rigid (alpha = 0) pair from lambda = 0 solves the
// constraint exactly when C is linear along the pair's line: particle a
// (inverse mass wa) moves by -wa*C/(wa + wb) along g_a, b by -wb*C/(wa + wb)
// along g_b = -g_a. Tether: C = length - |d|, g_a = -d/|d|, so a stretched
// tether pulls a towards b.
TEST(PairDistanceKernel, TetherPullsBackToLength) {
  const Vec3 xa(Real(0.3), Real(-1.2), Real(0.4)), xb(Real(0.1), Real(0.2), Real(-0.1));
  const Real len0 = (xa - xb).norm(), length = Real(0.6) * len0;  // m
  Cloud c{{xa, xb}, {xa, xb}, {Real(0.5), Real(2)}};  // 1/kg
  const std::vector<Tether> cs{make_pair<Tether>(0, 1, length, Material{})};
  std::vector<Real> lambda(1, Real(0));
  project_all<Tether, false>(std::span<const Tether>(cs), std::span<Real>(lambda),
                             context(c, Real(0.01), Method::xpbd));
  const Vec3 n = (xa - xb) / len0;
  const Real C = length - len0, wsum = Real(2.5);
  // Coordinates O(1) m after a few operations: 64 ulp.
  const Real tol = 64 * kEps;
  EXPECT_LT((c.x[0] - (xa - (Real(0.5) * C / wsum) * (-n))).norm(), tol);
  EXPECT_LT((c.x[1] - (xb - (Real(2) * C / wsum) * n)).norm(), tol);
  EXPECT_NEAR((c.x[0] - c.x[1]).norm(), length, tol);
  EXPECT_NEAR(lambda[0], -C / wsum, tol);  // lambda >= 0: the tether pulls
}

TEST(PairDistanceKernel, SlackTetherDoesNothing) {
  const Vec3 xa(Real(0.3), Real(-1.2), Real(0.4)), xb(Real(0.1), Real(0.2), Real(-0.1));
  Cloud c{{xa, xb}, {xa, xb}, {Real(0.5), Real(2)}};
  const std::vector<Tether> cs{make_pair<Tether>(0, 1, Real(2) * (xa - xb).norm(), Material{})};
  std::vector<Real> lambda(1, Real(0));
  project_all<Tether, false>(std::span<const Tether>(cs), std::span<Real>(lambda),
                             context(c, Real(0.01), Method::xpbd));
  EXPECT_EQ(c.x[0], xa);
  EXPECT_EQ(c.x[1], xb);
  EXPECT_EQ(lambda[0], Real(0));
}

// A pair so short that |d|^2 is subnormal (only possible for rest lengths
// below ~1e-154 m in double, ~1e-19 m in float): the kernel must not form
// 1/|d|^2 (it would overflow) and still solve the constraint. Rigid, equal
// masses: one projection brings |d| to rest. |d|^2 loses at most a couple of
// bits to subnormal precision here (it is half the smallest normal), so the
// result is within a few ulp of rest, relatively.
TEST(PairDistanceKernel, SubnormalSquaredLengthStaysFinite) {
  const Real len = std::sqrt(std::numeric_limits<Real>::min() * Real(0.5));
  const Real rest = Real(0.5) * len;
  ASSERT_LT(len * len, std::numeric_limits<Real>::min());
  const Vec3 dir = Vec3(Real(1), Real(2), Real(2)) / Real(3);
  Cloud c{{len * dir, Vec3::Zero()}, {len * dir, Vec3::Zero()}, {Real(1), Real(1)}};
  const std::vector<Distance> cs{make_pair<Distance>(0, 1, rest, Material{})};
  std::vector<Real> lambda(1, Real(0));
  project_all<Distance, false>(std::span<const Distance>(cs), std::span<Real>(lambda),
                               context(c, Real(0.01), Method::xpbd));
  ASSERT_TRUE(test::all_finite(c.x));
  EXPECT_NEAR((c.x[0] - c.x[1]).norm() / rest, Real(1), 64 * kEps);
}

// Both particles kinematic and alpha = 0: the denominator is 0, the element
// is skipped (no division by zero, nothing moves).
TEST(PairDistanceKernel, AllKinematicRigidPairIsSkipped) {
  const Vec3 xa(1, 0, 0), xb(0, 0, 0);
  Cloud c{{xa, xb}, {xa, xb}, {Real(0), Real(0)}};
  const std::vector<Distance> cs{make_pair<Distance>(0, 1, Real(0.5), Material{})};
  std::vector<Real> lambda(1, Real(0));
  for (Method m : {Method::xpbd, Method::pbd})
    project_all<Distance, false>(std::span<const Distance>(cs), std::span<Real>(lambda),
                                 context(c, Real(0.01), m));
  EXPECT_EQ(c.x[0], xa);
  EXPECT_EQ(c.x[1], xb);
  EXPECT_EQ(lambda[0], Real(0));
}

// SolveContext::reverse (StepConfig::alternate_sweeps): a reversed sweep
// over cs is, bit for bit, a forward sweep over cs reversed. Both kernels
// (pair-distance for Distance, generic for the tether's eval() path), with
// several sweeps so that lambda != 0 and clamps are exercised.
template <class T, bool kGeneric>
void check_reverse_is_reversed_order(Method method) {
  std::mt19937 rng(777);
  const Cloud start = make_cloud(rng, 30);
  const std::vector<T> cs = make_pairs<T>(rng, start, 200, true);
  const std::vector<T> rev(cs.rbegin(), cs.rend());
  const Real h = Real(1) / Real(600);  // s
  Cloud a = start, b = start;
  std::vector<Real> la(cs.size(), Real(0)), lb(cs.size(), Real(0));
  SolveContext sa = context(a, h, method);
  sa.reverse = true;
  const SolveContext sb = context(b, h, method);
  for (int sweep = 0; sweep < 3; ++sweep) {
    if constexpr (kGeneric) {
      project_all_generic<T, true>(std::span<const T>(cs), std::span<Real>(la), sa);
      project_all_generic<T, true>(std::span<const T>(rev), std::span<Real>(lb), sb);
    } else {
      project_all<T, true>(std::span<const T>(cs), std::span<Real>(la), sa);
      project_all<T, true>(std::span<const T>(rev), std::span<Real>(lb), sb);
    }
  }
  Real moved = 0;
  for (std::size_t i = 0; i < start.x.size(); ++i) {
    EXPECT_EQ(a.x[i], b.x[i]) << "particle " << i;
    moved = std::max(moved, (a.x[i] - start.x[i]).norm());
  }
  for (std::size_t k = 0; k < cs.size(); ++k) EXPECT_EQ(la[k], lb[cs.size() - 1 - k]) << "element " << k;
  // The order matters here (so the test can fail): a forward sweep over cs
  // ends elsewhere.
  Cloud f = start;
  std::vector<Real> lf(cs.size(), Real(0));
  const SolveContext sf = context(f, h, method);
  for (int sweep = 0; sweep < 3; ++sweep)
    project_all<T, true>(std::span<const T>(cs), std::span<Real>(lf), sf);
  Real order_diff = 0;
  for (std::size_t i = 0; i < start.x.size(); ++i) order_diff = std::max(order_diff, (f.x[i] - a.x[i]).norm());
  EXPECT_GT(moved, Real(1e-2));
  EXPECT_GT(order_diff, Real(1e-4));
}

TEST(PairDistanceKernel, ReverseSweepIsForwardSweepOverReversedElements) {
  for (Method m : {Method::xpbd, Method::pbd}) {
    check_reverse_is_reversed_order<Distance, false>(m);
    check_reverse_is_reversed_order<Tether, false>(m);
    check_reverse_is_reversed_order<Distance, true>(m);
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd

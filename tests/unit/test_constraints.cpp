// Constraint value/gradient functions (constraints.hpp): every type's
// analytic gradient against central finite differences of its own C, at
// random configurations; C against an independent long-double evaluation; and
// the documented "gradient undefined -> eval() returns false" cases.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

// Finite-difference step and tolerance, derived from the precision.
//
// Central difference error for a smooth f: h^2/6 |f'''| (truncation) plus
// about e_C/h (round-off of C, e_C ~ a few eps times the coordinate scale).
// h = eps^(1/3) balances the two, giving an error ~ eps^(2/3) times a
// constant. The configurations below keep |x| <= sqrt(3), rest <= 1.5 and the
// distance between the points >= 0.25, so |f'''| <= 3/0.25^2 = 48 for the
// norm-based C and the constant is below ~16. The tolerance is 64 eps^(2/3):
// 2.4e-9 in double and 1.6e-3 in float. The gradients are unit vectors, so any
// real mistake (sign, wrong normalisation, wrong particle) is an O(1) error.
const Real kFdStep = std::cbrt(kEps);
const Real kFdTol = Real(64) * std::cbrt(kEps) * std::cbrt(kEps);
constexpr int kConfigs = 50;
constexpr Real kMinSeparation = Real(0.25);  // m

// An EvalContext with the fields these four types read (set by member so that
// fields other types add later keep their defaults).
EvalContext context(const Vec3* x, const Vec3* pin_target, const Plane* planes) {
  EvalContext c;
  c.x = x;
  c.pin_target = pin_target;
  c.planes = planes;
  return c;
}

Vec3 random_point(std::mt19937& rng) {
  std::uniform_real_distribution<Real> u(-1, 1);
  return Vec3(u(rng), u(rng), u(rng));
}

// Central FD of C with respect to coordinate j of particle i, for a constraint
// whose positions live in x[]. The step actually taken is (xp - xm), which is
// what it is after rounding, not 2h.
template <class T>
Vec3 fd_gradient(const T& c, Index k, EvalContext ctx, std::vector<Vec3> x, int i) {
  Vec3 g;
  for (int j = 0; j < 3; ++j) {
    const Real x0 = x[c.p[i]][j];
    const Real xp = x0 + kFdStep, xm = x0 - kFdStep;
    Real cp = 0, cm = 0;
    Vec3 unused[T::kArity];
    x[c.p[i]][j] = xp;
    ctx.x = x.data();
    EXPECT_TRUE(T::eval(c, k, ctx, cp, unused));
    x[c.p[i]][j] = xm;
    ctx.x = x.data();
    EXPECT_TRUE(T::eval(c, k, ctx, cm, unused));
    x[c.p[i]][j] = x0;
    g[j] = (cp - cm) / (xp - xm);
  }
  return g;
}

template <class T>
void check_gradient(const T& c, Index k, const EvalContext& base, const std::vector<Vec3>& x) {
  EvalContext ctx = base;
  ctx.x = x.data();
  Real C;
  Vec3 g[T::kArity];
  ASSERT_TRUE(T::eval(c, k, ctx, C, g));
  for (int i = 0; i < T::kArity; ++i) {
    const Vec3 fd = fd_gradient(c, k, ctx, x, i);
    EXPECT_LT((g[i] - fd).norm(), kFdTol)
        << "particle " << i << " analytic " << g[i].transpose() << " fd " << fd.transpose();
  }
}

// Two points at least kMinSeparation apart, and a rest length in [0.5, 1.5].
void random_pair(std::mt19937& rng, std::vector<Vec3>& x, Real& rest) {
  std::uniform_real_distribution<Real> r(Real(0.5), Real(1.5));
  do {
    x = {random_point(rng), random_point(rng)};
  } while ((x[0] - x[1]).norm() < kMinSeparation);
  rest = r(rng);
}

// |a - b| in long double, as an independent reference for C.
long double dist_ld(const Vec3& a, const Vec3& b) {
  long double s = 0;
  for (int j = 0; j < 3; ++j) {
    const long double d = static_cast<long double>(a[j]) - static_cast<long double>(b[j]);
    s += d * d;
  }
  return std::sqrt(s);
}

TEST(ConstraintGradient, DistanceMatchesFiniteDifferences) {
  std::mt19937 rng(12345);
  for (int n = 0; n < kConfigs; ++n) {
    std::vector<Vec3> x;
    Real rest;
    random_pair(rng, x, rest);
    // Swap the order half of the time so that both index slots are exercised.
    const Distance c{{Index(n % 2), Index(1 - n % 2)}, rest, {}};
    check_gradient(c, 0, EvalContext{}, x);
    Real C;
    Vec3 g[2];
    EvalContext ctx = context(x.data(), nullptr, nullptr);
    ASSERT_TRUE(Distance::eval(c, 0, ctx, C, g));
    // C = |xa - xb| - rest; the float rounding of one norm and one subtraction
    // is a few eps times the magnitudes (<= 3.5 + 1.5).
    EXPECT_NEAR(C, static_cast<Real>(dist_ld(x[0], x[1]) - rest), 16 * kEps * 5);
  }
}

TEST(ConstraintGradient, CollisionMatchesFiniteDifferences) {
  std::mt19937 rng(23456);
  for (int n = 0; n < kConfigs; ++n) {
    std::vector<Vec3> x;
    Real rest;
    random_pair(rng, x, rest);  // overlapping and separated configurations both occur
    const Collision c{{Index(n % 2), Index(1 - n % 2)}, rest, {}};
    check_gradient(c, 0, EvalContext{}, x);
    Real C;
    Vec3 g[2];
    EvalContext ctx = context(x.data(), nullptr, nullptr);
    ASSERT_TRUE(Collision::eval(c, 0, ctx, C, g));
    EXPECT_NEAR(C, static_cast<Real>(dist_ld(x[0], x[1]) - rest), 16 * kEps * 5);
  }
}

TEST(ConstraintGradient, WallMatchesFiniteDifferences) {
  std::mt19937 rng(34567);
  std::uniform_real_distribution<Real> u(-1, 1);
  for (int n = 0; n < kConfigs; ++n) {
    // Several planes so that Wall::plane indexing is exercised; the gradient
    // must be the normal of the plane the element references.
    std::vector<Plane> planes(3);
    for (Plane& p : planes) {
      Vec3 nrm;
      do nrm = random_point(rng);
      while (nrm.norm() < Real(0.1));
      p.normal = nrm.normalized();
      p.offset = u(rng);
    }
    const Index which = n % 3;
    const Wall c{{0}, which, Real(0.5) * (u(rng) + 1), {}};
    std::vector<Vec3> x = {random_point(rng)};
    check_gradient(c, 0, context(nullptr, nullptr, planes.data()), x);
    Real C;
    Vec3 g[1];
    EvalContext ctx = context(x.data(), nullptr, planes.data());
    ASSERT_TRUE(Wall::eval(c, 0, ctx, C, g));
    const Plane& p = planes[static_cast<std::size_t>(which)];
    long double ref = -static_cast<long double>(p.offset) - c.radius;
    for (int j = 0; j < 3; ++j) ref += static_cast<long double>(p.normal[j]) * x[0][j];
    EXPECT_NEAR(C, static_cast<Real>(ref), 16 * kEps * 4);
    EXPECT_EQ(g[0], p.normal);
  }
}

TEST(ConstraintGradient, PinMatchesFiniteDifferences) {
  std::mt19937 rng(45678);
  for (int n = 0; n < kConfigs; ++n) {
    // Several targets; eval() must use the one at the element index k.
    std::vector<Vec3> targets = {random_point(rng), random_point(rng), random_point(rng)};
    const Index k = n % 3;
    std::vector<Vec3> x;
    do x = {random_point(rng)};
    while ((x[0] - targets[static_cast<std::size_t>(k)]).norm() < kMinSeparation);
    const Pin c{{0}, {}};
    check_gradient(c, k, context(nullptr, targets.data(), nullptr), x);
    Real C;
    Vec3 g[1];
    EvalContext ctx = context(x.data(), targets.data(), nullptr);
    ASSERT_TRUE(Pin::eval(c, k, ctx, C, g));
    EXPECT_NEAR(C, static_cast<Real>(dist_ld(x[0], targets[static_cast<std::size_t>(k)])),
                16 * kEps * 4);
  }
}

// Documented degenerate cases: the gradient is undefined, eval() says so
// instead of returning a NaN direction.
TEST(ConstraintGradient, UndefinedDirectionIsReportedNotNaN) {
  const std::vector<Vec3> x = {Vec3(Real(0.3), Real(-0.2), Real(0.7)),
                               Vec3(Real(0.3), Real(-0.2), Real(0.7))};
  EvalContext ctx = context(x.data(), x.data(), nullptr);
  Real C = 0;
  Vec3 g[2];
  EXPECT_FALSE(Distance::eval(Distance{{0, 1}, 1, {}}, 0, ctx, C, g));
  EXPECT_FALSE(Collision::eval(Collision{{0, 1}, Real(0.1), {}}, 0, ctx, C, g));
  // Pin exactly on its target (pin_target points at x itself here).
  EXPECT_FALSE(Pin::eval(Pin{{0}, {}}, 0, ctx, C, g));

  // Just above the degeneracy threshold (kDegenerateRel * rest) the direction
  // is defined and exact.
  std::vector<Vec3> y = x;
  y[1].x() += Real(4) * kDegenerateRel;
  ctx.x = y.data();
  ASSERT_TRUE(Distance::eval(Distance{{0, 1}, 1, {}}, 0, ctx, C, g));
  EXPECT_TRUE(g[0].allFinite());
  EXPECT_NEAR(g[0].x(), -1, 8 * kEps);
  EXPECT_NEAR(g[1].x(), 1, 8 * kEps);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd

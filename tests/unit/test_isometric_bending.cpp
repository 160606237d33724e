// IsometricBending (constraints_bending.hpp): zero on every flat hinge, the
// small-angle value sqrt(3/(A0+A1)) |e| theta, analytic gradient against
// central finite differences at 50 random configurations, compile()
// validation, finite results on degenerate configurations.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

// Central differences, h = eps^(1/3): error ~ h^2/6 |C'''| + (a few eps)/h.
// C = |v| with v linear in x (dv/dx_ij = k_i e_j), so the third derivative
// along one coordinate is at most ~3 |k_i|^3 / |v|^2 and the truncation
// error, relative to |g| >= |k_i|, ~ |k_i|^2 / (2 |v|^2) eps^(2/3). The rest
// hinges (heights >= 0.3) give |k_i| of a few, and the configurations keep
// |v| >= 0.25, so the typical relative error is ~10-50 eps^(2/3).
// Tolerance 256 eps^(2/3) relative to max(1, max|g|): 9.4e-9 in double,
// 6.2e-3 in float (a float run with 32 instead of 256 still passes).
const Real kFdStep = std::cbrt(kEps);
const Real kFdTol = Real(256) * std::cbrt(kEps) * std::cbrt(kEps);

std::vector<Vec3> flat_hinge(std::mt19937& rng, const Vec3& origin, const Mat3& rot) {
  // Edge (0,0)-(L,0) with L in [0.5, 1.5], wings above and below with
  // heights in [0.3, 1.2]; then rotated and translated (still planar).
  std::uniform_real_distribution<Real> len(Real(0.5), Real(1.5)), off(Real(-0.5), Real(1.5)),
      h(Real(0.3), Real(1.2));
  const Real l = len(rng);
  std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(l, 0, 0), Vec3(off(rng), h(rng), 0),
                         Vec3(off(rng), -h(rng), 0)};
  for (auto& p : x) p = origin + rot * p;
  return x;
}

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<Real> n;
  Eigen::Quaternion<Real> q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}

IsometricBending make(const std::vector<Vec3>& rest) {
  IsometricBending c{{0, 1, 2, 3}, {}, {}};
  EXPECT_TRUE(IsometricBending::rest_weights(rest[0], rest[1], rest[2], rest[3], c.k));
  return c;
}

TEST(IsometricBending, ZeroOnEveryFlatHinge) {
  // The cotangent weights reproduce linear functions, so sum_i k_i x_i = 0
  // for any planar hinge, whatever its shape, orientation or position, and
  // for planar deformations of the rest hinge too.
  std::mt19937 rng(3);
  std::uniform_real_distribution<Real> u(-5, 5);
  for (int t = 0; t < 20; ++t) {
    const auto rest = flat_hinge(rng, Vec3(u(rng), u(rng), u(rng)), random_rotation(rng));
    const IsometricBending c = make(rest);
    Real ksum = 0, kabs = 0;
    for (Real k : c.k) ksum += k, kabs += std::abs(k);
    EXPECT_LE(std::abs(ksum), 16 * kEps * kabs);  // translation invariance
    // An in-plane affine map of the rest hinge is still flat.
    std::vector<Vec3> x = rest;
    const Vec3 n = (rest[1] - rest[0]).cross(rest[2] - rest[0]).normalized();
    Mat3 a = Mat3::Identity() + Real(0.3) * random_rotation(rng);
    a = a - n * (n.transpose() * a) + n * n.transpose();  // keep the plane
    for (auto& p : x) p = rest[0] + a * (p - rest[0]);
    EvalContext ctx;
    ctx.x = x.data();
    Real C = 0;
    Vec3 g[4];
    // Either skipped (v below kDegenerateRel times the magnitude of its
    // terms) or C at round-off level of those terms.
    Real terms = 0;
    for (int i = 1; i < 4; ++i) terms += std::abs(c.k[i]) * (x[i] - x[0]).norm();
    if (IsometricBending::eval(c, 0, ctx, C, g)) {
      EXPECT_LE(C, 64 * kEps * terms) << "hinge " << t;
    }
  }
}

TEST(IsometricBending, SmallBendMatchesDiscreteShellsForm) {
  // Rotating one wing by theta about the hinge moves it by h3*theta normal to
  // the plane; k3 = sqrt(3/A) (cot a + cot b) and h3 (cot a + cot b) = |e|,
  // so C = sqrt(3/(A0+A1)) |e| theta + O(theta^2) for any hinge shape.
  const Real l = Real(1.3);
  const std::vector<Vec3> rest = {Vec3(0, 0, 0), Vec3(l, 0, 0), Vec3(Real(0.2), Real(0.9), 0),
                                  Vec3(Real(1.1), Real(-0.6), 0)};
  const IsometricBending c = make(rest);
  const Real area = Real(0.5) * l * (Real(0.9) + Real(0.6));
  for (Real theta : {Real(1e-2), Real(3e-2)}) {
    std::vector<Vec3> x = rest;
    x[3] = Vec3(Real(1.1), Real(-0.6) * std::cos(theta), Real(0.6) * std::sin(theta));
    EvalContext ctx;
    ctx.x = x.data();
    Real C;
    Vec3 g[4];
    ASSERT_TRUE(IsometricBending::eval(c, 0, ctx, C, g));
    const Real expected = std::sqrt(Real(3) / area) * l * theta;
    // Only x3 moves, along a chord of length 2 h3 sin(theta/2): the ratio is
    // sin(theta/2)/(theta/2) = 1 - theta^2/24 + ..., plus round-off of v
    // (~eps relative to its terms, O(1)) divided by C ~ theta.
    EXPECT_NEAR(C / expected, 1, theta * theta / 24 + 256 * kEps / theta) << "theta " << theta;
  }
}

TEST(IsometricBending, GradientMatchesFiniteDifferences) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<Real> u(-1, 1);
  int tested = 0;
  while (tested < 50) {
    const auto rest = flat_hinge(rng, Vec3::Zero(), random_rotation(rng));
    const IsometricBending c = make(rest);
    std::vector<Vec3> x = rest;
    for (auto& p : x) p += Real(0.5) * Vec3(u(rng), u(rng), u(rng));
    EvalContext ctx;
    ctx.x = x.data();
    Real C;
    Vec3 g[4];
    if (!IsometricBending::eval(c, 0, ctx, C, g) || C < Real(0.25)) continue;  // see kFdTol
    Real gmax = 1;
    for (const Vec3& gi : g) gmax = std::max(gmax, gi.norm());
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 3; ++j) {
        const Real x0 = x[i][j], xp = x0 + kFdStep, xm = x0 - kFdStep;
        Real cp, cm;
        Vec3 unused[4];
        x[i][j] = xp;
        ASSERT_TRUE(IsometricBending::eval(c, 0, ctx, cp, unused));
        x[i][j] = xm;
        ASSERT_TRUE(IsometricBending::eval(c, 0, ctx, cm, unused));
        x[i][j] = x0;
        EXPECT_NEAR((cp - cm) / (xp - xm), g[i][j], kFdTol * gmax)
            << "config " << tested << " particle " << i << " coord " << j;
      }
    ++tested;
  }
}

TEST(IsometricBending, GradientNormIsBoundedByWeights) {
  // |grad_i C| = |k_i| (i >= 1) however small the bend: no blow-up near rest.
  const std::vector<Vec3> rest = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, -1, 0)};
  const IsometricBending c = make(rest);
  for (Real dz : {Real(1e-3), Real(1e-1), Real(1)}) {
    std::vector<Vec3> x = rest;
    x[3].z() = dz;
    EvalContext ctx;
    ctx.x = x.data();
    Real C;
    Vec3 g[4];
    ASSERT_TRUE(IsometricBending::eval(c, 0, ctx, C, g));
    for (int i = 1; i < 4; ++i) EXPECT_NEAR(g[i].norm(), std::abs(c.k[i]), 16 * kEps);
  }
}

SceneDesc hinge_scene() {
  SceneDesc s;
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, -1, 0)})
    s.add_particle(p, 1);
  s.isometric_bends.push_back(IsometricBendingDesc{{0, 1, 2, 3}, {}});
  return s;
}

TEST(IsometricBending, CompileRejectsBadInput) {
  auto s = hinge_scene();
  s.isometric_bends[0].p[0] = -1;
  EXPECT_TRUE(test::scene_error_names(s, {"isometric_bends[0]", "p0", "-1"}));
  s = hinge_scene();
  s.isometric_bends[0].p[2] = 3;
  EXPECT_TRUE(test::scene_error_names(s, {"isometric_bends[0]", "p3", "duplicate particle 3", "p2"}));
  s = hinge_scene();
  s.positions[3] = Vec3(2, 0, 0);  // rest triangle 2 degenerate
  EXPECT_TRUE(test::scene_error_names(s, {"isometric_bends[0]", "degenerate"}));
  s = hinge_scene();
  s.isometric_bends[0].mat.stiffness = 2;
  EXPECT_TRUE(test::scene_error_names(s, {"isometric_bends[0]", "mat.stiffness", "2"}));
}

TEST(IsometricBending, DegenerateConfigurationsStayFinite) {
  const std::vector<std::vector<Vec3>> cases = {
      std::vector<Vec3>(4, Vec3(1, 2, 3)),                                    // coincident
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, 0), Vec3(0.5, -1, 0)},      // zero area
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, -1, 0)},      // flat (rest)
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, 1, 0)},       // folded
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, 1, 1e-30)}};  // nearly folded
  for (const auto& x : cases)
    for (Real alpha : {Real(0), Real(1e-2)})
      for (Method method : {Method::xpbd, Method::pbd}) {
        auto s = hinge_scene();
        s.isometric_bends[0].mat.compliance = alpha;
        const Model m = compile(s);
        State st = make_state(m);
        st.x = x;
        StepConfig cfg;
        cfg.method = method;
        cfg.iterations = 4;
        for (int i = 0; i < 10; ++i) step(m, st, cfg);
        EXPECT_TRUE(test::all_finite(st));
      }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd

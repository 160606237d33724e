// The catenary reference (demos/compare/catenary.hpp): the equilibrium of a
// discrete elastic chain between two supports, checked
// (1) independently from its positions alone: at every interior particle
//     the two link tensions that balance gravity along the links' own
//     directions, and every link's length against Hooke's law;
// (2) against answers known in closed form: three particles, the small-sag
//     limit, symmetry, the supports carrying the interior weight;
// (3) for bad input (errors naming the field);
// (4) against XPBD: the scene run to rest settles on it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "demos/compare/catenary.hpp"
#include "demos/compare/compare.hpp"
#include "demos/scene_runner.hpp"

namespace xpbd_compare {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using V3d = Eigen::Vector3d;
constexpr double kEps = std::numeric_limits<Real>::epsilon();

V3d d3(const Vec3& v) { return v.cast<double>(); }

double max_abs(const std::vector<Vec3>& x) {
  double m = 0;
  for (const auto& v : x) m = std::max(m, d3(v).cwiseAbs().maxCoeff());
  return m;
}

// Checks x against the statics of the chain without using how
// catenary_equilibrium built it: at interior particle k the links k-1 and k
// pull along their own directions u (from the positions) with tensions
// (T_{k-1}, T_k) that must balance the weight: T_k u_k - T_{k-1} u_{k-1} =
// m g y (solved in least squares; the out-of-plane remainder must vanish).
// Then every link must be l + alpha T long (T from either end), and the end
// links' tensions are the support forces.
//
// Tolerances: every position is rounded once to Real, |dx| <= eps |x|max
// (eps of Real; double: the Newton residual, ~1e-16 m, is as small). A unit
// direction over a link of length len is then off by <= 2 dx / len, and the
// 2x2 solve divides that by the sine of the angle between the two links
// (the kink, ~m g / T), so a tension is off by <= T * 2 (2 dx / len) / sin.
// The factor 4 below is margin over these bounds.
void check_statics(const CatenaryParams& p, const CatenaryEquilibrium& eq) {
  const int n = p.n;
  ASSERT_EQ(eq.x.size(), std::size_t(n));
  const double dx = kEps * std::max(max_abs(eq.x), 1e-3);
  EXPECT_EQ(eq.x.front(), p.a);
  // The end: its rounding plus Newton's convergence bound (1e-12 L).
  EXPECT_LE((d3(eq.x.back()) - d3(p.b)).norm(), 2 * dx + 1e-12 * (n - 1) * double(p.spacing));
  EXPECT_LT(eq.residual, 1e-12 * (n - 1) * double(p.spacing));

  std::vector<V3d> u(std::size_t(n - 1));
  std::vector<double> len(std::size_t(n - 1));
  for (int k = 0; k + 1 < n; ++k) {
    const V3d d = d3(eq.x[std::size_t(k + 1)]) - d3(eq.x[std::size_t(k)]);
    len[std::size_t(k)] = d.norm();
    u[std::size_t(k)] = d / d.norm();
  }
  const double w = double(p.mass) * double(p.g);
  const double alpha = p.compliance, l = p.spacing;
  std::vector<double> T_from_left(std::size_t(n - 1), NAN), T_from_right(std::size_t(n - 1), NAN);
  for (int k = 1; k + 1 < n; ++k) {
    const V3d& ul = u[std::size_t(k - 1)];
    const V3d& ur = u[std::size_t(k)];
    Eigen::Matrix<double, 3, 2> A;
    A.col(0) = -ul;
    A.col(1) = ur;
    const V3d rhs(0, w, 0);
    const Eigen::Vector2d T = A.colPivHouseholderQr().solve(rhs);
    const double sin_kink = ul.cross(ur).norm();
    ASSERT_GT(sin_kink, 0) << "particle " << k;
    const double dir_err = 2 * dx / std::min(len[std::size_t(k - 1)], len[std::size_t(k)]);
    const double tolT = 4 * std::max(T(0), T(1)) * 2 * dir_err / sin_kink;
    // Links in tension, and the balance closes out of the plane too.
    EXPECT_GT(T(0), 0) << "particle " << k;
    EXPECT_GT(T(1), 0) << "particle " << k;
    EXPECT_LE((A * T - rhs).norm(), 4 * (T(0) + T(1)) * dir_err + 1e-12 * w) << "particle " << k;
    T_from_right[std::size_t(k - 1)] = T(0);  // link k-1 seen from its right end
    T_from_left[std::size_t(k)] = T(1);       // link k seen from its left end
    // The same link seen from its two ends carries the same tension.
    if (k >= 2) {
      EXPECT_NEAR(T_from_right[std::size_t(k - 1)], T_from_left[std::size_t(k - 1)], tolT) << "link " << k - 1;
    }
    // Hooke: each link is l + alpha T long.
    EXPECT_NEAR(len[std::size_t(k)], l + alpha * T(1), 4 * dx + alpha * tolT) << "link " << k;
    EXPECT_NEAR(len[std::size_t(k - 1)], l + alpha * T(0), 4 * dx + alpha * tolT) << "link " << k - 1;
    // The reported H and V0 give the same tension (link k: |(H, V0 - k m g)|).
    EXPECT_NEAR(T(1), std::hypot(eq.H, eq.V0 - k * w), tolT) << "link " << k;
  }
  // The supports hold the end links' tensions (the end particles' own weight
  // excluded, as documented).
  const double tol_end = 1e-6 * eq.support_force_a + 1e3 * dx / std::max(l, 1e-9) * eq.support_force_a;
  EXPECT_NEAR(eq.support_force_a, T_from_right[0], tol_end);
  EXPECT_NEAR(eq.support_force_b, T_from_left[std::size_t(n - 2)], tol_end);
}

TEST(CatenaryEquilibrium, DefaultChainBalancesEveryParticle) {
  CatenaryParams p;
  const CatenaryEquilibrium eq = catenary_equilibrium(p);
  check_statics(p, eq);
  EXPECT_LE(eq.newton_iterations, 20);
}

TEST(CatenaryEquilibrium, AsymmetricSupportsOutOfTheXyPlane) {
  // b higher than a and off in z: the plane of the chain is not x-y.
  CatenaryParams p;
  p.b = Vec3(Real(0.3), Real(0.25), Real(0.35));
  const CatenaryEquilibrium eq = catenary_equilibrium(p);
  check_statics(p, eq);
  // Every particle lies in the vertical plane through a and b.
  const V3d e = V3d(double(p.b.x() - p.a.x()), 0, double(p.b.z() - p.a.z())).normalized();
  const V3d normal = e.cross(V3d::UnitY());
  for (const auto& x : eq.x) EXPECT_NEAR((d3(x) - d3(p.a)).dot(normal), 0, 4 * kEps);
  // The supports carry the interior particles' weight, (n-2) m g = 19 N
  // (with the mass as Real rounds it: 0.1f is 1.5e-9 off).
  const double weight = 19 * double(p.mass) * double(p.g);
  EXPECT_NEAR(eq.support_vertical_a + eq.support_vertical_b, weight, 1e-12 * weight);
  // b is higher: it takes more of the weight.
  EXPECT_GT(eq.support_vertical_b, eq.support_vertical_a);
}

TEST(CatenaryEquilibrium, VeryCompliantChainStillBalances) {
  // Links stretched by ~4x their rest length (alpha T ~ 0.2 m for T ~ 10 N).
  CatenaryParams p;
  p.compliance = Real(0.02);
  p.b = Vec3(Real(0.4), Real(-0.3), 0);
  check_statics(p, catenary_equilibrium(p));
}

TEST(CatenaryLimits, ThreeParticlesClosedForm) {
  // One free particle of 1 kg on two 0.5 m links between supports 0.6 m
  // apart: it hangs sqrt(0.5^2 - 0.3^2) = 0.4 m below them; each link
  // carries T = m g l / (2 depth) = 10 * 0.5 / 0.8 = 6.25 N, H = 3.75 N,
  // V0 = 5 N. (In the float build the supports are 0.6f apart, 2.4e-8 m
  // more: the expected values use that D.)
  CatenaryParams p;
  p.n = 3;
  p.mass = 1;
  p.spacing = Real(0.5);
  p.compliance = 0;
  p.a = Vec3(Real(-0.3), 0, 0);
  p.b = Vec3(Real(0.3), 0, 0);
  const CatenaryEquilibrium eq = catenary_equilibrium(p);
  const double D = double(p.b.x()) - double(p.a.x());
  const double depth = std::sqrt(0.25 - D * D / 4);  // 0.4 m
  const double T = 10 * 0.5 / (2 * depth);           // 6.25 N
  const double tol = 8 * kEps;  // positions of ~0.5 m rounded to Real
  EXPECT_NEAR(eq.x[1].x(), (double(p.a.x()) + double(p.b.x())) / 2, tol);
  EXPECT_NEAR(eq.x[1].y(), -depth, tol);
  EXPECT_NEAR(depth, 0.4, 1e-7);
  EXPECT_NEAR(eq.H, T * (D / 2) / 0.5, 1e-12);
  EXPECT_NEAR(eq.H, 3.75, 1e-6);
  EXPECT_NEAR(eq.V0, 5.0, 1e-12);
  EXPECT_NEAR(eq.support_force_a, T, 1e-12);
  EXPECT_NEAR(eq.support_force_b, T, 1e-12);

  // Elastic (alpha = 0.01 m/N): the link length L = l + alpha T with
  // T = m g L / (2 sqrt(L^2 - 0.09)), a fixed point solved here by
  // iteration (a contraction: dT/dL * alpha ~ 0.1).
  p.compliance = Real(0.01);
  double L = 0.5;
  const double alpha = p.compliance;  // 0.01f is 2e-10 off in float
  for (int i = 0; i < 200; ++i) L = 0.5 + alpha * (10 * L / (2 * std::sqrt(L * L - D * D / 4)));
  const CatenaryEquilibrium el = catenary_equilibrium(p);
  EXPECT_NEAR(el.x[1].y(), -std::sqrt(L * L - D * D / 4), tol);
  EXPECT_NEAR(el.support_force_a, (L - 0.5) / alpha, 1e-9);
}

TEST(CatenaryLimits, NearlyTautInextensibleChainHasTheSmallSagOfTheParabola) {
  // 20 links of 5 cm (L = 1 m), supports L - 1 mm apart, compliance 0. To
  // leading order in the link angles theta_k = V_k / H = (m g / H)(9.5 - k):
  // sum l theta_k^2 / 2 = L - D, i.e. (m g / H)^2 = 2 (L - D) / (l * 665)
  // (sum of (9.5 - k)^2 over k = 0..19 is 665), and the middle particle
  // hangs s = l (m g / H) * (9.5 + 8.5 + ... + 0.5) = 50 l m g / H below the
  // supports: m g / H = 7.76e-3, s = 19.4 mm. The neglected terms are of
  // relative order theta_0^2 = 5.4e-3, so 1 % (about twice that) is the
  // tolerance.
  CatenaryParams p;
  p.compliance = 0;
  p.a = Vec3(Real(-0.4995), 0, 0);
  p.b = Vec3(Real(0.4995), 0, 0);
  const CatenaryEquilibrium eq = catenary_equilibrium(p);
  const double D = double(p.b.x()) - double(p.a.x());
  const double mg_over_H = std::sqrt(2 * (1.0 - D) / (0.05 * 665));
  EXPECT_NEAR(eq.H, 1.0 / mg_over_H, 0.01 / mg_over_H);
  const double sag = -double(eq.x[10].y());
  EXPECT_NEAR(sag, 50 * 0.05 * mg_over_H, 0.01 * 50 * 0.05 * mg_over_H);
  check_statics(p, eq);
}

TEST(CatenaryLimits, SymmetricSupportsGiveASymmetricChain) {
  // Same height: by symmetry each support carries half of the interior
  // weight, V0 = (n-2) m g / 2 = 9.5 N, and particle k mirrors n-1-k.
  CatenaryParams p;
  const CatenaryEquilibrium eq = catenary_equilibrium(p);
  EXPECT_NEAR(eq.V0, 9.5 * double(p.mass) * double(p.g), 1e-12 * 9.5);
  EXPECT_NEAR(eq.support_force_a, eq.support_force_b, 1e-12 * eq.support_force_a);
  const double tol = 4 * kEps * max_abs(eq.x) + 1e-15;
  for (int k = 0; k < p.n; ++k) {
    const Vec3& l = eq.x[std::size_t(k)];
    const Vec3& r = eq.x[std::size_t(p.n - 1 - k)];
    EXPECT_NEAR(l.x(), -r.x(), tol) << k;
    EXPECT_NEAR(l.y(), r.y(), tol) << k;
    EXPECT_EQ(l.z(), 0) << k;
  }
  // The elastic chain is longer, so it sags more than the inextensible one
  // (by 1.33 mm for these links stretched ~1e-4 m each).
  CatenaryParams rigid = p;
  rigid.compliance = 0;
  const CatenaryEquilibrium r = catenary_equilibrium(rigid);
  EXPECT_GT(-eq.x[10].y(), -r.x[10].y() + 1e-3);
  EXPECT_GT(r.H, eq.H);
}

TEST(CatenaryLimits, SupportsCarryTheInteriorWeight) {
  for (Real by : {Real(-0.5), Real(0), Real(0.2), Real(0.55)}) {
    CatenaryParams p;
    p.b = Vec3(Real(0.2), by, Real(0.1));
    const CatenaryEquilibrium eq = catenary_equilibrium(p);
    EXPECT_NEAR(eq.support_vertical_a + eq.support_vertical_b, (p.n - 2) * double(p.mass) * double(p.g), 1e-11)
        << "b.y = " << by;
    // Horizontal components are H at both ends.
    EXPECT_NEAR(eq.support_force_a * eq.support_force_a - eq.support_vertical_a * eq.support_vertical_a,
                eq.H * eq.H, 1e-9 * eq.support_force_a * eq.support_force_a);
  }
}

// ---------------------------------------------------------------------------

void expect_invalid(const CatenaryParams& p, const std::string& field) {
  try {
    catenary_equilibrium(p);
    ADD_FAILURE() << "no error for " << field;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("CatenaryParams." + field), std::string::npos) << e.what();
  }
  EXPECT_THROW(catenary_scene(p, 10), std::invalid_argument) << field;
}

TEST(CatenaryErrors, BadInputNamesTheField) {
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const Real inf = std::numeric_limits<Real>::infinity();
  CatenaryParams p;
  { auto q = p; q.n = 2; expect_invalid(q, "n"); }
  { auto q = p; q.mass = 0; expect_invalid(q, "mass"); }
  { auto q = p; q.mass = nan; expect_invalid(q, "mass"); }
  { auto q = p; q.spacing = -1; expect_invalid(q, "spacing"); }
  { auto q = p; q.g = 0; expect_invalid(q, "g"); }
  { auto q = p; q.compliance = Real(-1e-6); expect_invalid(q, "compliance"); }
  { auto q = p; q.compliance = inf; expect_invalid(q, "compliance"); }
  { auto q = p; q.drag = -1; expect_invalid(q, "drag"); }
  { auto q = p; q.start_angle = nan; expect_invalid(q, "start_angle"); }
  { auto q = p; q.a.y() = inf; expect_invalid(q, "a"); }
  // Supports as far apart as the unstretched chain is long (1 m): no.
  { auto q = p; q.b.x() = Real(0.6); expect_invalid(q, "b"); }
  // b straight above a: a vertical chain, not a catenary.
  { auto q = p; q.b = q.a + Vec3(0, Real(0.3), 0); expect_invalid(q, "b"); }
  try {
    catenary_equilibrium([&] { auto q = p; q.b.x() = Real(0.6); return q; }());
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rest length"), std::string::npos) << e.what();
  }
  EXPECT_THROW(catenary_scene(p, 0), std::invalid_argument);
}

TEST(CatenaryErrors, DegenerateFoldedChainIsARuntimeError) {
  // Supports 1e-5 m apart horizontally and 18 links apart vertically: the
  // chain folds at a point where the tensile equilibrium degenerates (see
  // catenary.cpp); the error says so and gives the residual.
  CatenaryParams p;
  p.b = Vec3(Real(-0.39999), Real(0.9), 0);
  if (double(p.b.x()) == double(p.a.x())) GTEST_SKIP() << "float rounds the 1e-5 m offset away";
  try {
    catenary_equilibrium(p);
    ADD_FAILURE() << "converged on a degenerate chain";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("did not converge"), std::string::npos) << m;
    EXPECT_NE(m.find("m from support b"), std::string::npos) << m;
  }
}

// ---------------------------------------------------------------------------

TEST(CatenaryScene, StartsUnstretchedAndPinnedAtTheSupports) {
  CatenaryParams p;
  p.start_angle = Real(0.5);
  const xpbd_demos::SceneSpec s = catenary_scene(p, 60);
  const xpbd::SceneDesc& d = s.soft.particles;
  ASSERT_EQ(d.num_particles(), p.n);
  ASSERT_EQ(d.distances.size(), std::size_t(p.n - 1));
  ASSERT_EQ(d.pins.size(), 2u);
  EXPECT_EQ(d.positions.front(), p.a);
  EXPECT_EQ(d.positions.back(), p.b);
  EXPECT_EQ(d.masses.front(), 0);
  EXPECT_EQ(d.masses.back(), 0);
  for (int i = 1; i + 1 < p.n; ++i) EXPECT_EQ(d.masses[std::size_t(i)], p.mass);
  // Every link at its rest length up to the rounding of the positions.
  for (const auto& c : d.distances) {
    ASSERT_TRUE(c.rest.has_value());
    EXPECT_EQ(*c.rest, p.spacing);
    EXPECT_EQ(c.mat.compliance, p.compliance);
    const double len = (d3(d.positions[std::size_t(c.b)]) - d3(d.positions[std::size_t(c.a)])).norm();
    EXPECT_NEAR(len, p.spacing, 8 * kEps * 0.5);
  }
  // Turned 0.5 rad about the support line: the middle particle, 0.266 m
  // below it at rest, is 0.266 sin(0.5) = 0.127 m out of the x-y plane.
  EXPECT_NEAR(std::abs(double(d.positions[10].z())), 0.2658 * std::sin(0.5), 1e-3);
  EXPECT_EQ(s.solver.gravity, Vec3(0, -p.g, 0));
  EXPECT_EQ(s.solver.drag, p.drag);
  EXPECT_EQ(s.solver.frames, 60);
  EXPECT_TRUE(xpbd_demos::bullet_can_express(s));
}

TEST(CatenaryScene, XpbdSettlesOnTheElasticEquilibrium) {
  // Start swung 0.5 rad out of the vertical plane (RMS 0.09 m from the
  // answer), 3 s at 20 substeps x 10 iterations (h = 1/1200 s).
  // - Settling: drag 10/s damps the swing's amplitude as exp(-5 t)
  //   (measured: 7e-5 m RMS at 1.5 s), i.e. ~3e-8 m by 3 s.
  // - XPBD's fixed point: the chain rests slightly off the exact statics
  //   because each substep's corrections use gradients from different
  //   iterates (measured in double, RMS: 1.2e-6 m at 20 substeps, 4.2e-6 at
  //   10, 1.6e-5 at 5, the same for 10 or 50 iterations -- so it is the
  //   substep h, not the iteration count; roughly h^2).
  // - Float: the per-substep gravity drop g h^2 = 6.9e-6 m is only ~150 ulp
  //   of |x| ~ 0.4 m, and rounding keeps the chain jittering: measured
  //   1e-5 .. 3.6e-5 m RMS (~750 ulp of 0.4 m) over 2..3 s.
  // Tolerance: 5e-6 m (4x the double bias) + 2000 ulp of 0.4 m (float:
  // 1e-4 m; double: 2e-13 m). The inextensible chain is 8.8e-4 m RMS away
  // (checked below), so a solver that ignores the compliance, or one that
  // did not settle, fails.
  CatenaryParams p;
  p.start_angle = Real(0.5);
  const xpbd_demos::SceneSpec spec = catenary_scene(p, 180);
  xpbd_demos::RunOptions o = xpbd_demos::run_options(spec);
  o.solver = xpbd_demos::Solver::xpbd;
  o.substeps = 20;
  o.iterations = 10;
  std::vector<Vec3> last;
  const auto r = xpbd_demos::run_scene(spec, o, [&](const xpbd_demos::FrameView& v) {
    last.assign(v.positions.begin(), v.positions.end());
  });
  ASSERT_TRUE(r.finite);
  const CatenaryEquilibrium eq = catenary_equilibrium(p);
  const double tol = 5e-6 + 2000 * kEps * 0.4;
  const double err = position_error(last, eq.x).rms;
  EXPECT_LT(err, tol);

  CatenaryParams rigid = p;
  rigid.compliance = 0;
  const double elastic_vs_rigid = position_error(eq.x, catenary_equilibrium(rigid).x).rms;
  EXPECT_GT(elastic_vs_rigid, 8 * tol);  // the test can tell them apart
  EXPECT_GT(position_error(last, catenary_equilibrium(rigid).x).rms, 0.5 * elastic_vs_rigid);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd_compare

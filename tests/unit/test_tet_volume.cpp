// TetVolume (constraints_volume.hpp): signed volume against closed forms,
// gradient against central finite differences at 50 random tetrahedra,
// compile() validation, finite results on degenerate configurations.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;

TEST(TetVolume, SignedVolumeOfCornerTet) {
  // Corner tetrahedron of the unit cube: 1/6; swapping two vertices inverts it.
  const std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  EvalContext ctx;
  ctx.x = x.data();
  Real C;
  Vec3 g[4];
  ASSERT_TRUE(TetVolume::eval(TetVolume{{0, 1, 2, 3}, 0, {}}, 0, ctx, C, g));
  EXPECT_NEAR(C, Real(1) / 6, 4 * kEps);
  // Gradient of the corner volume: dV/dx of a unit vertex = (area of the
  // opposite face = 1/2)/3 along its axis = e_i/6; the origin's opposite face
  // has area sqrt(3)/2 and normal -(1,1,1)/sqrt(3): -(1,1,1)/6.
  EXPECT_TRUE(g[0].isApprox(-Vec3(1, 1, 1) / 6, 4 * kEps));
  EXPECT_TRUE(g[1].isApprox(Vec3(1, 0, 0) / 6, 4 * kEps));
  ASSERT_TRUE(TetVolume::eval(TetVolume{{0, 2, 1, 3}, Real(0.5), {}}, 0, ctx, C, g));
  EXPECT_NEAR(C, -Real(1) / 6 - Real(0.5), 4 * kEps);
  EXPECT_TRUE(g[0].isApprox(Vec3(1, 1, 1) / 6, 4 * kEps));  // inverted: gradients flip
}

TEST(TetVolume, GradientMatchesFiniteDifferences) {
  // V is affine in each particle's position (det is multilinear and the x0
  // terms of degree >= 2 cancel), so central differences have no truncation
  // error: only round-off, ~ a few eps * |V terms| / h with terms <= 8/6 in
  // the box [-1,1]^3. h = eps^(1/3), tolerance 64 eps^(2/3): 2.4e-9 in
  // double, 1.6e-3 in float.
  const Real h = std::cbrt(kEps);
  const Real tol = Real(64) * h * h;
  std::mt19937 rng(9);
  std::uniform_real_distribution<Real> u(-1, 1);
  const TetVolume c{{0, 1, 2, 3}, Real(0.1), {}};
  for (int t = 0; t < 50; ++t) {
    std::vector<Vec3> x(4);
    for (auto& p : x) p = Vec3(u(rng), u(rng), u(rng));
    EvalContext ctx;
    ctx.x = x.data();
    Real C;
    Vec3 g[4];
    ASSERT_TRUE(TetVolume::eval(c, 0, ctx, C, g));
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 3; ++j) {
        const Real x0 = x[i][j], xp = x0 + h, xm = x0 - h;
        Real cp, cm;
        Vec3 unused[4];
        x[i][j] = xp;
        TetVolume::eval(c, 0, ctx, cp, unused);
        x[i][j] = xm;
        TetVolume::eval(c, 0, ctx, cm, unused);
        x[i][j] = x0;
        EXPECT_NEAR((cp - cm) / (xp - xm), g[i][j], tol) << "tet " << t << " particle " << i;
      }
  }
}

SceneDesc tet_scene() {
  SceneDesc s;
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}) s.add_particle(p, 1);
  s.tets.push_back(TetVolumeDesc{{0, 1, 2, 3}, std::nullopt, {}});
  return s;
}

TEST(TetVolume, CompileMeasuresRestVolume) {
  const Model m = compile(tet_scene());
  EXPECT_NEAR(m.get<TetVolume>()[0].rest_volume, Real(1) / 6, 4 * kEps);
}

TEST(TetVolume, CompileRejectsBadInput) {
  auto s = tet_scene();
  s.tets[0].p[2] = 99;
  EXPECT_TRUE(test::scene_error_names(s, {"tets[0]", "p2", "index 99 out of range [0, 4)"}));
  s = tet_scene();
  s.tets[0].p[3] = 0;
  EXPECT_TRUE(test::scene_error_names(s, {"tets[0]", "p3", "duplicate particle 0", "p0"}));
  s = tet_scene();
  s.positions[3] = Vec3(0.3, 0.3, 0);  // flat
  EXPECT_TRUE(test::scene_error_names(s, {"tets[0]", "rest_volume", "flat"}));
  s = tet_scene();
  s.tets[0].rest_volume = 0;
  EXPECT_TRUE(test::scene_error_names(s, {"tets[0]", "rest_volume", "0"}));
  s.tets[0].rest_volume = std::numeric_limits<Real>::infinity();
  EXPECT_TRUE(test::scene_error_names(s, {"tets[0]", "rest_volume", "inf"}));
}

TEST(TetVolume, DegenerateConfigurationsStayFinite) {
  const std::vector<std::vector<Vec3>> cases = {
      std::vector<Vec3>(4, Vec3(1, 2, 3)),                             // coincident
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.3, 0.3, 0)},  // flat
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, -1)},   // inverted
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)}};   // collinear
  for (const auto& x : cases)
    for (Real alpha : {Real(0), Real(1e-3)})
      for (Method method : {Method::xpbd, Method::pbd}) {
        auto s = tet_scene();
        s.tets[0].mat.compliance = alpha;
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

// GlobalVolume (constraints_volume.hpp, special_constraints.hpp): enclosed
// volume against closed forms, gradient against central finite differences
// at 50 random surfaces, compile() validation (closed, oriented, positive
// volume), finite results on degenerate configurations.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "support/xpbd_test.hpp"
#include "xpbd/special_constraints.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;
using Tri = std::array<Index, 3>;

// Regular icosahedron with vertices (0, +-1, +-phi) and cyclic permutations
// (edge length 2), scaled by `scale` and centred at `c`. Faces are the 20
// vertex triples at mutual distance 2, oriented outward.
std::vector<Tri> add_icosahedron(SceneDesc& s, const Vec3& c, Real scale, Real mass) {
  const Real phi = (1 + std::sqrt(Real(5))) / 2;
  std::vector<Vec3> v;
  for (Real a : {Real(-1), Real(1)})
    for (Real b : {-phi, phi}) {
      v.emplace_back(0, a, b);
      v.emplace_back(a, b, 0);
      v.emplace_back(b, 0, a);
    }
  const Index first = s.num_particles();
  for (const Vec3& p : v) s.add_particle(c + scale * p, mass);
  std::vector<Tri> tris;
  auto edge = [&](int i, int j) { return std::abs((v[i] - v[j]).norm() - 2) < Real(1e-3); };
  for (int i = 0; i < 12; ++i)
    for (int j = i + 1; j < 12; ++j)
      for (int k = j + 1; k < 12; ++k)
        if (edge(i, j) && edge(j, k) && edge(i, k)) {
          const bool outward = (v[j] - v[i]).cross(v[k] - v[i]).dot(v[i] + v[j] + v[k]) > 0;
          tris.push_back(outward ? Tri{first + i, first + j, first + k}
                                 : Tri{first + i, first + k, first + j});
        }
  return tris;
}

// Volume of the regular icosahedron of edge a: (5/12)(3 + sqrt 5) a^3.
Real icosahedron_volume(Real a) { return Real(5) / 12 * (3 + std::sqrt(Real(5))) * a * a * a; }

SceneDesc ico_scene(const Vec3& c = Vec3::Zero(), Real scale = 1, Real pressure = 1) {
  SceneDesc s;
  const auto tris = add_icosahedron(s, c, scale, 1);
  s.global_volumes.push_back(GlobalVolumeDesc{tris, pressure, {}});
  return s;
}

TEST(GlobalVolume, IcosahedronVolumeFarFromOrigin) {
  // Positions 100 m from the origin carry round-off ~eps*100 each; the
  // volume, computed relative to a surface vertex, then has relative error
  // ~ a few * eps * 100 / scale. Tolerance 64 * eps * 100 relative.
  for (const Vec3& c : {Vec3(0, 0, 0), Vec3(100, -50, 30)}) {
    const Model m = compile(ico_scene(c, Real(0.5), Real(1.5)));
    const GlobalVolume& g = m.get<GlobalVolume>()[0];
    const Real expected = icosahedron_volume(1);  // edge 2 * 0.5
    EXPECT_NEAR(g.rest_volume / expected, 1, 64 * kEps * 100);
    EXPECT_NEAR(g.target / (Real(1.5) * expected), 1, 64 * kEps * 100);
    EXPECT_EQ(g.vert_end - g.vert_begin, 12);
    EXPECT_EQ(g.tri_end - g.tri_begin, 20);
  }
}

TEST(GlobalVolume, UnitCube) {
  SceneDesc s;
  for (int i = 0; i < 8; ++i) s.add_particle(Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1), 1);
  // Two triangles per face, counter-clockwise seen from outside.
  const std::vector<Tri> t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                              {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  s.global_volumes.push_back(GlobalVolumeDesc{t, 1, {}});
  const Model m = compile(s);
  EXPECT_NEAR(m.get<GlobalVolume>()[0].rest_volume, 1, 16 * kEps);
}

TEST(GlobalVolume, GradientMatchesFiniteDifferences) {
  // Each triangle's triple product is linear in each coordinate of each
  // vertex, so central differences have no truncation error; round-off is a
  // few eps * (sum of |terms| ~ 20 triangles * 8) / h, relative to gradients
  // of size ~1. h = eps^(1/3), tolerance 256 eps^(2/3): 9.4e-9 in double,
  // 6.2e-3 in float.
  const Real h = std::cbrt(kEps);
  const Real tol = Real(256) * h * h;
  const Model m = compile(ico_scene());
  const GlobalVolume& g = m.get<GlobalVolume>()[0];
  std::mt19937 rng(17);
  std::uniform_real_distribution<Real> u(Real(-0.3), Real(0.3));
  std::vector<Vec3> grad(m.global_volume_verts.size());
  for (int t = 0; t < 50; ++t) {
    std::vector<Vec3> x = m.x0;
    for (auto& p : x) p += Vec3(u(rng), u(rng), u(rng));
    global_volume(m, g, x.data(), grad.data());
    Vec3 sum = Vec3::Zero();
    for (Index v = g.vert_begin; v < g.vert_end; ++v) {
      sum += grad[v];
      const Index i = m.global_volume_verts[v];
      for (int j = 0; j < 3; ++j) {
        const Real x0 = x[i][j], xp = x0 + h, xm = x0 - h;
        x[i][j] = xp;
        const Real vp = global_volume(m, g, x.data(), nullptr);
        x[i][j] = xm;
        const Real vm = global_volume(m, g, x.data(), nullptr);
        x[i][j] = x0;
        EXPECT_NEAR((vp - vm) / (xp - xm), grad[v][j], tol) << "surface " << t << " vertex " << i;
      }
    }
    EXPECT_LE(sum.norm(), 64 * kEps);  // translation invariance of a closed surface
  }
}

TEST(GlobalVolume, CompileRejectsBadInput) {
  auto s = ico_scene();
  s.global_volumes[0].triangles.pop_back();  // hole
  EXPECT_TRUE(test::scene_error_names(s, {"global_volumes[0]", "triangles[", "not closed"}));
  s = ico_scene();
  std::swap(s.global_volumes[0].triangles[3][0], s.global_volumes[0].triangles[3][1]);  // one flipped
  EXPECT_TRUE(test::scene_error_names(s, {"global_volumes[0]", "not consistently oriented"}));
  s = ico_scene();
  for (auto& t : s.global_volumes[0].triangles) std::swap(t[0], t[1]);  // all inward
  EXPECT_TRUE(test::scene_error_names(s, {"global_volumes[0]", "triangles", "must be > 0"}));
  s = ico_scene();
  s.global_volumes[0].triangles[5][2] = 40;
  EXPECT_TRUE(test::scene_error_names(s, {"global_volumes[0]", "triangles[5][2]", "40", "[0, 12)"}));
  s = ico_scene();
  s.global_volumes[0].triangles[2][1] = s.global_volumes[0].triangles[2][0];
  EXPECT_TRUE(test::scene_error_names(s, {"global_volumes[0]", "triangles[2][1]", "duplicate"}));
  s = ico_scene();
  s.global_volumes[0].pressure = 0;
  EXPECT_TRUE(test::scene_error_names(s, {"global_volumes[0]", "pressure", "0"}));
  s = ico_scene();
  s.global_volumes[0].triangles.clear();
  EXPECT_TRUE(test::scene_error_names(s, {"global_volumes[0]", "triangles", "empty"}));
  s = ico_scene();
  s.global_volumes[0].mat.compliance = std::nan("");
  EXPECT_TRUE(test::scene_error_names(s, {"global_volumes[0]", "mat.compliance", "nan"}));
}

TEST(GlobalVolume, StepRejectsMismatchedScratch) {
  const Model m = compile(ico_scene());
  State st = make_state(m);
  st.volume_grad.resize(3);
  EXPECT_TRUE(test::config_error_names(m, st, {}, {"volume_grad", "3", "12"}));
}

TEST(GlobalVolume, TwoSurfacesShareNothing) {
  // Two balloons in one model: flat ranges must not overlap.
  SceneDesc s;
  const auto t1 = add_icosahedron(s, Vec3::Zero(), 1, 1);
  const auto t2 = add_icosahedron(s, Vec3(5, 0, 0), 2, 1);
  s.global_volumes.push_back(GlobalVolumeDesc{t1, 1, {}});
  s.global_volumes.push_back(GlobalVolumeDesc{t2, 1, {}});
  const Model m = compile(s);
  const auto& g = m.get<GlobalVolume>();
  EXPECT_EQ(g[1].vert_begin, g[0].vert_end);
  EXPECT_EQ(g[1].tri_begin, g[0].tri_end);
  EXPECT_NEAR(g[1].rest_volume / g[0].rest_volume, 8, 64 * kEps);
  for (Index v = g[1].vert_begin; v < g[1].vert_end; ++v) EXPECT_GE(m.global_volume_verts[v], 12);
}

TEST(GlobalVolume, DegenerateConfigurationsStayFinite) {
  // All vertices coincident (zero gradient), and a surface flattened into a
  // plane (volume 0, gradient non-zero).
  for (int c = 0; c < 2; ++c)
    for (Real alpha : {Real(0), Real(1e-3)})
      for (Method method : {Method::xpbd, Method::pbd}) {
        auto s = ico_scene();
        s.global_volumes[0].mat.compliance = alpha;
        const Model m = compile(s);
        State st = make_state(m);
        for (auto& p : st.x) p = c == 0 ? Vec3(1, 2, 3) : Vec3(p.x(), p.y(), 0);
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

// Global volume / pressure on a closed balloon: an icosphere (icosahedron
// subdivided twice: 162 particles, 320 triangles, 480 edges) of radius
// 0.5 m and mass 1 kg, with compliant edge distance constraints.
//  - Inflation to pressure 1.5 (target 1.5 V0) without gravity: the stiff
//    volume constraint is projected after the distances in every iteration,
//    so the volume at the end of a step misses the target only by the
//    second-order remainder of the last Newton step.
//  - Free fall at pressure 1.3: all constraints are internal, so the centre
//    of mass follows the discrete free-fall formula of symplectic Euler,
//    y_n = y0 - g h^2 n(n+1)/2, to round-off.
//  - Resting on a floor under gravity at pressure 1: the volume stays close
//    to V0 although the floor contacts (projected after the volume) flatten
//    the bottom in every iteration.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <vector>

#include "support/xpbd_test.hpp"
#include "xpbd/special_constraints.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;
using Tri = std::array<Index, 3>;

struct Mesh {
  std::vector<Vec3> x;
  std::vector<Tri> tris;
};

// Regular icosahedron on the unit sphere, faces oriented outward.
Mesh icosahedron() {
  const Real phi = (1 + std::sqrt(Real(5))) / 2;
  Mesh m;
  for (Real a : {Real(-1), Real(1)})
    for (Real b : {-phi, phi}) {
      m.x.emplace_back(0, a, b);
      m.x.emplace_back(a, b, 0);
      m.x.emplace_back(b, 0, a);
    }
  auto edge = [&](int i, int j) { return std::abs((m.x[i] - m.x[j]).norm() - 2) < Real(1e-3); };
  for (int i = 0; i < 12; ++i)
    for (int j = i + 1; j < 12; ++j)
      for (int k = j + 1; k < 12; ++k)
        if (edge(i, j) && edge(j, k) && edge(i, k)) {
          const bool out = (m.x[j] - m.x[i]).cross(m.x[k] - m.x[i]).dot(m.x[i] + m.x[j] + m.x[k]) > 0;
          m.tris.push_back(out ? Tri{i, j, k} : Tri{i, k, j});
        }
  for (auto& p : m.x) p.normalize();
  return m;
}

// Splits every triangle into four at the edge midpoints, pushed to the unit
// sphere. Orientation is preserved.
Mesh subdivide(const Mesh& in) {
  Mesh out{in.x, {}};
  std::map<std::pair<Index, Index>, Index> mid;
  auto midpoint = [&](Index a, Index b) {
    const auto key = std::minmax(a, b);
    const auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    out.x.push_back((in.x[a] + in.x[b]).normalized());
    const Index i = static_cast<Index>(out.x.size() - 1);
    mid.emplace(key, i);
    return i;
  };
  for (const Tri& t : in.tris) {
    const Index ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
    out.tris.push_back({t[0], ab, ca});
    out.tris.push_back({ab, t[1], bc});
    out.tris.push_back({ca, bc, t[2]});
    out.tris.push_back({ab, bc, ca});
  }
  return out;
}

constexpr Real kRadius = Real(0.5);  // m

SceneDesc balloon(const Vec3& centre, Real pressure, Real edge_compliance) {
  const Mesh mesh = subdivide(subdivide(icosahedron()));
  SceneDesc s;
  const Real mass = Real(1) / Real(mesh.x.size());
  for (const Vec3& p : mesh.x) s.add_particle(centre + kRadius * p, mass);
  std::map<std::pair<Index, Index>, bool> edges;
  for (const Tri& t : mesh.tris)
    for (int c = 0; c < 3; ++c) edges[std::minmax(t[c], t[(c + 1) % 3])] = true;
  for (const auto& [e, unused] : edges)
    s.distances.push_back(DistanceDesc{e.first, e.second, std::nullopt, Material{edge_compliance, 0, 1}});
  s.global_volumes.push_back(GlobalVolumeDesc{mesh.tris, pressure, {}});
  return s;
}

Real enclosed(const Model& m, const State& st) {
  return global_volume(m, m.get<GlobalVolume>()[0], st.x.data(), nullptr);
}

TEST(GlobalVolumeBalloon, MeshIsAClosedIcosphere) {
  const Mesh mesh = subdivide(subdivide(icosahedron()));
  ASSERT_EQ(mesh.x.size(), 162u);
  ASSERT_EQ(mesh.tris.size(), 320u);
  // compile() checks closedness and orientation; the inscribed polyhedron's
  // volume is below the sphere's (4/3) pi r^3 by a few percent at this
  // resolution (an edge subtends ~0.3 rad: the sagitta is ~1.2% of r).
  const Model m = compile(balloon(Vec3::Zero(), 1, 0));
  const Real sphere = Real(4) / 3 * std::numbers::pi_v<Real> * kRadius * kRadius * kRadius;
  const Real v0 = m.get<GlobalVolume>()[0].rest_volume;
  EXPECT_LT(v0, sphere);
  EXPECT_GT(v0, Real(0.95) * sphere);
}

TEST(GlobalVolumeBalloon, InflatesToPressureTimesRestVolume) {
  // Edge compliance 1e-3 m/N lets the membrane stretch by 1.5^(1/3) - 1 =
  // 14.5%. Drag 3 /s damps the inflation. Tolerance 1e-5 relative: the last
  // Newton step on the cubic V leaves a remainder of order
  // 3 (dr/r)^2 V for a radial correction dr, and at equilibrium the
  // per-iteration correction (what the distances undo) is dr/r < ~1e-3.
  const Model m = compile(balloon(Vec3::Zero(), Real(1.5), Real(1e-3)));
  State st = make_state(m);
  StepConfig cfg;
  cfg.gravity = Vec3::Zero();
  cfg.iterations = 4;
  cfg.drag = 3;
  const Real target = m.get<GlobalVolume>()[0].target;
  Real worst_late = 0;
  for (int i = 0; i < 300; ++i) {
    step(m, st, cfg);
    if (i >= 240) worst_late = std::max(worst_late, std::abs(enclosed(m, st) / target - 1));
  }
  std::printf("balloon inflation: max |V/(p V0) - 1| over the last second %.3e, mean edge strain %.4f\n",
              double(worst_late), double(distance_strain(m, st).mean));
  EXPECT_LT(worst_late, Real(1e-5));
  // It really inflated: the edges carry the stretch (mean strain near 14.5%).
  EXPECT_GT(distance_strain(m, st).mean, Real(0.10));
}

TEST(GlobalVolumeBalloon, FreeFallCentreOfMassIsBallistic) {
  // Starting from rest at pressure 1.3: the volume constraint inflates the
  // balloon while it falls; internal corrections move the centre of mass by
  // sum_i m_i w_i dl g_i = dl sum_i g_i = 0 (closed surface). Round-off:
  // ~eps |x| per projection, 600 substeps x 4 iterations x (480 + 1)
  // constraints. Tolerance 1e-9 m (double).
  const Model m = compile(balloon(Vec3(0, 10, 0), Real(1.3), Real(1e-4)));
  State st = make_state(m);
  StepConfig cfg;
  cfg.iterations = 4;
  const int steps = 60;
  for (int i = 0; i < steps; ++i) step(m, st, cfg);
  Vec3 com = Vec3::Zero();
  for (const Vec3& p : st.x) com += p;
  com /= Real(st.x.size());
  const Real h = cfg.dt / Real(cfg.substeps);
  const Real n = Real(steps * cfg.substeps);
  const Real expected_y = 10 + cfg.gravity.y() * h * h * n * (n + 1) / 2;
  EXPECT_NEAR(com.y(), expected_y, Real(1e-9));
  EXPECT_NEAR(com.x(), 0, Real(1e-9));
  EXPECT_NEAR(com.z(), 0, Real(1e-9));
  EXPECT_NEAR(enclosed(m, st) / m.get<GlobalVolume>()[0].target, 1, Real(1e-3));
}

TEST(GlobalVolumeBalloon, RestingOnFloorKeepsVolume) {
  // Pressure 1, stiff edges' compliance 1e-4 m/N, floor y = 0 (all
  // particles collide with it). The floor projections come after the volume
  // in each iteration and push the bottom up; the stated tolerance is 0.1% of
  // V0 at every step end (measured 2.5e-4). It must also rest on the
  // floor (no particle below it beyond round-off after the projections).
  SceneDesc s = balloon(Vec3(0, Real(0.7), 0), 1, Real(1e-4));
  s.planes.push_back(PlaneDesc{Vec3::UnitY(), 0, {}});
  const Model m = compile(s);
  State st = make_state(m);
  StepConfig cfg;
  cfg.iterations = 4;
  cfg.drag = 1;
  const Real v0 = m.get<GlobalVolume>()[0].rest_volume;
  Real worst = 0;
  for (int i = 0; i < 240; ++i) {
    step(m, st, cfg);
    worst = std::max(worst, std::abs(enclosed(m, st) / v0 - 1));
    Real lowest = st.x[0].y();
    for (const Vec3& p : st.x) lowest = std::min(lowest, p.y());
    ASSERT_GE(lowest, -16 * kEps) << "step " << i;
  }
  Real lowest = st.x[0].y();
  for (const Vec3& p : st.x) lowest = std::min(lowest, p.y());
  std::printf("balloon on floor: max |V/V0 - 1| over 4 s %.3e, final lowest particle y %.3e m\n",
              double(worst), double(lowest));
  EXPECT_LT(worst, Real(1e-3));
  EXPECT_LT(lowest, Real(1e-3));  // it reached the floor
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd

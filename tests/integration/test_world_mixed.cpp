// Integration tests of XpbdWorld next to other Bullet objects: an XPBD cloth
// and a btSoftBody cloth on the same floor in one btSoftRigidDynamicsWorld,
// and a soft (tetrahedral) cube dropped on a static triangle-mesh staircase.
#include <gtest/gtest.h>

#include <BulletSoftBody/btSoftBodyHelpers.h>

#include <cmath>
#include <limits>
#include <algorithm>
#include <cstdio>
#include <memory>
#include <vector>

#include "support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

// ---------------------------------------------------------------------------
// 8. One btSoftRigidDynamicsWorld holds a static floor, an XPBD cloth (through
// XpbdWorld, a btActionInterface) and a btSoftBody cloth. Both cloths must
// land and rest on the floor at their contact distance, and the XPBD action
// must not disturb the btSoftBody at all.

constexpr Real kFloorMargin = Real(0.004);  // m, the floor's collision margin
constexpr Real kSoftMargin = Real(0.006);   // m, the btSoftBody's collision margin
// Rest height of both cloths (m): btSoftBody's node-rigid contact distance
// for a movable node is the sum of both margins (Bullet keeps a box's margin
// inside its dimensions, so the floor's surface itself stays at y = 0); the
// XPBD cloth gets the same value as its thickness (docs/design.md section 5).
constexpr Real kRestHeight = kSoftMargin + kFloorMargin;

struct MixedRun {
  std::vector<Vec3> sb_final;           // btSoftBody node positions at the end, m
  std::vector<std::vector<Vec3>> sb_history;  // every step
  Real sb_lowest = 1e9;                 // lowest node ever, m
  Real sb_ke = 0;                       // J, at the end
  std::vector<Vec3> xpbd_final;
  Real xpbd_lowest = 1e9;
  Real xpbd_ke = 0;
};

// Both cloths: 0.8 m square, 17 x 17 nodes, 0.2 kg, released flat 0.15 m
// above the floor (top face at y = 0), side by side. with_xpbd = false runs
// the same world without the XPBD cloth and its action.
constexpr int kN = 17;
constexpr Real kSize = Real(0.8), kMass = Real(0.2), kY0 = Real(0.15);

MixedRun run_mixed(bool with_xpbd, int steps) {
  BulletWorld bw(Vec3(0, -kG, 0), /*soft=*/true);
  auto* floor_shape = new btBoxShape(btVector3(2, Real(0.5), 2));
  floor_shape->setMargin(kFloorMargin);
  bw.add_body(floor_shape, 0, BulletWorld::at(Vec3(0, Real(-0.5), 0)));
  // The sparse SDF btSoftBody queries: voxels no larger than the thinnest
  // feature that matters (docs/design.md section 5), here 5 cm.
  bw.soft_info().m_sparsesdf.setDefaultVoxelsz(Real(0.05));
  bw.soft_info().m_sparsesdf.Reset();

  const Real h = kSize / 2;
  btSoftBody* sb = btSoftBodyHelpers::CreatePatch(
      bw.soft_info(), btVector3(Real(0.2), kY0, -h), btVector3(Real(0.2) + kSize, kY0, -h),
      btVector3(Real(0.2), kY0, h), btVector3(Real(0.2) + kSize, kY0, h), kN, kN, 0, true);
  sb->getCollisionShape()->setMargin(kSoftMargin);
  sb->setTotalMass(kMass);
  sb->m_cfg.piterations = 10;
  sb->m_cfg.kDF = Real(0.5);  // friction, as the XPBD cloth's 0.5 x the floor's 1
  sb->m_cfg.kDP = 0;
  sb->m_cfg.kCHR = sb->m_cfg.kKHR = 1;  // full contact hardness (docs/design.md section 5)
  sb->setActivationState(DISABLE_DEACTIVATION);
  bw.add_soft_body(sb);

  std::unique_ptr<XpbdWorld> xw;
  xpbd_bullet::SystemId id;
  if (with_xpbd) {
    xw = std::make_unique<XpbdWorld>(bw.world());
    xpbd::SceneDesc scene;
    xpbd::ClothGridDesc d;
    d.nx = d.ny = kN;
    d.size_u = d.size_v = kSize;
    d.u = Vec3::UnitX();
    d.v = Vec3::UnitZ();
    d.origin = Vec3(Real(-0.2) - kSize, kY0, -h);
    d.mass = kMass;
    d.bend_mat.compliance = Real(1e-2);
    xpbd::add_cloth_grid(scene, d);
    System cloth = make_system(scene);
    SystemSettings set;
    set.contacts.thickness = kRestHeight;
    id = xw->add_system(cloth.model, cloth.state, set);
  }

  MixedRun r;
  for (int k = 0; k < steps; ++k) {
    bw.step();
    std::vector<Vec3> nodes;
    for (int i = 0; i < sb->m_nodes.size(); ++i) {
      nodes.push_back(vec(sb->m_nodes[i].m_x));
      r.sb_lowest = std::min(r.sb_lowest, nodes.back().y());
    }
    r.sb_history.push_back(std::move(nodes));
    if (xw)
      for (const Vec3& x : xw->state(id).x) r.xpbd_lowest = std::min(r.xpbd_lowest, x.y());
  }
  r.sb_final = r.sb_history.back();
  for (int i = 0; i < sb->m_nodes.size(); ++i)
    if (sb->m_nodes[i].m_im > 0)
      r.sb_ke += Real(0.5) / sb->m_nodes[i].m_im * sb->m_nodes[i].m_v.length2();
  if (xw) {
    r.xpbd_final = xw->state(id).x;
    r.xpbd_ke = xpbd::kinetic_energy(xw->model(id), xw->state(id));
  }
  return r;
}

Real mean_height(const std::vector<Vec3>& xs) {
  Real y = 0;
  for (const Vec3& x : xs) y += x.y();
  return y / Real(xs.size());
}

TEST(WorldMixed, XpbdClothAndBtSoftBodyClothRestOnTheSameFloor) {
  const int steps = 3 * 60;
  const MixedRun r = run_mixed(true, steps);

  Real xpbd_min = 1e9, xpbd_max = -1e9;
  for (const Vec3& x : r.xpbd_final) {
    xpbd_min = std::min(xpbd_min, x.y());
    xpbd_max = std::max(xpbd_max, x.y());
  }
  Real sb_min = 1e9, sb_max = -1e9;
  for (const Vec3& x : r.sb_final) {
    sb_min = std::min(sb_min, x.y());
    sb_max = std::max(sb_max, x.y());
  }
  // btSoftBody: mean height over the last second, and its range.
  Real sb_mean = 0, sb_mean_lo = 1e9, sb_mean_hi = -1e9;
  for (int k = steps - 60; k < steps; ++k) {
    const Real y = mean_height(r.sb_history[k]);
    sb_mean += y / 60;
    sb_mean_lo = std::min(sb_mean_lo, y);
    sb_mean_hi = std::max(sb_mean_hi, y);
  }
  std::printf("expected rest height %.4g m\n  xpbd: y in [%.6g, %.6g], lowest ever %.6g, KE %.3g J\n"
              "  btSoftBody: y in [%.6g, %.6g], lowest ever %.6g, KE %.3g J, mean height over the "
              "last second %.6g (range %.6g .. %.6g)\n",
              kRestHeight, xpbd_min, xpbd_max, r.xpbd_lowest, r.xpbd_ke, sb_min, sb_max, r.sb_lowest,
              r.sb_ke, sb_mean, sb_mean_lo, sb_mean_hi);

  // XPBD cloth: at rest, kinetic energy below 1e-4 of m g y0 = 0.29 J (a
  // mean particle speed of 1.7 cm/s would exceed it)...
  const Real e0 = kMass * kG * kY0;
  EXPECT_LT(r.xpbd_ke, Real(1e-4) * e0);
  // ... flat at the contact distance. The contact is solved to C = 0 every
  // substep; gravity adds g h^2 = 2.7e-5 m (h = 1/600 s) before the next
  // projection: 1e-4 m covers it.
  EXPECT_NEAR(xpbd_min, kRestHeight, Real(1e-4));
  EXPECT_NEAR(xpbd_max, kRestHeight, Real(1e-4));
  EXPECT_GT(r.xpbd_lowest, 0);  // never below the floor's surface

  // btSoftBody cloth. Its contact is a velocity-level projection that acts
  // once a node is inside the contact distance, after the node's predicted
  // motion of the step, so a node rests within one step of gravity travel,
  // g dt^2 = 2.7 mm, of the contact distance. With kDP = 0 (the fairness
  // setting) the nodes never settle completely: they keep jittering by about
  // a centimetre (measured, printed above; docs/bullet-bridge.md), so rest
  // is checked on the cloth as a whole: its mean height, averaged over the
  // last second, is within g dt^2 of the contact distance (a cloth still
  // falling or bouncing would be centimetres off), and no node ever goes
  // below the floor's surface.
  const Real g_dt2 = kG * kDt * kDt;
  EXPECT_NEAR(sb_mean, kRestHeight, g_dt2);
  EXPECT_GT(r.sb_lowest, 0);
}

// The XPBD action does not touch the btSoftBody: with a static floor there
// is nothing they share, so the btSoftBody's trajectory must be bitwise the
// same with and without the XPBD cloth in the world.
TEST(WorldMixed, XpbdActionLeavesBtSoftBodyTrajectoryUnchanged) {
  const int steps = 60;
  const MixedRun with = run_mixed(true, steps);
  const MixedRun without = run_mixed(false, steps);
  ASSERT_EQ(with.sb_history.size(), without.sb_history.size());
  for (int k = 0; k < steps; ++k)
    for (std::size_t i = 0; i < with.sb_history[k].size(); ++i)
      ASSERT_EQ(with.sb_history[k][i], without.sb_history[k][i]) << "step " << k << " node " << i;
  // It did land (so the comparison covers contacts, not just free fall).
  EXPECT_LT(mean_height(without.sb_final), kRestHeight + Real(0.01));
}

// ---------------------------------------------------------------------------
// 9. A soft cube (tetrahedra) dropped onto a static triangle-mesh staircase
// (btBvhTriangleMeshShape): it comes to rest on a step, and no vertex ever
// gets inside the stairs.
//
// The staircase descends along +x: step k (k = 0..3) covers x in
// [k run, (k+1) run], z in [-w, w], and is solid from y = 0 up to its tread at
// y = (4 - k) rise. The mesh holds the treads (facing +y) and the risers
// (facing +x, down each step, including the last one down to y = 0), wound
// counter-clockwise seen from the open side (narrowphase.hpp: triangle meshes
// are one-sided, front = counter-clockwise side).

constexpr int kSteps = 4;
constexpr Real kRise = Real(0.1), kRun = Real(0.4), kHalfWidth = Real(0.5);  // m

Real tread_height(int k) { return Real(kSteps - k) * kRise; }

// Height (m) of the stairs' top surface above (x, z), or -infinity outside.
Real stair_height(Real x, Real z) {
  if (x < 0 || x > kSteps * kRun || std::abs(z) > kHalfWidth) return -std::numeric_limits<Real>::infinity();
  const int k = std::min(kSteps - 1, static_cast<int>(x / kRun));
  return tread_height(k);
}

void add_quad(btTriangleMesh& mesh, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // Quad a, b, c, d counter-clockwise seen from its front.
  mesh.addTriangle(bt(a), bt(b), bt(c));
  mesh.addTriangle(bt(a), bt(c), bt(d));
}

struct StairsRun {
  Real deepest = -1e9;  // m, deepest vertex inside the stairs over the run (<= 0: none)
  Real bottom_lo = 0, bottom_hi = 0;  // m, height range of the cube's bottom face at the end
  Real ke = 0;          // J, at the end
  Vec3 com = Vec3::Zero();
  std::vector<Vec3> x;  // m, final vertex positions
};

// Vertices of r within tol (m) of height y.
int vertices_at(const StairsRun& r, Real y, Real tol) {
  int n = 0;
  for (const Vec3& x : r.x) n += std::abs(x.y() - y) <= tol;
  return n;
}

constexpr Real kCube = Real(0.2);  // m, cube side
constexpr Real kThickness = Real(0.005);  // m

// The cube (bottom face centre at `start`, velocity v0) on the stairs.
StairsRun run_stairs(const Vec3& start, const Vec3& v0, Real seconds) {
  BulletWorld bw;
  auto mesh = std::make_unique<btTriangleMesh>();
  const Real w = kHalfWidth;
  for (int k = 0; k < kSteps; ++k) {
    const Real x0 = k * kRun, x1 = (k + 1) * kRun, y = tread_height(k);
    const Real y_below = k + 1 < kSteps ? tread_height(k + 1) : Real(0);
    // Tread, normal +y: (x0,-w) -> (x0,+w) -> (x1,+w) -> (x1,-w) is
    // counter-clockwise seen from above.
    add_quad(*mesh, Vec3(x0, y, -w), Vec3(x0, y, w), Vec3(x1, y, w), Vec3(x1, y, -w));
    // Riser at x1, normal +x.
    add_quad(*mesh, Vec3(x1, y_below, -w), Vec3(x1, y, -w), Vec3(x1, y, w), Vec3(x1, y_below, w));
  }
  auto* shape = new btBvhTriangleMeshShape(mesh.get(), true);
  bw.add_body(shape, 0, BulletWorld::at(Vec3::Zero()));
  XpbdWorld xw(bw.world());

  // A 0.2 m soft cube of 2 x 2 x 2 cells (six tets each), 1 kg, bulk modulus
  // 1 MPa.
  const Real a = kCube;
  xpbd::SceneDesc scene;
  xpbd::TetBoxDesc d;
  d.nx = d.ny = d.nz = 2;
  d.size = Vec3::Constant(a);
  d.origin = start - Vec3(a / 2, 0, a / 2);
  d.mass = 1;
  d.bulk_modulus = Real(1e6);
  d.edge_mat.compliance = Real(1e-6);  // m/N: a stiff rubber-like block
  const xpbd::TetBox box = xpbd::add_tet_box(scene, d);
  scene.velocities.assign(scene.positions.size(), v0);
  System cube = make_system(scene);
  SystemSettings set;
  set.iterations = 4;
  set.contacts.thickness = kThickness;
  const auto id = xw.add_system(cube.model, cube.state, set);

  StairsRun r;
  const int steps = static_cast<int>(std::lround(seconds / kDt));
  for (int k = 0; k < steps; ++k) {
    bw.step();
    for (const Vec3& x : xw.state(id).x) r.deepest = std::max(r.deepest, stair_height(x.x(), x.z()) - x.y());
  }
  const xpbd::State& s = xw.state(id);
  r.bottom_lo = 1e9;
  r.bottom_hi = -1e9;
  for (int i = 0; i <= d.nx; ++i)
    for (int kk = 0; kk <= d.nz; ++kk) {
      const Real y = s.x[box.at(i, 0, kk)].y();
      r.bottom_lo = std::min(r.bottom_lo, y);
      r.bottom_hi = std::max(r.bottom_hi, y);
    }
  r.ke = xpbd::kinetic_energy(xw.model(id), s);
  r.com = centre_of_mass(xw.model(id), s);
  r.x = s.x;
  std::printf("deepest vertex inside the stairs: %.3g m; bottom face y in [%.6g, %.6g]; KE %.3g J; "
              "centre of mass (%.4g %.4g %.4g)\n",
              r.deepest, r.bottom_lo, r.bottom_hi, r.ke, r.com.x(), r.com.y(), r.com.z());
  return r;
}

// Dropped 0.1 m onto the middle of step 1's tread.
TEST(WorldMixed, SoftCubeComesToRestOnTriangleMeshStairsWithoutEnteringThem) {
  const int step = 1;
  const Real drop = Real(0.1), x_mid = (step + Real(0.5)) * kRun;
  const StairsRun r = run_stairs(Vec3(x_mid, tread_height(step) + drop, 0), Vec3::Zero(), 3);
  // No vertex ever inside the stairs (the closed form above: below the top
  // surface over the stairs' footprint).
  EXPECT_LT(r.deepest, 0);
  // Resting on step 1: the bottom face at tread + thickness, within g h^2 of
  // the contact solution (h = 1/600 s: 2.7e-5 m; 1e-4 m allowed), and the
  // cube's centre still over step 1.
  const Real rest = tread_height(step) + kThickness;
  EXPECT_NEAR(r.bottom_lo, rest, Real(1e-4));
  EXPECT_NEAR(r.bottom_hi, rest, Real(1e-4));
  EXPECT_NEAR(r.com.x(), x_mid, kRun / 2 - kCube / 2);
  // At rest: kinetic energy below 1e-4 of the energy of the fall m g drop
  // = 0.98 J (a 1 kg block moving at 1.4 cm/s would exceed it).
  EXPECT_LT(r.ke, Real(1e-4) * 1 * kG * drop);
}

// Pushed off step 0 at 1.5 m/s: it flies over the edge, hits lower treads
// (and possibly a riser) and must end at rest flat on one of the steps.
TEST(WorldMixed, SoftCubeThrownDownTheStairsComesToRestOnALowerStep) {
  const StairsRun r = run_stairs(Vec3(Real(0.15), tread_height(0) + Real(0.01), 0),
                                 Vec3(Real(1.5), 0, 0), 4);
  EXPECT_LT(r.deepest, 0);
  // Which step is it on? The one under its centre of mass.
  ASSERT_GT(r.com.x(), kRun) << "did not leave step 0";
  ASSERT_LT(r.com.x(), kSteps * kRun) << "left the stairs";
  const int k = static_cast<int>(r.com.x() / kRun);
  // It may have tumbled: whichever face is down, its 3 x 3 vertices lie at
  // tread + thickness (within the g h^2 bound above) and none lower.
  const Real rest = tread_height(k) + kThickness;
  Real lowest = 1e9;
  for (const Vec3& x : r.x) lowest = std::min(lowest, x.y());
  EXPECT_NEAR(lowest, rest, Real(1e-4)) << "step " << k;
  EXPECT_EQ(vertices_at(r, rest, Real(1e-4)), 9) << "not lying flat on step " << k;
  EXPECT_LT(r.ke, Real(1e-4) * 1 * kG * kRise);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

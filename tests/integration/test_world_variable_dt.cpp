// The sequence in a Bullet world: a 24 x 24 cloth (0.4 kg) draped
// over a static sphere on a plane, stepped at 1/60 s (stepSimulation(dt, 0):
// one internal step of dt, 10 XPBD substeps), then one step of 1e-4 s, then
// 1/60 s again. Before the velocity update took a shrinking step into
// account (step.cpp, update_velocities) the one short step threw the cloth
// 15 m up (kinetic energy 0.002 J -> 88 J). Closed form: over 1e-4 s gravity
// and the contacts can change the kinetic energy of a cloth moving at
// < 0.4 m/s by no more than M g v t ~ 2e-5 J; afterwards the cloth must move
// as the same cloth stepped at 1/60 s throughout (the control), whose
// largest kinetic energy over the next second bounds it. The same for thirty
// steps of 1e-4 s in a row (a step that stays short for 3 ms). Measured:
// 0.00197 J before, 0.00196 J after one short step and 0.00203 J after
// thirty; 0.0212 J largest over the next second in both, against the
// control's 0.0231 J (before the fix: 88 J and 1,450 J after the short
// steps).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;

Real kinetic(const xpbd::Model& m, const xpbd::State& s) {
  Real e = 0;
  for (std::size_t i = 0; i < s.v.size(); ++i)
    if (m.inv_mass[i] > Real(0)) e += Real(0.5) / m.inv_mass[i] * s.v[i].squaredNorm();
  return e;
}

struct DtRun {
  Real before = 0, after_short = 0, next_second = 0;
  bool finite = true;
};

DtRun run(int short_steps, Real short_dt) {
  BulletWorld bw;
  bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, BulletWorld::at(Vec3::Zero()));
  bw.add_static_sphere(Real(0.3), Vec3(0, 0.5, 0));
  xpbd_bullet::XpbdWorld xw(bw.world());
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc c;
  c.nx = c.ny = 24;
  c.mass = Real(0.4);
  c.origin = Vec3(-0.5, 1.0, -0.5);
  c.v = Vec3::UnitZ();  // horizontal
  xpbd::add_cloth_grid(scene, c);
  System sys = make_system(scene);
  const auto id = xw.add_system(sys.model, sys.state, {});
  const auto ke = [&] { return kinetic(xw.model(id), xw.state(id)); };
  for (int k = 0; k < 180; ++k) bw.world().stepSimulation(kDt, 0);  // draped, at rest
  DtRun r;
  r.before = ke();
  for (int k = 0; k < short_steps; ++k) bw.world().stepSimulation(short_dt, 0);
  r.after_short = ke();
  for (int k = 0; k < 60; ++k) {
    bw.world().stepSimulation(kDt, 0);
    r.next_second = std::max(r.next_second, ke());
  }
  for (const Vec3& x : xw.state(id).x) r.finite = r.finite && x.allFinite();
  return r;
}

TEST(WorldVariableDt, ShortStepsAddNoEnergy) {
  const DtRun control = run(0, 0), one = run(1, Real(1e-4)), thirty = run(30, Real(1e-4));
  std::printf("kinetic energy (J): before %.3g, after one 1e-4 s step %.3g; largest over the next second: "
              "%.3g (control at 1/60 s: %.3g); after 30 steps of 1e-4 s: %.3g, next second %.3g\n",
              double(one.before), double(one.after_short), double(one.next_second),
              double(control.next_second), double(thirty.after_short), double(thirty.next_second));
  ASSERT_TRUE(one.finite && thirty.finite);
  EXPECT_LE(one.after_short, one.before + Real(2e-5));
  EXPECT_LE(one.next_second, Real(1.1) * control.next_second);
  EXPECT_LE(thirty.after_short, thirty.before + 30 * Real(2e-5));
  EXPECT_LE(thirty.next_second, Real(1.1) * control.next_second);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

// The contact report and the step callback of XpbdWorld (world.hpp).
//
// Closed forms: a cloth at rest on a body pushes it with its weight, so the
// impulse over one step is M g dt, straight down; in zero gravity the
// impulses the report gives a free body add up to that body's momentum
// change as Bullet integrates it (nothing else acts on it). The callback
// runs once per internal step, with the system's id and Bullet's fixed step.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

// A 0.2 m square cloth of `mass` kg, 6 x 6, lying flat at height y.
System small_cloth(Real y, Real mass, const Vec3& v0 = Vec3::Zero()) {
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc d;
  d.nx = d.ny = 6;
  d.size_u = d.size_v = Real(0.2);
  d.origin = Vec3(Real(-0.1), y, Real(-0.1));
  d.u = Vec3::UnitX();
  d.v = Vec3::UnitZ();
  d.mass = mass;
  xpbd::add_cloth_grid(scene, d);
  System s = make_system(scene);
  for (auto& v : s.state.v) v = v0;
  return s;
}

TEST(WorldReport, ClothAtRestPushesItsSupportWithItsWeight) {
  for (const Real box_mass : {Real(0), Real(2)}) {  // static, then dynamic on the ground
    BulletWorld bw;
    bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, BulletWorld::at(Vec3::Zero()));
    btRigidBody* box = bw.add_body(new btBoxShape(btVector3(Real(0.2), Real(0.1), Real(0.2))), box_mass,
                                   BulletWorld::at(Vec3(0, Real(0.1), 0)));
    btRigidBody* far = bw.add_static_sphere(Real(0.1), Vec3(2, Real(0.1), 0));  // never touched
    XpbdWorld xw(bw.world());
    const Real M = Real(0.3);
    const System cloth = small_cloth(Real(0.21), M);
    const auto id = xw.add_system(cloth.model, cloth.state);
    EXPECT_TRUE(xw.contact_report(id).empty());
    for (int f = 0; f < 120; ++f) bw.step();
    const auto& report = xw.contact_report(id);
    ASSERT_EQ(report.size(), 1u) << "box mass " << box_mass;
    EXPECT_EQ(report[0].body, box);
    EXPECT_NE(report[0].body, far);
    const Vec3 j = vec(report[0].impulse);
    std::printf("box of %g kg: impulse over one step (%g, %g, %g) N s, M g dt = %g N s\n", double(box_mass),
                double(j.x()), double(j.y()), double(j.z()), double(M * kG * kDt));
    EXPECT_NEAR(j.y(), -M * kG * kDt, 0.01 * M * kG * kDt) << "box mass " << box_mass;
    EXPECT_NEAR(Vec3(j.x(), 0, j.z()).norm(), 0, 1e-3 * M * kG * kDt) << "box mass " << box_mass;
  }
}

TEST(WorldReport, ImpulsesOnAFreeBodyAddUpToItsMomentumChange) {
  BulletWorld bw(Vec3::Zero());
  const Real mb = 1;
  btRigidBody* box = bw.add_body(new btBoxShape(btVector3(Real(0.2), Real(0.1), Real(0.2))), mb,
                                 BulletWorld::at(Vec3(0, 0, 0)));
  XpbdWorld xw(bw.world());
  // The cloth flies down onto the box's top at 3 m/s.
  const System cloth = small_cloth(Real(0.3), Real(0.5), Vec3(0, -3, 0));
  const auto id = xw.add_system(cloth.model, cloth.state);
  Vec3 sum = Vec3::Zero();
  bool touched = false;
  for (int f = 0; f < 30; ++f) {
    bw.step();
    for (const auto& r : xw.contact_report(id)) {
      EXPECT_EQ(r.body, box);
      sum += vec(r.impulse);
      touched = true;
    }
  }
  ASSERT_TRUE(touched);
  const Vec3 p = mb * vec(box->getLinearVelocity());
  std::printf("sum of the reported impulses (%g, %g, %g) N s, box momentum (%g, %g, %g) N s\n", double(sum.x()),
              double(sum.y()), double(sum.z()), double(p.x()), double(p.y()), double(p.z()));
  EXPECT_LT(sum.y(), -Real(0.5));  // a real push: most of the cloth's 1.5 N s
  // Round-off only: the hand-over gives Bullet the shadow's velocity change.
  EXPECT_NEAR((sum - p).norm(), 0, (sizeof(Real) == 4 ? 1e-4 : 1e-9) * p.norm());
}

TEST(WorldReport, CallbackRunsOncePerInternalStepAndItsErrorsStayInside) {
  BulletWorld bw;
  XpbdWorld xw(bw.world());
  const System a = small_cloth(1, Real(0.1)), b = small_cloth(2, Real(0.1));
  const auto ia = xw.add_system(a.model, a.state), ib = xw.add_system(b.model, b.state);
  std::vector<std::pair<xpbd_bullet::SystemId, btScalar>> calls;
  Real time_seen = -1;
  xw.set_step_callback(ia, [&](xpbd_bullet::SystemId id, btScalar dt) {
    calls.emplace_back(id, dt);
    time_seen = xw.state(id).time;  // the state after this step
  });
  // Two internal steps in one stepSimulation call.
  bw.world().stepSimulation(2 * kDt, 2, kDt);
  ASSERT_EQ(calls.size(), 2u);
  for (const auto& [id, dt] : calls) {
    EXPECT_EQ(id, ia);
    EXPECT_EQ(dt, btScalar(kDt));
  }
  EXPECT_NEAR(time_seen, 2 * kDt, 1e-6);
  // A throwing callback stops its system only; stepSimulation does not throw.
  xw.set_step_callback(ib, [](xpbd_bullet::SystemId, btScalar) { throw std::runtime_error("boom"); });
  EXPECT_NO_THROW(bw.step());
  EXPECT_EQ(xw.error(ib), "step callback: boom");
  EXPECT_TRUE(xw.error(ia).empty());
  const Real tb = xw.state(ib).time;
  bw.step();
  EXPECT_EQ(xw.state(ib).time, tb);  // frozen
  EXPECT_EQ(calls.size(), 4u);       // a went on
  // A callback may remove its own system; an empty one is removed.
  xw.set_step_callback(ia, [&](xpbd_bullet::SystemId id, btScalar) { xw.remove_system(id); });
  EXPECT_NO_THROW(bw.step());
  EXPECT_FALSE(xw.has_system(ia));
  EXPECT_THROW(xw.set_step_callback(ia, {}), std::out_of_range);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

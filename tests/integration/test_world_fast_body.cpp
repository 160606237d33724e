// A fast rigid body reaching particles within one step (issue 16: the
// contact search along the bodies' motion, not only the particles'). No
// gravity; a box of 1 kg (half extent 0.1 m) slides at 10 m/s (0.17 m per
// 60 Hz step, more than its half extent) at particles at rest.
//
// Closed forms, restitution 0 (the default): the box pushes a particle
// ahead of its face. Momentum is conserved; kinetic energy cannot grow.
// A perfectly inelastic hit leaves both at the common speed v M / (M + m):
//  - a particle of 1 kg: 5 m/s (25 J of the 50 J);
//  - a particle of 10 g: 9.90 m/s, carried ahead of the box.
// In both, no particle centre deeper inside the box than the contact
// thickness at any frame.
// Before the bodies' motion widened the search (bullet_bridge,
// detail::add_moving_candidates) the box reached the particle without a
// contact, and the next step pushed the 1 kg particle out of its middle at
// 36.5 m/s and the box back at -26.5 m/s (kinetic energy 50 J -> 1017 J).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "support.hpp"
#include "xpbd_bullet/narrowphase.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::XpbdWorld;

struct Hit {
  Real energy_max = 0;    // J, box + particle, largest over the run
  Real momentum_end = 0;  // kg m/s along x at the end
  Real particle_speed = 0, box_speed = 0;  // m/s at the end
  Real deepest = 0;       // m, deepest particle centre inside the box over the run
};

Hit hit(Real particle_mass, Real speed) {
  BulletWorld bw(Vec3::Zero());
  XpbdWorld xw(bw.world());
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3(0, 0, 0), particle_mass);
  System s = make_system(scene);
  const auto id = xw.add_system(s.model, s.state);
  btRigidBody* box =
      bw.add_body(new btBoxShape(btVector3(0.1f, 0.1f, 0.1f)), 1, BulletWorld::at(Vec3(Real(-0.5), 0, 0)));
  box->setLinearVelocity(btVector3(speed, 0, 0));
  Hit h;
  for (int k = 0; k < 30; ++k) {
    bw.step();
    const xpbd::State& st = xw.state(id);
    const Real vb = box->getLinearVelocity().length();
    h.energy_max = std::max(h.energy_max, Real(0.5) * (particle_mass * st.v[0].squaredNorm() + vb * vb));
    xpbd_bullet::ParticleContact pc;
    if (xpbd_bullet::query_point(*box, st.x[0], 0, pc)) h.deepest = std::max(h.deepest, -pc.distance);
  }
  const xpbd::State& st = xw.state(id);
  h.momentum_end = particle_mass * st.v[0].x() + box->getLinearVelocity().x();
  h.particle_speed = st.v[0].norm();
  h.box_speed = box->getLinearVelocity().length();
  return h;
}

TEST(WorldFastBody, BoxAtTenMetresPerSecondPushesParticlesAhead) {
  const Real v = 10, thickness = xpbd_bullet::ContactSettings{}.thickness;
  for (Real mass : {Real(1), Real(0.01)}) {
    const Hit h = hit(mass, v);
    std::printf("particle %.3g kg, box 1 kg at %.3g m/s: particle %.4g m/s, box %.4g m/s, momentum %.5g kg m/s "
                "(%.5g before), largest kinetic energy %.4g J (%.4g before), deepest %.3g m\n",
                double(mass), double(v), double(h.particle_speed), double(h.box_speed), double(h.momentum_end),
                double(v), double(h.energy_max), double(Real(0.5) * v * v), double(h.deepest));
    EXPECT_NEAR(h.momentum_end, v, Real(1e-3) * v);
    EXPECT_LE(h.energy_max, Real(0.5) * v * v * Real(1.001));
    EXPECT_LE(h.particle_speed, v * Real(1.01));
    EXPECT_LE(h.deepest, thickness);
    const Real common = v / (1 + mass);  // box of 1 kg
    EXPECT_NEAR(h.particle_speed, common, Real(0.01) * v);
    EXPECT_NEAR(h.box_speed, common, Real(0.01) * v);
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

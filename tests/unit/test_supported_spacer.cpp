// A light particle between a heavy body above and a light body that rests
// on the static world below (a cloth between a box and a crate on the
// floor), without Bullet: the joint block of the particle's contacts
// (xpbd/src/contact_block.cpp) takes the lower body as held by the world
// when the push on it goes into its support, inside the friction cone of
// its contacts with the static world and through their support polygon.
// Closed forms, one substep, no gravity: the upper body's face starts
// 1 mm inside the particle's band.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "xpbd/xpbd.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Real;
using xpbd::Vec3;

constexpr Real kT = Real(0.005);      // m, the contacts' thickness
constexpr Real kSlabHalf = Real(0.05);  // m, the slab's half height
constexpr Real kOverlap = Real(0.001);  // m, the upper body's face inside the band

struct Scene {
  xpbd::Model m;
  xpbd::State s;
};

// A 1 kg slab (1 m x 0.1 m x 1 m) whose lower face lies on the plane y = 0,
// touching it at the corners of [x_lo, x_hi] x [-0.5, 0.5] (a slab over a
// ledge: x_hi < 0.5); a 1 g particle on its top face at x = px, at the band;
// a 100 kg body above, its lower face kOverlap inside the particle's band.
Scene stack(Real x_lo, Real x_hi, Real px, Real mu = Real(0.5)) {
  xpbd::SceneDesc scene;
  const Real top = 2 * kSlabHalf;
  scene.add_particle(Vec3(px, top + kT, 0), Real(1e-3));
  Scene u{xpbd::compile(scene), {}};
  u.s = xpbd::make_state(u.m);
  xpbd::RigidBody slab;
  slab.x = Vec3(0, kSlabHalf, 0);
  slab.inv_mass = 1;
  slab.inv_inertia = Vec3(12 / (0.01 + 1.0), 12 / 2.0, 12 / (1.0 + 0.01));
  xpbd::RigidBody heavy;
  heavy.x = Vec3(px, top + 2 * kT - kOverlap + Real(0.05), 0);
  heavy.inv_mass = Real(0.01);
  heavy.inv_inertia = Vec3::Constant(Real(0.1));
  u.s.bodies = {slab, heavy};
  for (Real x : {x_lo, x_hi})
    for (Real z : {Real(-0.5), Real(0.5)}) {
      xpbd::BodyWorldContact c;
      c.body = 0;
      c.r = Vec3(x, -kSlabHalf, z);
      c.p = Vec3(x, 0, z);
      c.n = Vec3::UnitY();
      c.friction = mu;
      u.s.world_contacts.push_back(c);
    }
  xpbd::BodyContact on_slab;  // the slab's top face, normal +y
  on_slab.particle = 0;
  on_slab.body = 0;
  on_slab.r = Vec3(px, kSlabHalf, 0);
  on_slab.n = Vec3::UnitY();
  on_slab.thickness = kT;
  xpbd::BodyContact under_heavy;  // the heavy body's lower face, normal -y
  under_heavy.particle = 0;
  under_heavy.body = 1;
  under_heavy.r = Vec3(0, Real(-0.05), 0);
  under_heavy.n = Vec3(0, -1, 0);
  under_heavy.thickness = kT;
  u.s.contacts = {on_slab, under_heavy};
  return u;
}

xpbd::StepConfig one_substep() {
  xpbd::StepConfig cfg;
  cfg.gravity.setZero();
  cfg.substeps = 1;
  cfg.dt = Real(1) / 60;
  return cfg;
}

// Round-off of positions about 0.2 m, and of the joint solve's
// cancellation (in double) at a mass ratio of 1e5.
double tol() {
  return 64 * 0.2 * std::numeric_limits<Real>::epsilon() + 16 * 1e-3 * 1e5 * std::numeric_limits<double>::epsilon();
}

// The push goes straight down, through the slab's support: the floor holds
// the slab, the particle is a spacer, and the heavy body takes the whole
// correction. Before, the slab took w_slab / (w_slab + w_heavy) = 99 % of
// it, the floor then pushed the slab back, and the heavy body rose by 1 %
// of the overlap per substep; the rest came out over the next substeps as
// an upward speed (a 100 kg box landing on a cloth on a 20 kg crate at
// 1.8 m/s bounced back at 1.3 m/s at 45 substeps).
TEST(SupportedSpacer, BodyOnTheFloorHoldsThePushAndTheHeavyBodyTakesIt) {
  Scene u = stack(Real(-0.5), Real(0.5), Real(0.2));
  const Vec3 slab_x = u.s.bodies[0].x;
  xpbd::step(u.m, u.s, one_substep());
  EXPECT_NEAR(double(u.s.bodies[1].x.y()), double(2 * kSlabHalf + 2 * kT + Real(0.05)), tol());
  EXPECT_NEAR(double(u.s.x[0].y()), double(2 * kSlabHalf + kT), tol());
  EXPECT_NEAR(double((u.s.bodies[0].x - slab_x).norm()), 0.0, tol());
  EXPECT_NEAR(double(u.s.bodies[0].q.vec().norm()), 0.0, tol());
}

// The same push outside the support polygon (the slab rests on the floor
// only for x in [-0.5, 0]; the particle is at x = 0.4, over the ledge):
// the floor does not hold it there, so the slab turns about the ledge and
// the heavy body rises by less than the overlap.
TEST(SupportedSpacer, PushOutsideTheSupportPolygonTurnsTheBody) {
  Scene u = stack(Real(-0.5), Real(0), Real(0.4));
  xpbd::step(u.m, u.s, one_substep());
  const Real risen = u.s.bodies[1].x.y() - (2 * kSlabHalf + 2 * kT - kOverlap + Real(0.05));
  EXPECT_LT(risen, Real(0.5) * kOverlap);
  EXPECT_GT(u.s.bodies[0].q.vec().norm(), Real(1e-4));  // turned
}

// A push at 45 degrees to the floor (down and along +x), outside the
// friction cone of the slab's floor contacts (mu = 0.5): the floor cannot
// hold the slab against its sideways part, so it is not taken as held and
// the slab moves along +x. Inside the cone (mu = 1.5) it is held.
TEST(SupportedSpacer, PushOutsideTheFrictionConeMovesTheBody) {
  Scene u = stack(Real(-0.5), Real(0.5), Real(0));
  const Vec3 n = Vec3(1, -1, 0).normalized();  // the heavy body's face, leaning
  u.s.contacts[1].n = n;
  u.s.contacts[0].n = -n;
  u.s.contacts[0].r = Vec3(0, kSlabHalf, 0);
  const Real x0 = u.s.bodies[0].x.x();
  xpbd::step(u.m, u.s, one_substep());
  EXPECT_GT(u.s.bodies[0].x.x(), x0 + Real(1e-5));  // pushed along +x by the particle
  // Inside the cone (mu = 1.5) the floor holds it.
  Scene held = stack(Real(-0.5), Real(0.5), Real(0), Real(1.5));
  held.s.contacts[1].n = n;
  held.s.contacts[0].n = -n;
  held.s.contacts[0].r = Vec3(0, kSlabHalf, 0);
  xpbd::step(held.m, held.s, one_substep());
  EXPECT_NEAR(double(held.s.bodies[0].x.x()), double(x0), tol());
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

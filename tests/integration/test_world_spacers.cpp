// ContactSettings::spacers: the cloth between two bodies is seen by
// Bullet's solver, which then cannot push them together through it.
//
// The scene (no gravity): a hanging cloth (top edge pinned) between two
// coupled boxes, each 9 mm from it, inside the contact margin. The first
// box is on a slider joint whose motor drives it towards the cloth and the
// second box at 3 m/s. XPBD does not see Bullet's joints, so inside every
// Bullet step the motor, in Bullet's solve, pushes the first box on after
// XPBD has run, and the second box through Bullet's own contact with it.
// Without spacers the two boxes close on each other with the cloth between
// them, and no position fix of the particles alone can put the cloth back
// outside both.
//
// The spacers are contacts of Bullet's velocity solve. Bullet's split
// impulse (its penetration recovery, on by default) moves apart bodies
// that its own contacts found interpenetrating, and it does not see them:
// a box striking the first box from 0.2 m away at 6 m/s, which ends inside
// it, closed the two boxes to 2.4 mm (12.2 mm with m_splitImpulse off,
// 18 mm before the strike).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "support.hpp"
#include "xpbd_bullet/narrowphase.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

constexpr Real kHalf = Real(0.1);   // m, half side of the boxes
constexpr Real kGap = Real(0.009);  // m, each coupled box's face to the cloth
constexpr Real kSpeed = 3;          // m/s, the motor's target speed
constexpr int kFrames = 40;

struct Outcome {
  Real deepest = 0;      // m, deepest particle centre inside either coupled box, over all frames
  Real closest = 1;      // m, smallest gap between the two coupled boxes' facing faces, over all frames
  int spacers = 0;       // spacer points added, summed over steps
  Real speed = 0;        // m/s, the far coupled box's speed at the end
};

Outcome run(bool spacers, bool wedges) {
  BulletWorld bw(Vec3::Zero());
  const Vec3 near_at(0, Real(0.3), -kHalf - kGap), far_at(0, Real(0.3), kHalf + kGap);
  btRigidBody* near = bw.add_body(new btBoxShape(btVector3(kHalf, kHalf, kHalf)), 1, BulletWorld::at(near_at));
  btRigidBody* far = bw.add_body(new btBoxShape(btVector3(kHalf, kHalf, kHalf)), 1, BulletWorld::at(far_at));
  // The slider's axis is its frame's x: turned onto the world's z.
  const btTransform axis(btQuaternion(btVector3(0, 1, 0), -kPi / 2));
  btSliderConstraint motor(*near, axis, true);
  motor.setLowerLinLimit(-1);
  motor.setUpperLinLimit(1);
  motor.setPoweredLinMotor(true);
  motor.setTargetLinMotorVelocity(kSpeed);
  motor.setMaxLinMotorForce(1000);  // N: holds its speed against the cloth and the second box
  bw.world().addConstraint(&motor);
  XpbdWorld xw(bw.world());
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc c;
  c.nx = c.ny = 16;
  c.size_u = c.size_v = Real(0.6);
  c.mass = Real(0.2);
  c.origin = Vec3(Real(-0.3), Real(0.6), 0);  // vertical, in the plane z = 0
  c.pins = xpbd::ClothPins::top_edge;
  xpbd::add_cloth_grid(scene, c);
  System sys = make_system(scene);
  SystemSettings set;
  set.contacts.spacers = spacers;
  set.contacts.wedges = wedges;
  const xpbd_bullet::SystemId id = xw.add_system(sys.model, sys.state, set);
  Outcome r;
  for (int f = 0; f < kFrames; ++f) {
    bw.step();
    r.spacers += xw.last_stats().spacers;
    for (const Vec3& x : xw.state(id).x)
      for (const btRigidBody* b : {near, far}) {
        xpbd_bullet::ParticleContact pc;
        if (xpbd_bullet::query_point(*b, x, 0, pc)) r.deepest = std::max(r.deepest, -pc.distance);
      }
    // The boxes stay square to z (struck face-on, along the line of centres).
    const Real gap = Real(far->getCenterOfMassPosition().z() - near->getCenterOfMassPosition().z()) - 2 * kHalf;
    r.closest = std::min(r.closest, gap);
  }
  r.speed = Real(far->getLinearVelocity().length());
  bw.world().removeConstraint(&motor);
  return r;
}

TEST(Spacers, ClothBetweenTwoBodiesThatBulletPushesTogether) {
  const Real thickness = xpbd_bullet::ContactSettings{}.thickness;
  // Wedges off in both (ContactSettings::wedges moves a box out of the
  // cloth after Bullet's solve; WedgesAloneKeepTheClothOutOfBoth below).
  const Outcome on = run(true, false), off = run(false, false);
  std::printf("cloth between two boxes, one driven at %.3g m/s: smallest gap between the boxes %.4g m "
              "(spacers) / %.4g m (none), twice the thickness %.3g m; deepest particle centre in a box %.4g m "
              "/ %.4g m; %d spacer points; far box at %.3g / %.3g m/s\n",
              double(kSpeed), double(on.closest), double(off.closest), double(2 * thickness), double(on.deepest),
              double(off.deepest), on.spacers, double(on.speed), double(off.speed));
  // The motor's push reaches the far box in both runs.
  EXPECT_GT(on.speed, Real(1));
  EXPECT_GT(off.speed, Real(1));
  // Without spacers the boxes close on the cloth, which ends inside one.
  EXPECT_EQ(off.spacers, 0);
  EXPECT_LT(off.closest, thickness);
  EXPECT_GT(off.deepest, thickness);
  // With them, the boxes stay apart by more than one thickness (the cloth's
  // two thicknesses are 10 mm; measured 12.7 mm in double and 8.5 mm in
  // float, where Bullet's iterative solve of the motor, the spacers and
  // the boxes' own contact ends differently), and no particle centre is
  // inside either box.
  EXPECT_GT(on.spacers, 0);
  EXPECT_GE(on.closest, thickness);
  EXPECT_LE(on.deepest, Real(0));
}

// Without spacers, with ContactSettings::wedges (the default): the settle
// pass cannot put the particles outside both boxes that Bullet pushed
// together, and moves the boxes out of them instead. Closed form: the
// cloth is one layer of particles of radius 0 kept a thickness t from
// each face, so the boxes end no closer than 2 t (to round-off), and no
// particle centre is inside either. The motor's push still reaches the far
// box.
TEST(Spacers, WedgesAloneKeepTheClothOutOfBoth) {
  const Real thickness = xpbd_bullet::ContactSettings{}.thickness;
  const Outcome r = run(false, true);
  std::printf("wedges without spacers: smallest gap %.6g m (2 t = %.3g m), deepest particle centre %.3g m, far "
              "box at %.3g m/s\n",
              double(r.closest), double(2 * thickness), double(r.deepest), double(r.speed));
  EXPECT_EQ(r.spacers, 0);
  EXPECT_GE(r.closest, 2 * thickness - Real(1e-6));
  EXPECT_LE(r.deepest, Real(0));
  EXPECT_GT(r.speed, Real(1));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

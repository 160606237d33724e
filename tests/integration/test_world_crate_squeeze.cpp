// Heavy on light between two bodies: a 100 kg box dropped 0.2 m onto a
// 0.4 kg cloth that lies on a 20 kg crate on the ground (the cloth drapes
// over the crate's edges). The cloth is squeezed between two dynamic
// bodies, and the crate is held by the ground, which XPBD sees only
// through the crate's contacts with it (xpbd::BodyWorldContact).
//
// Closed forms: with restitution 0 the box lands and stays, its lower face
// two thicknesses above the crate's top (the cloth between); no particle
// goes deeper than the thickness into either body; no edge stretches by
// more than 20 % (issue 11's bound).
//
// Before the joint block held a body against a push into its support
// (xpbd/src/contact_block.cpp, supported_against), the crate took 5/6 of
// each correction between the box and the particles, the ground pushed it
// back, and the box kept an overlap that came out as an upward speed: at 45
// substeps the box bounced back at 1.27 m/s (it landed at 1.80 m/s) and rose
// 8 cm, and at the defaults it came to rest 1.3 mm high.
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

constexpr Real kCrateHalfY = Real(0.1);  // m; the crate is 0.6 x 0.2 x 0.6 m
constexpr Real kBoxHalfY = Real(0.05);   // m; the box is 0.3 x 0.1 x 0.3 m

struct Outcome {
  double rebound = 0;   // m, highest the box rose above its rest height after it first came within 5 mm of it
  double rest = 0;      // m, box's lower face above the crate's top at the end
  double speed = 0;     // m/s, box's speed at the end
  double deepest = 0;   // m, deepest particle centre inside the box, the crate or the ground's band
  double strain = 0;    // largest edge strain over the run
};

Outcome drop(const SystemSettings& set) {
  BulletWorld bw;
  bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, BulletWorld::at(Vec3::Zero()));
  const Real t = set.contacts.thickness;
  const Real top = 2 * kCrateHalfY;
  btRigidBody* crate =
      bw.add_body(new btBoxShape(btVector3(0.3, kCrateHalfY, 0.3)), 20, BulletWorld::at(Vec3(0, kCrateHalfY, 0)));
  const Real rest_y = top + 2 * t + kBoxHalfY;
  btRigidBody* box =
      bw.add_body(new btBoxShape(btVector3(0.15, kBoxHalfY, 0.15)), 100, BulletWorld::at(Vec3(0, rest_y + 0.2, 0)));
  XpbdWorld xw(bw.world());
  System sys = lying_cloth(1, 1, top + t);
  const auto id = xw.add_system(sys.model, sys.state, set);
  Outcome r;
  bool arrived = false;
  for (int k = 0; k < 180; ++k) {
    bw.step();
    const xpbd::State& s = xw.state(id);
    const double y = double(box->getCenterOfMassPosition().y()) - double(rest_y);
    arrived = arrived || y <= 5e-3;
    if (arrived) r.rebound = std::max(r.rebound, y);
    for (const Vec3& x : s.x) {
      r.deepest = std::max(r.deepest, double(t - x.y()));
      for (const btRigidBody* b : {box, crate}) {
        xpbd_bullet::ParticleContact pc;
        if (xpbd_bullet::query_point(*b, x, t, pc)) r.deepest = std::max(r.deepest, double(t - pc.distance));
      }
    }
    for (const xpbd::Distance& d : xw.model(id).get<xpbd::Distance>())
      r.strain = std::max(r.strain, double(((s.x[d.p[0]] - s.x[d.p[1]]).norm() - d.rest) / d.rest));
  }
  r.rest = double(box->getCenterOfMassPosition().y()) - kBoxHalfY - double(top);
  r.speed = double(box->getLinearVelocity().length());
  return r;
}

void expect_clean(const Outcome& r, Real t, const char* what) {
  std::printf("%s: rebound %.3g mm, lower face %.4g mm above the crate (2 t = %.3g mm), speed %.3g m/s, deepest "
              "%.3g mm, largest strain %.3g\n",
              what, 1e3 * r.rebound, 1e3 * r.rest, 2e3 * double(t), r.speed, 1e3 * r.deepest, r.strain);
  // Measured: 0.33 mm at the defaults and 0.91 mm at 45 substeps in double,
  // 0.33 and 3.85 mm in float (the box leaves the landing step at +0.22 m/s
  // there; why was not traced); 68 and 82 mm before.
  EXPECT_LE(r.rebound, 5e-3) << what;
  EXPECT_NEAR(r.rest, 2 * double(t), 2e-4) << what;
  EXPECT_LE(r.speed, 0.01) << what;
  EXPECT_LE(r.deepest, 1e-4) << what;  // a tenth of a millimetre into the band at most
  EXPECT_LE(r.strain, 0.2) << what;
}

TEST(CrateSqueeze, HeavyBoxOnClothOnACrateLandsAndStaysAtTheDefaults) {
  const SystemSettings set;
  expect_clean(drop(set), set.contacts.thickness, "defaults");
}

// The bounce grew with the substep count (none at 10, 1.15 m/s at 20,
// 1.27 m/s at 45): the overlap left per substep is about the landing speed
// times h, and it came out at that overlap over h.
TEST(CrateSqueeze, HeavyBoxOnClothOnACrateDoesNotBounceAtManySubsteps) {
  SystemSettings set;
  set.substeps = 45;
  set.tolerance.penetration = 0;  // a fixed count
  expect_clean(drop(set), set.contacts.thickness, "45 substeps");
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

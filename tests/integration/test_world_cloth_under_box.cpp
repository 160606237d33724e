// A light cloth squeezed between a heavy box and the ground, at the default
// settings (10 substeps x 1 iteration, thickness 5 mm), in a real Bullet
// world: a 24 x 24 cloth of 0.4 kg (1 m square, about 0.7 g per particle)
// lies flat on a static plane; a box of `mass` kg (0.3 x 0.1 x 0.3 m) is
// dropped onto its middle from `drop` m (flat, or tilted so that it lands on
// an edge) and left there for 3 s.
//
// Closed forms: a particle under the box is held at the thickness t from
// both surfaces, so the box rests with its bottom at 2t above the ground;
// nothing is deeper inside the box or below the ground than t (a particle's
// centre at the surface is a violation of t, no more); the cloth lies flat,
// so its edges keep their rest length (strain <= 20%, the bound).
// With the contacts of a particle solved one by one, the box pushes the
// particles through the ground (tests/validation/test_contact_squeeze.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "support.hpp"
#include "xpbd_bullet/narrowphase.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

const Vec3 kHalf(0.15, 0.05, 0.15);  // m, the box's half extents

struct Result {
  Real deepest = 0;           // m, deepest particle centre inside the box or below the ground
  Real strain = 0;            // largest edge strain over the run
  Real bottom_lo = 1, bottom_hi = -1;  // m, the box bottom's range over the last second
  bool finite = true;
};

Result run(Real mass, Real drop, Real tilt) {
  BulletWorld bw;
  bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, BulletWorld::at(Vec3::Zero()));
  const Real t = xpbd_bullet::ContactSettings{}.thickness;
  btTransform pose = BulletWorld::at(Vec3(0, 2 * t + kHalf.y() + drop, 0));
  pose.setRotation(btQuaternion(btVector3(0, 0, 1), tilt));
  btRigidBody* box = bw.add_body(new btBoxShape(bt(kHalf)), mass, pose);
  XpbdWorld xw(bw.world());
  System sys = lying_cloth(1, 1, t);  // 24 x 24, at the thickness above the ground
  const auto id = xw.add_system(sys.model, sys.state, SystemSettings{});
  Result r;
  constexpr int kFrames = 180;
  for (int f = 0; f < kFrames; ++f) {
    bw.step();
    const xpbd::State& s = xw.state(id);
    const xpbd::Model& m = xw.model(id);
    for (const Vec3& x : s.x)
      if (!x.allFinite()) {
        r.finite = false;
        return r;
      }
    for (const xpbd::Distance& d : m.get<xpbd::Distance>())
      r.strain = std::max(r.strain, ((s.x[d.p[0]] - s.x[d.p[1]]).norm() - d.rest) / d.rest);
    for (const Vec3& x : s.x) {
      r.deepest = std::max(r.deepest, -x.y());
      xpbd_bullet::ParticleContact pc;
      if (xpbd_bullet::query_point(*box, x, 0, pc)) r.deepest = std::max(r.deepest, -pc.distance);
    }
    if (f >= kFrames - 60) {
      const Real bottom = Real(box->getCenterOfMassPosition().y()) - kHalf.y();
      r.bottom_lo = std::min(r.bottom_lo, bottom);
      r.bottom_hi = std::max(r.bottom_hi, bottom);
    }
  }
  return r;
}

struct Case {
  const char* name;
  Real mass;  // kg
  Real drop;  // m, height of the box's centre above its rest height
  Real tilt;  // rad, about z: the box lands on an edge first
};

class ClothUnderBox : public ::testing::TestWithParam<Case> {};

TEST_P(ClothUnderBox, StaysBetweenTheBoxAndTheGround) {
  const Case k = GetParam();
  const Result r = run(k.mass, k.drop, k.tilt);
  ASSERT_TRUE(r.finite);
  const Real t = xpbd_bullet::ContactSettings{}.thickness;
  std::printf("box %.3g kg dropped %.3g m, tilted %.3g rad, on a 0.4 kg cloth, 10 x 1: deepest particle centre %.3g mm inside "
              "the box or below the ground (t = %.3g mm), largest strain %.3g, box bottom over the last "
              "second %.4g..%.4g mm (closed form 2t = %.3g mm)\n",
              double(k.mass), double(k.drop), double(k.tilt), 1e3 * double(r.deepest), 1e3 * double(t), double(r.strain),
              1e3 * double(r.bottom_lo), 1e3 * double(r.bottom_hi), 2e3 * double(t));
  EXPECT_LE(r.deepest, t);
  EXPECT_LE(r.strain, Real(0.2));
  // At rest on the particles: the bottom at 2t, within 1 mm (the cloth's
  // own sag between particles and Bullet's contact slop are below that).
  EXPECT_NEAR(r.bottom_lo, 2 * t, Real(1e-3));
  EXPECT_NEAR(r.bottom_hi, 2 * t, Real(1e-3));
}

INSTANTIATE_TEST_SUITE_P(Boxes, ClothUnderBox,
                         ::testing::Values(Case{"placed_2kg", 2, 0, 0}, Case{"dropped_2kg", 2, Real(0.2), 0},
                                           Case{"dropped_20kg", 20, Real(0.2), 0},
                                           Case{"on_edge_2kg", 2, Real(0.2), Real(0.3)}),
                         [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

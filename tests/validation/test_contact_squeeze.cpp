// A light particle between a heavy body and the ground, or between two
// bodies: the joint solve of one particle's contacts (xpbd/src/contact_block.cpp)
// against closed forms. Without it (contact by contact), a 2 kg box resting
// on 1 g particles pushes them through the ground: the ground contact lifts
// a particle, the box contact moves almost only the particle back down.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "xpbd/xpbd.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;

constexpr Real kG = Real(9.81);
constexpr Real kT = Real(0.005);  // m, contact thickness

// Contacts of particle i with the ground plane y = 0 (the static world) and
// with the bottom face of box `b` (half extents `half`, found from the
// current poses, as a host finds them once per step); friction 0.5 (on
// frictionless ground the marbles would roll out from under the box).
void add_contacts(xpbd::State& s, Index i, Index b, const Vec3& half) {
  xpbd::BodyContact g;
  g.particle = i;
  g.body = -1;
  g.r = Vec3(s.x[i].x(), 0, s.x[i].z());
  g.n = Vec3::UnitY();
  g.thickness = kT;
  g.static_friction = g.dynamic_friction = Real(0.5);
  s.contacts.push_back(g);
  const xpbd::RigidBody& box = s.bodies[b];
  const Vec3 local = box.q.conjugate() * (s.x[i] - box.x);
  xpbd::BodyContact c;
  c.particle = i;
  c.body = b;
  c.r = Vec3(local.x(), -half.y(), local.z());
  c.n = -Vec3::UnitY();
  c.thickness = kT;
  c.static_friction = c.dynamic_friction = Real(0.5);
  s.contacts.push_back(c);
}

struct Squeeze {
  Real box_bottom = 0;      // m, lowest over the last second
  Real lowest_particle = 0;  // m, over the whole run
};

// A 2 kg box (0.2 x 0.1 x 0.2 m) lying on a 3 x 3 grid of 1 g particles on
// the ground, 10 substeps x 1 iteration, 2 s.
Squeeze box_on_particles() {
  xpbd::SceneDesc scene;
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) scene.add_particle(Vec3(Real(0.08) * (a - 1), kT, Real(0.08) * (c - 1)), Real(0.001));
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  const Vec3 half(0.1, 0.05, 0.1);
  xpbd::RigidBody box;
  box.x = Vec3(0, 2 * kT + half.y(), 0);
  box.inv_mass = Real(0.5);
  const Real I = Real(2) / 12 * (4 * half.y() * half.y() + 4 * half.z() * half.z());
  box.inv_inertia = Vec3::Constant(1 / I);
  box.accel = Vec3(0, -kG, 0);
  xpbd::StepConfig cfg;
  cfg.gravity = Vec3(0, -kG, 0);
  Squeeze out{1e9, 1e9};
  for (int k = 0; k < 120; ++k) {
    s.bodies.assign(1, box);
    s.contacts.clear();
    for (Index i = 0; i < m.num_particles(); ++i) add_contacts(s, i, 0, half);
    xpbd::step(m, s, cfg);
    box = s.bodies[0];
    for (const Vec3& x : s.x) out.lowest_particle = std::min(out.lowest_particle, x.y());
    if (k >= 60) out.box_bottom = std::min(out.box_bottom, box.x.y() - half.y());
  }
  return out;
}

// Closed form at rest: each particle centre at the thickness above the
// ground, the box's bottom face at the thickness above the particles.
TEST(ContactSqueeze, HeavyBoxRestsOnLightParticlesOnTheGround) {
  const Squeeze r = box_on_particles();
  std::printf("2 kg box on 1 g particles, 10 x 1: box bottom at least %.4g m (closed form %.4g), lowest particle "
              "%.4g m (closed form %.4g)\n",
              double(r.box_bottom), double(2 * kT), double(r.lowest_particle), double(kT));
  // At rest within a millimetre of the closed form; the penetration of the
  // particles into the ground below the thickness, by what one substep of
  // gravity adds (g h^2 = 0.27 mm).
  EXPECT_NEAR(r.box_bottom, 2 * kT, Real(1e-3));
  EXPECT_GT(r.lowest_particle, kT - Real(1e-3));
}

// Two free 1 kg boxes pressed onto one 1 g particle between them (zero
// gravity, approaching at 1 m/s each): the particle ends as a spacer, the
// boxes 2 t apart, and momentum is conserved.
TEST(ContactSqueeze, ParticleBetweenTwoBodiesConservesMomentumAndKeepsThem2tApart) {
  xpbd::SceneDesc scene;
  scene.add_particle(Vec3::Zero(), Real(0.001));
  const xpbd::Model m = xpbd::compile(scene);
  xpbd::State s = xpbd::make_state(m);
  const Vec3 half(0.1, 0.1, 0.1);
  xpbd::RigidBody lower, upper;
  lower.x = Vec3(0, -kT - half.y(), 0);  // touching: an initial overlap would be pushed out as velocity
  lower.v = Vec3(0, 1, 0);
  upper.x = Vec3(0, kT + half.y(), 0);
  upper.v = Vec3(0, -1, 0);
  for (xpbd::RigidBody* b : {&lower, &upper}) {
    b->inv_mass = 1;
    b->inv_inertia = Vec3::Constant(Real(1) / (Real(1) / 6 * 4 * half.x() * half.x()));
  }
  xpbd::StepConfig cfg;
  cfg.gravity = Vec3::Zero();
  const Vec3 p0 = lower.v + upper.v + s.v[0] / m.inv_mass[0];
  for (int k = 0; k < 30; ++k) {
    s.bodies = {lower, upper};
    s.contacts.clear();
    for (int side = 0; side < 2; ++side) {
      xpbd::BodyContact c;
      c.particle = 0;
      c.body = side;
      c.r = Vec3(0, side == 0 ? half.y() : -half.y(), 0);
      c.n = side == 0 ? Vec3::UnitY() : Vec3(-Vec3::UnitY());
      c.thickness = kT;
      s.contacts.push_back(c);
    }
    xpbd::step(m, s, cfg);
    lower = s.bodies[0];
    upper = s.bodies[1];
  }
  const Real gap = (upper.x.y() - half.y()) - (lower.x.y() + half.y());
  const Vec3 p1 = lower.v + upper.v + s.v[0] / m.inv_mass[0];
  std::printf("two 1 kg boxes onto a 1 g particle: gap %.6g m (closed form %.6g), momentum change %.3g kg m/s\n",
              double(gap), double(2 * kT), double((p1 - p0).norm()));
  EXPECT_NEAR(gap, 2 * kT, Real(1e-6));
  EXPECT_LT((p1 - p0).norm(), Real(1e-9) + Real(1e3) * std::numeric_limits<Real>::epsilon());
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

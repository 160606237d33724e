// StepConfig::refresh_contacts (step.cpp): the particles that leave the path
// their contacts cover are handed to the host inside the step, and the
// contacts the host adds then are solved in the same substep.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "support/xpbd_test.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::config_error_names;
using test::kEps;

const Real kTol = Real(1000) * kEps;  // m, round-off over 100 substeps

struct Call {
  std::vector<Index> escaped;
  int substep = 0;
  Vec3 x_prev, v;  // of the first escaped particle, when passed
};

SceneDesc one_particle(const Vec3& at) {
  SceneDesc s;
  s.add_particle(at, 1);
  return s;
}

TEST(RefreshContacts, RejectsBadMargin) {
  const Model m = compile(one_particle(Vec3::Zero()));
  State s = make_state(m);
  StepConfig cfg;
  cfg.contact_margin = Real(-0.01);
  EXPECT_TRUE(config_error_names(m, s, cfg, {"contact_margin", "-0.01"}));
  cfg.contact_margin = std::numeric_limits<Real>::infinity();
  EXPECT_TRUE(config_error_names(m, s, cfg, {"contact_margin"}));
}

// A free particle under gravity g, from rest, after k substeps of
// symplectic Euler is g h^2 k (k + 1) / 2 off its start's straight path
// (velocity 0): it leaves a margin d in the first substep k with
// g h^2 k (k + 1) / 2 > d. With g = 10, h = 0.01 and d = 0.012 that is
// k = 5 (k (k + 1) > 24), substep index 4, where the particle starts at
// -g h^2 * 4 * 5 / 2 = -0.01 m with velocity -g h * 5 = -0.5 m/s (after
// that substep's prediction). Its path restarts there,
// x(t) = x_prev + (t - 4 h) v, and j substeps later (counting substep 4)
// the particle is g h^2 j (j - 1) / 2 off it: j = 6, substep index 9.
TEST(RefreshContacts, FreeFallLeavesTheMarginWhereTheClosedFormSays) {
  const Model m = compile(one_particle(Vec3::Zero()));
  State s = make_state(m);
  StepConfig cfg;
  cfg.dt = 1;
  cfg.substeps = 100;
  cfg.gravity = Vec3(0, -10, 0);
  cfg.contact_margin = Real(0.012);
  std::vector<Call> calls;
  cfg.refresh_contacts = [&](std::span<const Index> escaped, int sub) {
    calls.push_back(Call{{escaped.begin(), escaped.end()}, sub, s.x_prev[0], s.v[0]});
  };
  step(m, s, cfg);
  ASSERT_GE(calls.size(), 2u);
  EXPECT_EQ(calls[0].escaped, std::vector<Index>{0});
  EXPECT_EQ(calls[0].substep, 4);
  EXPECT_NEAR(calls[0].x_prev.y(), -0.01, kTol);
  EXPECT_NEAR(calls[0].v.y(), -0.5, kTol);
  EXPECT_EQ(calls[1].substep, 9);
  // Off by default: no call without a margin.
  cfg.contact_margin = 0;
  calls.clear();
  step(m, s, cfg);
  EXPECT_TRUE(calls.empty());
}

// A kinematic particle never leaves (it follows what the host set), and a
// particle moving at constant velocity stays on its path.
TEST(RefreshContacts, StraightMotionAndKinematicParticlesAreNotPassed) {
  SceneDesc d;
  d.add_particle(Vec3::Zero(), 1);
  d.add_particle(Vec3(1, 0, 0), 0);
  const Model m = compile(d);
  State s = make_state(m);
  s.v[0] = Vec3(30, 0, 0);
  s.v[1] = Vec3(0, 50, 0);
  StepConfig cfg;
  cfg.gravity = Vec3::Zero();
  cfg.contact_margin = Real(1e-3);
  int calls = 0;
  cfg.refresh_contacts = [&](std::span<const Index>, int) { ++calls; };
  for (int k = 0; k < 10; ++k) step(m, s, cfg);
  EXPECT_EQ(calls, 0);
}

// Twenty particles at rest in a row, one substep of h = 0.01 s without
// gravity, margin d = 0.01 m: a particle of mass 1 kg pushed by a force f
// is h^2 f off its path after the prediction, so it is passed iff
// |h^2 f| > d. The escapes sit inside the vector kernels' batches (8
// particles in double, 16 in float) and in the tail after them, next to
// particles that come close to the margin (past d / sqrt(3) in a
// coordinate, or in all three) without leaving it, and a kinematic one
// with a force; and one that leaves it with each coordinate well inside. The particles passed are those of the closed form, with
// and without the vector kernels (StepConfig::simd).
TEST(RefreshContacts, EscapesInsideAndAfterWholeBatchesAreFound) {
  SceneDesc d;
  for (int i = 0; i < 20; ++i) d.add_particle(Vec3(Real(i), 0, 0), i == 9 ? 0 : 1);
  const Model m = compile(d);
  const Real h = Real(0.01), margin = Real(0.01);
  // Offsets after the prediction, in margins.
  const std::vector<std::pair<int, Vec3>> pushes = {
      {3, Vec3(1.5, 0, 0)},          // out
      {5, Vec3(0, 0.9, 0)},          // in, past d / sqrt(3) in y
      {9, Vec3(3, 0, 0)},            // kinematic: does not move
      {10, Vec3(0.58, 0.58, 0.5)},   // in (0.961 d), past d / sqrt(3) in x and y
      {12, Vec3(0.6, 0.6, 0.6)},     // out (1.039 d), each coordinate within 0.6 d
      {17, Vec3(0, 0, -2)}};         // out, after the double kernel's batches
  // Which pushes: all; the near misses and 12 (the only escape, within the
  // margin in every coordinate; in double in a batch of its own); the near
  // misses.
  const std::vector<std::vector<int>> cases = {{3, 5, 9, 10, 12, 17}, {5, 10, 12}, {5, 10}};
  for (const std::vector<int>& pushed : cases) {
    for (bool simd : {true, false}) {
      State s = make_state(m);
      s.f_ext.assign(20, Vec3::Zero());
      std::vector<Index> want;
      for (const auto& [i, off] : pushes) {
        if (std::find(pushed.begin(), pushed.end(), i) == pushed.end()) continue;
        s.f_ext[std::size_t(i)] = off * (margin / (h * h));
        if (m.inv_mass[i] > 0 && off.norm() > 1) want.push_back(i);
      }
      StepConfig cfg;
      cfg.dt = h;
      cfg.substeps = 1;
      cfg.gravity = Vec3::Zero();
      cfg.contact_margin = margin;
      cfg.simd = simd;
      std::vector<Call> calls;
      cfg.refresh_contacts = [&](std::span<const Index> e, int sub) {
        calls.push_back({std::vector<Index>(e.begin(), e.end()), sub, Vec3::Zero(), Vec3::Zero()});
      };
      step(m, s, cfg);
      if (want.empty()) {
        EXPECT_TRUE(calls.empty()) << "simd " << simd;
      } else {
        ASSERT_EQ(calls.size(), 1u) << "simd " << simd;
        EXPECT_EQ(calls[0].escaped, want) << "simd " << simd;
      }
      // The near misses did move as the closed form says (close to the margin).
      EXPECT_NEAR((s.x[5] - m.x0[5]).norm(), Real(0.9) * margin, 1e3 * kEps) << "simd " << simd;
    }
  }
}

// A floor the host did not know of at the start of the step (no contact):
// the particle falls 0.7525 m in the step, and the floor is 0.3 m below it.
// It leaves its path (margin 1 cm) in substep 19, 0.1 m down; the contact
// the host adds then stops it on the floor within the same step. Without
// the refresh it falls through.
TEST(RefreshContacts, ContactAddedInsideTheStepIsSolved) {
  const Model m = compile(one_particle(Vec3::Zero()));
  const Real floor = Real(-0.3), thickness = Real(0.005);
  for (bool refresh : {false, true}) {
    State s = make_state(m);
    s.v[0] = Vec3(0, -0.5, 0);  // 5 mm per substep: within the margin at first
    StepConfig cfg;
    cfg.dt = 1;
    cfg.substeps = 100;
    cfg.gravity = Vec3(0, -0.5, 0);  // 0.25 m more over the step
    if (refresh) {
      cfg.contact_margin = Real(0.01);
      cfg.refresh_contacts = [&](std::span<const Index> escaped, int) {
        for (Index i : escaped) {
          BodyContact c;
          c.particle = i;
          c.body = -1;
          c.r = Vec3(0, floor, 0);
          c.n = Vec3::UnitY();
          c.thickness = thickness;
          s.contacts.push_back(c);
        }
      };
    }
    step(m, s, cfg);
    if (refresh)
      EXPECT_NEAR(s.x[0].y(), floor + thickness, kTol);
    else
      EXPECT_NEAR(s.x[0].y(), -0.5 - 0.25 * (1 + 1.0 / 100), kTol);  // symplectic Euler
  }
}

// The host's index errors are caught as begin_step catches them.
TEST(RefreshContacts, BadContactFromTheHostIsNamed) {
  const Model m = compile(one_particle(Vec3::Zero()));
  State s = make_state(m);
  StepConfig cfg;
  cfg.dt = 1;
  cfg.gravity = Vec3(0, -10, 0);
  cfg.contact_margin = Real(0.01);
  cfg.refresh_contacts = [&](std::span<const Index>, int) {
    BodyContact c;
    c.particle = 7;
    s.contacts.push_back(c);
  };
  try {
    step(m, s, cfg);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("state.contacts[0].particle: index 7"), std::string::npos) << e.what();
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd

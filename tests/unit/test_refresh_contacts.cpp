// StepConfig::refresh_contacts (step.cpp): the particles that leave the path
// their contacts cover are handed to the host inside the step, and the
// contacts the host adds then are solved in the same substep.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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

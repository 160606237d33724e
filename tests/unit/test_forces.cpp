// Forces from the multipliers (xpbd/forces.hpp) against closed forms.
//
// A vertical chain of N particles of mass m, 1 cm links, g = 10 m/s^2, hung
// from its top particle (at the origin: small coordinates keep float
// round-off well below g h^2) and let come to rest (drag). Force balance fixes
// every tension: link k carries the particles below it. Expected values:
//  - top particle kinematic (mass 0), with or without a Pin element: the
//    support carries the N - 1 particles that hang, (N - 1) m g upward;
//  - top particle of mass m held by a Pin (compliant or stiff): the Pin
//    carries the whole chain, N m g upward;
//  - the largest Distance force is the top link's tension, (N - 1) m g.
#include <gtest/gtest.h>

#include <cstdio>

#include "support/xpbd_test.hpp"
#include "xpbd/forces.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

constexpr int N = 20;
constexpr Real kMass = 1, kG = 10, kSpacing = Real(0.01);
const Real kTol = Real(1e-3);  // relative: the solver's residual after 600 frames

enum class Top { kinematic_pin, kinematic_no_pin, pin_compliant, pin_stiff };

struct Chain {
  Model model;
  State state;
  StepConfig cfg;
};

Chain hang(Top top, Real link_compliance = 0) {
  SceneDesc sd;
  const bool kinematic = top == Top::kinematic_pin || top == Top::kinematic_no_pin;
  for (int k = 0; k < N; ++k)
    sd.add_particle(Vec3(0, -Real(k) * kSpacing, 0), k == 0 && kinematic ? Real(0) : kMass);
  for (int k = 0; k + 1 < N; ++k)
    sd.distances.push_back(DistanceDesc{k, k + 1, kSpacing, Material{link_compliance, 0, 1}});
  if (top != Top::kinematic_no_pin)
    sd.pins.push_back(PinDesc{0, std::nullopt, Material{top == Top::pin_compliant ? Real(1e-6) : Real(0), 0, 1}});
  Chain c{compile(sd), {}, {}};
  c.state = make_state(c.model);
  c.cfg.substeps = 10;
  c.cfg.iterations = 20;
  c.cfg.gravity = Vec3(0, -kG, 0);
  c.cfg.drag = 5;  // 1/s: the start-up transient decays; no force at rest
  for (int f = 0; f < 600; ++f) step(c.model, c.state, c.cfg);
  return c;
}

void expect_support(const Chain& c, Real expected_up, bool balance, Index pin) {
  const auto r = pin_reactions(c.model, c.state, c.cfg.gravity);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].particle, 0);
  EXPECT_EQ(r[0].pin, pin);
  EXPECT_EQ(r[0].from_balance, balance);
  std::printf("support: (%.9g, %.9g, %.9g) N, expected (0, %.9g, 0), rel. error %.3g\n", double(r[0].force.x()),
              double(r[0].force.y()), double(r[0].force.z()), double(expected_up),
              double(std::abs(r[0].force.y() - expected_up) / expected_up));
  EXPECT_NEAR(r[0].force.y(), expected_up, kTol * expected_up);
  EXPECT_NEAR(r[0].force.x(), 0, kTol * expected_up);
  EXPECT_NEAR(r[0].force.z(), 0, kTol * expected_up);
}

TEST(Forces, KinematicPinnedChainCarriesTheHangingParticles) {
  for (Real alpha : {Real(0), Real(1e-6)}) {
    const Chain c = hang(Top::kinematic_pin, alpha);
    expect_support(c, Real(N - 1) * kMass * kG, false, 0);
    // The largest Distance force is the top link's tension.
    const auto mx = max_constraint_forces(c.model, c.state);
    ASSERT_EQ(mx.size(), kNumConstraintTypes);
    const MaxConstraintForce& d = mx[type_index_v<Distance>];
    EXPECT_EQ(d.type, "distance");
    EXPECT_EQ(d.unit, "N");
    EXPECT_EQ(d.count, N - 1);
    EXPECT_EQ(d.element, 0);
    EXPECT_NEAR(d.force, Real(N - 1) * kMass * kG, kTol * Real(N - 1) * kMass * kG);
    // A kinematic particle's Pin is not solved (inverse mass 0): no multiplier.
    EXPECT_EQ(mx[type_index_v<Pin>].type, "pin");
    EXPECT_EQ(mx[type_index_v<Pin>].force, Real(0));
    EXPECT_EQ(mx[type_index_v<Wall>].count, 0);
    EXPECT_EQ(mx[type_index_v<Wall>].element, -1);
  }
}

TEST(Forces, KinematicParticleWithoutPinIsASupport) {
  expect_support(hang(Top::kinematic_no_pin), Real(N - 1) * kMass * kG, false, -1);
}

TEST(Forces, CompliantPinOnMovableParticleCarriesTheWholeChain) {
  const Chain c = hang(Top::pin_compliant);
  expect_support(c, Real(N) * kMass * kG, false, 0);
  // Its own multiplier: |lambda|/h^2 = N m g.
  const auto mx = max_constraint_forces(c.model, c.state);
  EXPECT_NEAR(mx[type_index_v<Pin>].force, Real(N) * kMass * kG, kTol * Real(N) * kMass * kG);
}

TEST(Forces, StiffPinOnMovableParticleFromBalance) {
  const Chain c = hang(Top::pin_stiff);
  expect_support(c, Real(N) * kMass * kG, true, 0);
  const auto mx = max_constraint_forces(c.model, c.state);
  EXPECT_NEAR(mx[type_index_v<Pin>].force, Real(N) * kMass * kG, kTol * Real(N) * kMass * kG);
}

// The chain hung from a fixed world point by an attachment (body -1) of its
// top particle (mass m): the attachment carries N m g; on its "body" (the
// world point) the force is N m g downward.
TEST(Forces, WorldPointAttachment) {
  for (Real alpha : {Real(0), Real(1e-6)}) {
    SceneDesc sd;
    for (int k = 0; k < N; ++k) sd.add_particle(Vec3(0, -Real(k) * kSpacing, 0), kMass);
    for (int k = 0; k + 1 < N; ++k) sd.distances.push_back(DistanceDesc{k, k + 1, kSpacing, Material{}});
    const Model model = compile(sd);
    State s = make_state(model);
    s.attachments.push_back(BodyAttachment{0, -1, Vec3::Zero(), alpha});
    StepConfig cfg;
    cfg.substeps = 10;
    cfg.iterations = 20;
    cfg.gravity = Vec3(0, -kG, 0);
    cfg.drag = 5;
    for (int f = 0; f < 600; ++f) step(model, s, cfg);
    const auto a = attachment_forces(model, s);
    ASSERT_EQ(a.size(), 1u);
    EXPECT_EQ(a[0].particle, 0);
    EXPECT_EQ(a[0].body, -1);
    const Real w = Real(N) * kMass * kG;
    std::printf("attachment (alpha %g): on the point (%.9g, %.9g, %.9g) N, expected (0, %.9g, 0)\n", double(alpha),
                double(a[0].on_body.x()), double(a[0].on_body.y()), double(a[0].on_body.z()), double(-w));
    EXPECT_NEAR(a[0].on_body.y(), -w, kTol * w);
    EXPECT_NEAR(a[0].on_body.x(), 0, kTol * w);
    EXPECT_NEAR(a[0].on_body.z(), 0, kTol * w);
    // No pin: no support listed.
    EXPECT_TRUE(pin_reactions(model, s, cfg.gravity).empty());
  }
}

TEST(Forces, UnsteppedStateIsRefused) {
  SceneDesc sd;
  sd.add_particle(Vec3::Zero(), 0);
  const Model model = compile(sd);
  const State s = make_state(model);
  try {
    (void)pin_reactions(model, s, Vec3(0, -kG, 0));
    FAIL() << "accepted a state that was never stepped";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("not been stepped"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)max_constraint_forces(model, s), ConfigError);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd

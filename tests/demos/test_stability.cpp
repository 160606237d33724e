// The stability map's classifier (demos/compare/stability.hpp) on hand-made
// observations whose answers follow from the stated thresholds, and one
// tiny real run per geometric check (a particle ending under the plate).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "demos/compare/stability.hpp"

namespace {

using namespace xpbd_stability;

// A quiet run: 1 J released, 0.5 J of kinetic energy at most, 1 % strain.
Observation quiet() {
  Observation o;
  o.potential0 = 0;
  o.potential_min = -1;
  o.kinetic_max = 0.5;
  o.max_strain = 0.01;
  return o;
}

TEST(StabilityClassify, QuietRunIsStable) { EXPECT_EQ(classify(quiet()), Outcome::stable); }

TEST(StabilityClassify, NonFiniteIsNaN) {
  Observation o = quiet();
  o.finite = false;
  EXPECT_EQ(classify(o), Outcome::nan);
  // A NaN that slipped into a metric is NaN too, and wins over everything.
  Observation p = quiet();
  p.max_strain = std::numeric_limits<double>::quiet_NaN();
  p.tunnelled = 3;
  EXPECT_EQ(classify(p), Outcome::nan);
}

TEST(StabilityClassify, StrainAboveThresholdIsOverStretched) {
  Observation o = quiet();
  o.max_strain = 0.2;
  Thresholds t;
  t.max_strain = 0.1;
  EXPECT_EQ(classify(o, t), Outcome::over_stretched);
  o.max_strain = 0.09;
  EXPECT_EQ(classify(o, t), Outcome::stable);
}

TEST(StabilityClassify, EnergyGrowthIsExploded) {
  // Budget = KE0 + released + floor = 2 + 1 + 1e-3 J; factor 10 -> 30.01 J.
  Observation o = quiet();
  o.kinetic0 = 2;
  o.kinetic_max = 29;
  EXPECT_EQ(classify(o), Outcome::stable);
  o.kinetic_max = 31;
  EXPECT_EQ(classify(o), Outcome::exploded);
  // Energy gained from falling is not growth: 1000 J released, 900 J kinetic.
  Observation f = quiet();
  f.potential_min = -1000;
  f.kinetic_max = 900;
  EXPECT_EQ(classify(f), Outcome::stable);
}

TEST(StabilityClassify, FlyingAwayIsExploded) {
  Observation o = quiet();
  o.max_escape = 11;  // m outside the initial box, bound 10 m
  EXPECT_EQ(classify(o), Outcome::exploded);
  // Within the ballistic reach (a mass falling 20 m in 2 s) plus the bound
  // it is not.
  o.reach = 19.62;
  o.max_escape = 25;
  EXPECT_EQ(classify(o), Outcome::stable);
  o.max_escape = 30;
  EXPECT_EQ(classify(o), Outcome::exploded);
}

TEST(StabilityClassify, ParticleUnderThePlateIsTunnelled) {
  Observation o = quiet();
  o.tunnelled = 1;
  EXPECT_EQ(classify(o), Outcome::tunnelled);
  // Tunnelled beats over-stretched (the strain comes from the particle
  // stuck on the other side).
  o.max_strain = 0.5;
  EXPECT_EQ(classify(o), Outcome::tunnelled);
  // ... and over the distance bound: a tunnelled particle keeps flying.
  o.max_escape = 30;
  EXPECT_EQ(classify(o), Outcome::tunnelled);
}

TEST(StabilityClassify, ParticleBelowThePlateIsCounted) {
  // The impact sweep's plate: bottom face at y = -0.01 m, footprint 2 m x 2 m.
  TunnelCheck c{true, -0.01, 0, 0, 1, 1};
  const std::vector<Vec3> above = {Vec3(0, Real(0.005), 0), Vec3(Real(0.5), 0, Real(-0.5))};
  EXPECT_EQ(particles_through(above, c), 0);
  // One under the plate, one below its height but outside the footprint
  // (it fell past the edge: not tunnelled).
  const std::vector<Vec3> mixed = {Vec3(Real(0.1), Real(-0.2), 0), Vec3(Real(1.5), Real(-0.2), 0)};
  EXPECT_EQ(particles_through(mixed, c), 1);
  Observation o = quiet();
  o.tunnelled = particles_through(mixed, c);
  EXPECT_EQ(classify(o), Outcome::tunnelled);
}

TEST(StabilityClassify, BallBelowTheClothIsThrough) {
  TunnelCheck c;
  c.body_through = true;
  c.body_radius = 0.15;
  const std::vector<Vec3> cloth = {Vec3(0, 0, 0), Vec3(Real(0.1), Real(-0.3), 0)};
  EXPECT_FALSE(body_through(cloth, -0.4, c));  // top at -0.25 m, in the pocket
  EXPECT_TRUE(body_through(cloth, -0.5, c));   // top at -0.35 m, under every particle
}

TEST(StabilityClassify, OutsideDistance) {
  const Vec3 lo(0, 0, 0), hi(1, 1, 1);
  EXPECT_EQ(outside_distance(Vec3(Real(0.5), Real(0.5), Real(0.5)), lo, hi), 0.0);
  // 3-4-5 triangle outside a corner; tolerance: a few float epsilons of 5.
  EXPECT_NEAR(outside_distance(Vec3(4, 5, 1), lo, hi), 5.0, 8 * std::numeric_limits<Real>::epsilon() * 5);
}

TEST(StabilityClassify, OutcomeNames) {
  EXPECT_STREQ(outcome_name(Outcome::stable), "stable");
  EXPECT_STREQ(outcome_name(Outcome::over_stretched), "over_stretched");
  EXPECT_STREQ(outcome_name(Outcome::exploded), "exploded");
  EXPECT_STREQ(outcome_name(Outcome::nan), "nan");
  EXPECT_STREQ(outcome_name(Outcome::tunnelled), "tunnelled");
}

}  // namespace

// The library's run classifier (xpbd/health.hpp) on hand-made observations
// whose answers follow from the stated thresholds.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "xpbd/error.hpp"
#include "xpbd/health.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using xpbd::Health;
using xpbd::HealthObservation;
using xpbd::HealthThresholds;

// A quiet run: 1 J released, 0.5 J of kinetic energy at most, 1 % strain.
HealthObservation quiet() {
  HealthObservation o;
  o.potential0 = 0;
  o.potential_min = -1;
  o.kinetic_max = 0.5;
  o.max_strain = 0.01;
  return o;
}

TEST(Health, QuietRunIsOk) { EXPECT_EQ(classify(quiet()), Health::ok); }

TEST(Health, NonFiniteWinsOverEverything) {
  HealthObservation o = quiet();
  o.finite = false;
  EXPECT_EQ(classify(o), Health::nonfinite);
  HealthObservation p = quiet();
  p.max_strain = std::numeric_limits<double>::quiet_NaN();
  p.tunnelled = 3;
  EXPECT_EQ(classify(p), Health::nonfinite);
  HealthObservation q = quiet();
  q.kinetic_max = std::numeric_limits<double>::infinity();
  EXPECT_EQ(classify(q), Health::nonfinite);
}

TEST(Health, StrainAboveTheBoundIsOverStretched) {
  HealthObservation o = quiet();
  o.max_strain = 1.5;  // default bound 1: an edge 2.5 times its rest length
  EXPECT_EQ(classify(o), Health::over_stretched);
  o.max_strain = 0.99;
  EXPECT_EQ(classify(o), Health::ok);
  HealthThresholds t;
  t.max_strain = 0.1;
  o.max_strain = 0.2;
  EXPECT_EQ(classify(o, t), Health::over_stretched);
  t.max_strain = std::numeric_limits<double>::infinity();  // off
  o.max_strain = 1e22;
  EXPECT_EQ(classify(o, t), Health::ok);
}

TEST(Health, EnergyGrowthIsExploded) {
  // Budget = KE0 + released + floor = 2 + 1 + 1e-3 J; factor 10 -> 30.01 J.
  HealthObservation o = quiet();
  o.kinetic0 = 2;
  EXPECT_DOUBLE_EQ(energy_budget(o, {}), 3.001);
  o.kinetic_max = 29;
  EXPECT_EQ(classify(o), Health::ok);
  o.kinetic_max = 31;
  EXPECT_EQ(classify(o), Health::exploded);
  // Energy put in from outside raises the budget: 31 J of kinetic energy
  // after 1 J of input is within 10 x 4.001 J.
  o.energy_input = 1;
  EXPECT_EQ(classify(o), Health::ok);
  // Energy gained from falling is not growth: 1000 J released, 900 J kinetic.
  HealthObservation f = quiet();
  f.potential_min = -1000;
  f.kinetic_max = 900;
  EXPECT_EQ(classify(f), Health::ok);
  // Exploded wins over over-stretched.
  o.kinetic_max = 1e6;
  o.max_strain = 5;
  EXPECT_EQ(classify(o), Health::exploded);
}

TEST(Health, FlyingAwayIsExplodedWhenABoundIsSet) {
  HealthObservation o = quiet();
  o.max_escape = 11;  // m outside the initial box
  EXPECT_EQ(classify(o), Health::ok);  // no bound by default
  HealthThresholds t;
  t.bound = 10;
  EXPECT_EQ(classify(o, t), Health::exploded);
  // Within the ballistic reach (a mass falling 20 m in 2 s) plus the bound
  // it is not.
  o.reach = 19.62;
  o.max_escape = 25;
  EXPECT_EQ(classify(o, t), Health::ok);
  o.max_escape = 30;
  EXPECT_EQ(classify(o, t), Health::exploded);
}

TEST(Health, TunnelledBeatsOverStretchedAndTheBound) {
  HealthObservation o = quiet();
  o.tunnelled = 1;
  EXPECT_EQ(classify(o), Health::tunnelled);
  o.max_strain = 5;
  EXPECT_EQ(classify(o), Health::tunnelled);
  HealthThresholds t;
  t.bound = 10;
  o.max_escape = 30;
  EXPECT_EQ(classify(o, t), Health::tunnelled);
}

TEST(Health, Names) {
  EXPECT_STREQ(health_name(Health::ok), "ok");
  EXPECT_STREQ(health_name(Health::over_stretched), "over_stretched");
  EXPECT_STREQ(health_name(Health::exploded), "exploded");
  EXPECT_STREQ(health_name(Health::nonfinite), "nonfinite");
  EXPECT_STREQ(health_name(Health::tunnelled), "tunnelled");
}

TEST(Health, ThresholdsAreChecked) {
  EXPECT_NO_THROW(validate(HealthThresholds{}));
  auto message = [](HealthThresholds t) {
    try {
      validate(t, "solver.");
    } catch (const xpbd::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  HealthThresholds t;
  t.max_strain = 0;
  EXPECT_EQ(message(t), "solver.max_strain: must be > 0 (infinity = off), got 0");
  t = {};
  t.max_strain = std::nan("");
  EXPECT_NE(message(t).find("solver.max_strain"), std::string::npos);
  t = {};
  t.energy_factor = 1;
  EXPECT_NE(message(t).find("solver.energy_factor"), std::string::npos);
  t = {};
  t.energy_floor = -1;
  EXPECT_NE(message(t).find("solver.energy_floor"), std::string::npos);
  t = {};
  t.bound = -1;
  EXPECT_NE(message(t).find("solver.bound"), std::string::npos);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

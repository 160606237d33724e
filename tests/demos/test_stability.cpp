// The stability map's thresholds and labels (demos/compare/stability.hpp), the
// tunnelling and attachment checks on hand-made frame sequences with known
// answers, and the CSV (quoting round trip, errors, merge).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "demos/compare/stability.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_stability;

// The classifier itself is the library's (tests/unit/test_health.cpp); the
// map sets its own thresholds.
TEST(StabilityClassify, MapThresholds) {
  Observation o;
  o.potential_min = -1;
  o.kinetic_max = 0.5;
  o.max_strain = 0.11;  // above the map's 10 %, below the library's default 100 %
  EXPECT_EQ(classify(o, map_thresholds()), Outcome::over_stretched);
  EXPECT_EQ(classify(o), Outcome::ok);
  o.max_strain = 0.01;
  o.max_escape = 11;  // m outside the initial box: the map's bound is 10 m
  EXPECT_EQ(classify(o, map_thresholds()), Outcome::exploded);
  EXPECT_EQ(classify(o), Outcome::ok);  // the library's bound is off by default
}

// The impact sweep's plate: bottom face y = -0.01 m, footprint 2 m x 2 m
// around the origin.
TunnelCheck plate() {
  TunnelCheck c;
  c.enabled = true;
  c.bottom_y = -0.01;
  c.half_x = c.half_z = 1;
  return c;
}

// One particle through a sequence of frames.
TunnelTracker track(const TunnelCheck& c, const std::vector<Vec3>& path) {
  TunnelTracker t(c);
  for (const Vec3& p : path) t.observe(std::span<const Vec3>(&p, 1));
  return t;
}

TEST(StabilityTunnel, ThroughThePlateAndBackIsCounted) {
  // Judged at every frame: through at frame 1, back above at frame 2 (the
  // old last-frame check missed this).
  const auto t = track(plate(), {Vec3(0, Real(0.05), 0), Vec3(0, Real(-0.2), 0), Vec3(0, Real(0.05), 0)});
  EXPECT_EQ(t.particles(), 1);
  EXPECT_EQ(t.first_frame(), 1);
  // Through, back, and through again: still one particle.
  const auto u = track(plate(), {Vec3(0, Real(0.05), 0), Vec3(0, Real(-0.2), 0), Vec3(0, Real(0.05), 0),
                                 Vec3(0, Real(-0.3), 0)});
  EXPECT_EQ(u.count(), 1);
}

TEST(StabilityTunnel, RestingOnThePlateThenSinkingThroughIsCounted) {
  // On the top face, inside the plate (above its bottom face), then out
  // through the bottom face: through at frame 2.
  const auto t = track(plate(), {Vec3(Real(0.5), 0, Real(0.5)), Vec3(Real(0.5), Real(-0.005), Real(0.5)),
                                 Vec3(Real(0.5), Real(-0.02), Real(0.5))});
  EXPECT_EQ(t.particles(), 1);
  EXPECT_EQ(t.first_frame(), 2);
}

TEST(StabilityTunnel, PastTheEdgeAndUnderThePlateIsNot) {
  // Falls past the edge (x = 1.2 m), then swings in under the plate: below
  // its bottom face inside the footprint, but it never crossed the plate.
  const auto t = track(plate(), {Vec3(Real(1.2), Real(0.05), 0), Vec3(Real(1.2), Real(-0.2), 0),
                                 Vec3(Real(0.5), Real(-0.2), 0)});
  EXPECT_EQ(t.particles(), 0);
  EXPECT_EQ(t.first_frame(), -1);
  // Starting under the plate and moving about there: not counted either.
  EXPECT_EQ(track(plate(), {Vec3(0, Real(-0.5), 0), Vec3(0, Real(-0.6), 0)}).particles(), 0);
}

TEST(StabilityTunnel, TheCrossingPointDecidesNotTheEndPoint) {
  // (0.9, 0, 0) -> (1.05, -0.03, 0) crosses y = -0.01 at a third of the way,
  // x = 0.95 m: through the bottom face although it ends outside the footprint.
  EXPECT_EQ(track(plate(), {Vec3(Real(0.9), 0, 0), Vec3(Real(1.05), Real(-0.03), 0)}).particles(), 1);
  // (0.95, 0, 0) -> (1.25, -0.03, 0) crosses at x = 1.05 m: past the edge.
  EXPECT_EQ(track(plate(), {Vec3(Real(0.95), 0, 0), Vec3(Real(1.25), Real(-0.03), 0)}).particles(), 0);
  // The same in z.
  EXPECT_EQ(track(plate(), {Vec3(0, 0, Real(-0.9)), Vec3(0, Real(-0.03), Real(-1.05))}).particles(), 1);
  EXPECT_EQ(track(plate(), {Vec3(0, 0, Real(-0.95)), Vec3(0, Real(-0.03), Real(-1.25))}).particles(), 0);
}

TEST(StabilityTunnel, ParticleCountMustNotChange) {
  TunnelTracker t(plate());
  const std::vector<Vec3> two = {Vec3::Zero(), Vec3::Zero()};
  t.observe(two);
  EXPECT_THROW(t.observe(std::span<const Vec3>(two.data(), 1)), std::invalid_argument);
}

TEST(StabilityTunnel, BallThroughTheCloth) {
  TunnelCheck c;
  c.body_through = true;
  c.body_radius = 0.15;
  // A cloth of 4 corners (footprint x, z in [-0.5, 0.5]) and a centre node.
  auto cloth = [](double centre_y) {
    return std::vector<Vec3>{Vec3(Real(-0.5), 0, Real(-0.5)), Vec3(Real(0.5), 0, Real(-0.5)),
                             Vec3(Real(-0.5), 0, Real(0.5)), Vec3(Real(0.5), 0, Real(0.5)),
                             Vec3(0, Real(centre_y), 0)};
  };
  TunnelTracker t(c);
  t.observe(cloth(0), Vec3(0, Real(0.25), 0));  // ball above the cloth
  t.observe(cloth(-0.3), Vec3(0, Real(-0.4), 0));  // in the pocket: top -0.25 m, above the centre node
  EXPECT_FALSE(t.body());
  t.observe(cloth(-0.3), Vec3(0, Real(-0.5), 0));  // top -0.35 m, under every node
  EXPECT_TRUE(t.body());
  EXPECT_EQ(t.first_frame(), 2);
  t.observe(cloth(-0.3), Vec3(0, Real(-0.4), 0));  // back in the pocket: it did pass through
  EXPECT_TRUE(t.body());
  EXPECT_EQ(t.count(), 1);

  // Under every node but beside the cloth (x = 0.8 m): it left over an edge.
  TunnelTracker e(c);
  e.observe(cloth(0), Vec3(0, Real(0.25), 0));
  e.observe(cloth(-0.1), Vec3(Real(0.8), Real(-0.5), 0));
  EXPECT_FALSE(e.body());
}

TEST(StabilityTunnel, TunnelledRunIsClassifiedTunnelled) {
  Observation o;
  o.tunnelled = track(plate(), {Vec3(0, Real(0.05), 0), Vec3(0, Real(-0.2), 0), Vec3(0, Real(0.05), 0)}).count();
  EXPECT_EQ(classify(o), Outcome::tunnelled);
}

TEST(StabilityAttach, GapToARotatedBody) {
  // Body at (1, 2, 3) turned 90 degrees about z: its local (0, 0.03, 0)
  // is at (1 - 0.03, 2, 3); a particle 4 cm above that point is 4 cm away.
  xpbd_demos::BodyPose pose;
  pose.position = Vec3(1, 2, 3);
  const Real h = std::sqrt(Real(0.5));
  pose.orientation = {h, 0, 0, h};
  const Vec3 local(0, Real(0.03), 0);
  // Tolerance: a few round-offs of coordinates of size 3.
  const double tol = 16 * std::numeric_limits<Real>::epsilon() * 3;
  EXPECT_NEAR(attachment_gap(Vec3(Real(0.97), Real(2.04), 3), pose, local), 0.04, tol);
  EXPECT_NEAR(attachment_gap(Vec3(Real(0.97), 2, 3), pose, local), 0.0, tol);
}

// ---------------------------------------------------------------------------
// The CSV: quoting, the reader's errors and merge.

std::string temp_path(const std::string& name) {
  return (std::filesystem::path(::testing::TempDir()) / ("xpbd_test_stability_" + name)).string();
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream o(path, std::ios::binary);
  o << text;
}

StabilityRow row(const std::string& sweep, const std::string& x, const std::string& y, const std::string& outcome) {
  StabilityRow r;
  r.sweep = sweep;
  r.method = "xpbd";
  r.x_label = x;
  r.y_label = y;
  r.outcome = outcome;
  r.frames = 60;
  r.frames_completed = 60;
  return r;
}

TEST(StabilityCsv, NoteWithCommaAndQuoteRoundTrips) {
  StabilityRow r = row("impact", "dt=1/60", "v=10", "tunnelled");
  r.xi = 1;
  r.yi = 2;
  r.max_strain = 0.125;  // exact in binary and in 6 digits
  r.energy_ratio = 0.5;
  r.max_escape = 2.25;
  r.tunnelled = 7;
  r.wall_s = 0.0625;
  r.note = "first through the plate at frame 3, then \"back\"; ok";
  const std::string path = temp_path("roundtrip.csv");
  write_file(path, std::string(stability_csv_header()) + "\n" + to_csv(r) + "\n");
  const auto back = read_stability_csv(path);
  ASSERT_EQ(back.size(), 1u);
  const StabilityRow& b = back[0];
  EXPECT_EQ(b.note, r.note);
  EXPECT_EQ(b.key(), r.key());
  EXPECT_EQ(b.outcome, r.outcome);
  EXPECT_EQ(b.xi, 1);
  EXPECT_EQ(b.yi, 2);
  EXPECT_EQ(b.max_strain, 0.125);
  EXPECT_EQ(b.energy_ratio, 0.5);
  EXPECT_EQ(b.max_escape, 2.25);
  EXPECT_EQ(b.tunnelled, 7);
  EXPECT_EQ(b.wall_s, 0.0625);
  std::filesystem::remove(path);
}

TEST(StabilityCsv, ErrorsNameTheFileAndLine) {
  const std::string path = temp_path("bad.csv");
  auto message = [&](const std::string& text) {
    write_file(path, text);
    try {
      read_stability_csv(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string good = to_csv(row("impact", "dt=1/60", "v=10", "stable"));
  // The sweep's CSV (docs/results.csv) is a foreign header.
  EXPECT_NE(message("scene,method,scalar\n").find(path + ":1: not the stability CSV header"), std::string::npos);
  // A line cut short (14 fields) on line 3.
  const std::string cut = good.substr(0, good.rfind(','));
  EXPECT_NE(message(std::string(stability_csv_header()) + "\n" + good + "\n" + cut + "\n").find(path + ":3: 14 fields"),
            std::string::npos);
  // A number that is not one, naming the column.
  StabilityRow r = row("impact", "dt=1/60", "v=10", "stable");
  std::string bad = to_csv(r);
  bad.replace(bad.find(",60,60,"), 7, ",60,6x,");
  EXPECT_NE(message(std::string(stability_csv_header()) + "\n" + bad + "\n").find(path + ":2 frames_completed"),
            std::string::npos);
  std::filesystem::remove(path);
}

TEST(StabilityCsv, MergeKeepsOneHeaderSweepOrderAndOneCopy) {
  // Two real keys of the default sweep, in reverse order across the shards,
  // and one run in both (same outcome): three runs, in sweep order.
  const auto runs = stability_runs(false);
  ASSERT_GE(runs.size(), 3u);
  auto as_row = [](const StabilityRun& k, const std::string& outcome) {
    StabilityRow r = row(k.sweep, k.x_label, k.y_label, outcome);
    r.method = k.method;
    return r;
  };
  const std::string h = std::string(stability_csv_header()) + "\n";
  const std::string a = temp_path("shard_a.csv"), b = temp_path("shard_b.csv");
  write_file(a, h + to_csv(as_row(runs[2], "stable")) + "\n" + to_csv(as_row(runs[1], "exploded")) + "\n");
  write_file(b, h + to_csv(as_row(runs[0], "nan")) + "\n" + to_csv(as_row(runs[1], "exploded")) + "\n");
  const auto merged = merge_stability({a, b});
  ASSERT_EQ(merged.size(), 3u);
  EXPECT_EQ(merged[0].key(), runs[0].key());
  EXPECT_EQ(merged[1].key(), runs[1].key());
  EXPECT_EQ(merged[2].key(), runs[2].key());
  EXPECT_EQ(merged[0].outcome, "nan");

  // The same run with another outcome: an error naming both places.
  write_file(b, h + to_csv(as_row(runs[1], "stable")) + "\n");
  try {
    merge_stability({a, b});
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(b + ":2"), std::string::npos) << m;
    EXPECT_NE(m.find(a + ":3"), std::string::npos) << m;
  }
  std::filesystem::remove(a);
  std::filesystem::remove(b);
}

TEST(StabilityClassify, OutsideDistance) {
  const Vec3 lo(0, 0, 0), hi(1, 1, 1);
  EXPECT_EQ(outside_distance(Vec3(Real(0.5), Real(0.5), Real(0.5)), lo, hi), 0.0);
  // 3-4-5 triangle outside a corner; tolerance: a few float epsilons of 5.
  EXPECT_NEAR(outside_distance(Vec3(4, 5, 1), lo, hi), 5.0, 8 * std::numeric_limits<Real>::epsilon() * 5);
}

TEST(StabilityClassify, OutcomeNames) {
  EXPECT_STREQ(outcome_name(Outcome::ok), "stable");
  EXPECT_STREQ(outcome_name(Outcome::over_stretched), "over_stretched");
  EXPECT_STREQ(outcome_name(Outcome::exploded), "exploded");
  EXPECT_STREQ(outcome_name(Outcome::nonfinite), "nan");
  EXPECT_STREQ(outcome_name(Outcome::tunnelled), "tunnelled");
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

// The comparison harness's metrics (demos/compare/compare.hpp) on cases with
// known answers: the hanging chain's support force (190 N, docs/design.md
// section 6) from a hand-built equilibrium and from a converged XPBD run,
// the position error of a snapshot against itself and against a shifted
// copy, the judged error with a rigid body, which side of a cloth a body
// is on, the Pareto front and its log-log interpolation, and the CSV round
// trip. Every expected value is written out here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include "demos/compare/cheapest.hpp"
#include "demos/compare/compare.hpp"

namespace xpbd_compare {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

constexpr double kEps = std::numeric_limits<Real>::epsilon();

TEST(CompareChain, SupportForceOfTheClosedFormChain) {
  // Built here, independently of chain_equilibrium: 20 particles of 1 kg,
  // 1 cm links, g = 10, alpha = 1e-6 m/N; link k carries (19 - k) * 10 N.
  ChainParams p;
  std::vector<Vec3> x(20, Vec3::Zero());
  for (int k = 0; k < 19; ++k) x[k + 1] = x[k] - Vec3(0, Real(0.01 + 1e-6 * (19 - k) * 10.0), 0);
  // Round-off: the top link's length (~0.0102 m) carries a few ulp of it,
  // ~4 eps * 0.0102 m, which alpha = 1e-6 m/N turns into a force error.
  const double tol = 4 * kEps * 0.0102 / 1e-6 + 1e-9;
  EXPECT_NEAR(support_force_from_positions(x, p), 190.0, tol);
  EXPECT_DOUBLE_EQ(chain_support_force(p), 190.0);
  // The harness's closed form is the same chain.
  const auto eq = chain_equilibrium(p);
  ASSERT_EQ(eq.size(), x.size());
  EXPECT_LE(position_error(eq, x).max, 20 * 4 * kEps * 0.2);
}

TEST(CompareChain, ConvergedXpbdRunCarries190N) {
  // The chain scene the sweep runs, with XPBD at 20 substeps x 20
  // iterations for 2 s. Why the tolerance is 1e-3 of 190 N:
  // - the chain starts unstretched; drag 10 1/s damps the oscillation by
  //   exp(-10 * 2 / 2) = 4.5e-5 of its initial size by t = 2 s (and
  //   backward Euler damps more), i.e. < 0.01 N in the top link;
  // - a converged backward-Euler substep has the exact static equilibrium
  //   as its fixed point. Per substep the Gauss-Seidel system is
  //   J W J^T + alpha/h^2 with alpha/h^2 = 1e-6 * 1200^2 = 1.44 and J W J^T
  //   the chain's tridiagonal (eigenvalues in (0, 4]), condition number
  //   <= (4 + 1.44) / 1.44 ~ 3.8, so 20 sweeps leave far below 1e-6 of the
  //   per-substep correction;
  // - float round-off: the gravity step per substep is g h^2 = 6.9e-6 m,
  //   ~900 ulp of the positions (|x| <= 0.2 m), so the balance of gravity
  //   and correction is resolved to ~1e-3 per substep. (At 100 substeps,
  //   g h^2 = 2.8e-7 m is only ~40 ulp and the float build's chain settles
  //   0.7 % off: measured 191.4 N. That is the float limit, not the metric.)
  // Together below 0.19 N; an unconverged or wrong metric (a rigid chain
  // reads ~0 N, a 1-sweep XPBD chain tens of kN) fails.
  ChainParams p;
  const xpbd_demos::SceneSpec spec = chain_scene(p, 120);
  xpbd_demos::RunOptions o = xpbd_demos::run_options(spec);
  o.substeps = 20;
  o.iterations = 20;
  std::vector<Vec3> last;
  const auto r = xpbd_demos::run_scene(spec, o, [&](const xpbd_demos::FrameView& v) {
    last.assign(v.positions.begin(), v.positions.end());
  });
  ASSERT_TRUE(r.finite);
  EXPECT_NEAR(support_force_from_positions(last, p), 190.0, 0.19);
  // Positions against the closed form: the total stretch is 1.9e-3 m; the
  // same bounds leave far less than 1e-6 m.
  EXPECT_LT(position_error(last, chain_equilibrium(p)).max, 1e-6);
}

TEST(ComparePositionError, SelfIsZeroAndShiftIsTheShift) {
  std::vector<Vec3> a;
  for (int i = 0; i < 50; ++i) a.push_back(Vec3(Real(0.1 * i), Real(std::sin(i)), Real(-0.02 * i)));
  const PositionError self = position_error(a, a);
  EXPECT_EQ(self.rms, 0.0);
  EXPECT_EQ(self.max, 0.0);
  // Shift by (0.003, -0.004, 0): |s| = 0.005 m for every particle, so RMS =
  // max = 0.005 up to the round-off of the shifted coordinates (|x| <= 5).
  std::vector<Vec3> b = a;
  for (Vec3& x : b) x += Vec3(Real(0.003), Real(-0.004), 0);
  const PositionError e = position_error(b, a);
  EXPECT_NEAR(e.rms, 0.005, 8 * kEps * 5);
  EXPECT_NEAR(e.max, 0.005, 8 * kEps * 5);
  // Half of the particles shifted: RMS = 0.005 / sqrt(2), max = 0.005.
  std::vector<Vec3> c = a;
  for (std::size_t i = 0; i < c.size(); i += 2) c[i] = b[i];
  EXPECT_NEAR(position_error(c, a).rms, 0.005 / std::sqrt(2.0), 8 * kEps * 5);
  std::vector<Vec3> shorter(a.begin(), a.end() - 1);
  EXPECT_THROW(position_error(shorter, a), std::invalid_argument);
  b[7].x() = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_TRUE(std::isnan(position_error(b, a).rms));
}

TEST(ComparePareto, FrontAndLogLogInterpolation) {
  // (ms, err): (1, 1e-1) (2, 1e-2) (3, 5e-2: dominated) (4, 1e-3) (4, 2e-3: dominated).
  const auto f = pareto_front({{3, 5e-2, "c"}, {1, 1e-1, "a"}, {4, 2e-3, "e"}, {2, 1e-2, "b"},
                               {4, 1e-3, "d"}, {5, std::nan(""), "nan"}});
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[0].label, "a");
  EXPECT_EQ(f[1].label, "b");
  EXPECT_EQ(f[2].label, "d");
  // Between (1, 1e-1) and (2, 1e-2) the line in log-log is err = 1e-1 * ms^(-log2(10)):
  // at ms = sqrt(2), err = 1e-1 / sqrt(10).
  EXPECT_NEAR(*error_at_time(f, std::sqrt(2.0)), 1e-1 / std::sqrt(10.0), 1e-12);
  EXPECT_NEAR(*time_at_error(f, 1e-1 / std::sqrt(10.0)), std::sqrt(2.0), 1e-12);
  EXPECT_DOUBLE_EQ(*error_at_time(f, 10), 1e-3);   // beyond the slowest point
  EXPECT_FALSE(error_at_time(f, 0.5).has_value());  // faster than any run
  EXPECT_DOUBLE_EQ(*time_at_error(f, 1), 1.0);      // any run reaches it
  EXPECT_FALSE(time_at_error(f, 1e-4).has_value());  // never reached
}

TEST(CompareCsv, RoundTripAndResumeKey) {
  Row r;
  r.scene = "hanging_chain";
  r.method = "bullet";
  r.scalar = "double";
  r.substeps = 5;
  r.iterations = 2;
  r.frames = 120;
  r.frames_completed = 120;
  r.status = "skipped";
  r.err_rms_final = 1.25e-3;
  r.err_mean = 2.5e-3;
  r.err_worst = 4e-3;
  r.err_series = "0.5:1e-3:2e-3:4e-3;2:1.25e-3:3e-3:1e-3";
  r.support_force = std::nan("");
  r.note = "a, \"quoted\" note";
  const auto path = std::filesystem::temp_directory_path() / "xpbd_test_compare.csv";
  {
    std::ofstream o(path);
    o << csv_header() << '\n' << to_csv(r) << '\n';
  }
  const auto rows = read_csv(path.string());
  std::filesystem::remove(path);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].key(), "hanging_chain/bullet/5x2");
  EXPECT_EQ(rows[0].note, r.note);
  EXPECT_EQ(rows[0].err_series, r.err_series);
  EXPECT_DOUBLE_EQ(rows[0].err_rms_final, 1.25e-3);
  EXPECT_TRUE(std::isnan(rows[0].support_force));
  EXPECT_DOUBLE_EQ(rows[0].err_mean, 2.5e-3);
  EXPECT_DOUBLE_EQ(rows[0].err_worst, 4e-3);
  // A sample is read back from the series by time; judged = max(rms, body).
  ASSERT_TRUE(error_at(rows[0], 0.5).has_value());
  EXPECT_DOUBLE_EQ(error_at(rows[0], 0.5)->rms, 1e-3);
  EXPECT_DOUBLE_EQ(error_at(rows[0], 0.5)->body, 4e-3);
  EXPECT_DOUBLE_EQ(error_at(rows[0], 0.5)->judged(), 4e-3);
  EXPECT_DOUBLE_EQ(error_at(rows[0], 2.0)->judged(), 1.25e-3);
  EXPECT_FALSE(error_at(rows[0], 1.0).has_value());
  // The judged error of a row: its mean or worst over the samples, except
  // for the static closed forms, judged at the final frame.
  EXPECT_DOUBLE_EQ(judged_error(rows[0], Judge::mean), 1.25e-3);  // hanging_chain: final frame
  Row t = rows[0];
  t.scene = "trampoline";
  EXPECT_DOUBLE_EQ(judged_error(t, Judge::mean), 2.5e-3);
  EXPECT_DOUBLE_EQ(judged_error(t, Judge::worst), 4e-3);
  EXPECT_EQ(parse_judge("worst"), Judge::worst);
  EXPECT_THROW(parse_judge("median"), std::invalid_argument);
}

// The error of a sample with a rigid body: particles shifted by 3 mm and
// the body by 5 mm: RMS 3 mm, judged 5 mm (the body); the body matching, 3
// mm (the particles). A NaN anywhere makes the sample NaN; unequal body
// counts throw.
TEST(CompareSampleError, JudgedIsTheLargerOfParticleRmsAndBodyError) {
  Sample ref;
  for (int i = 0; i < 10; ++i) ref.x.push_back(Vec3(Real(0.1 * i), Real(0.5), 0));
  ref.bodies = {Vec3(0, 1, 0)};
  Sample run = ref;
  for (Vec3& p : run.x) p.y() += Real(0.003);
  run.bodies[0].x() += Real(0.005);
  const SampleError e = sample_error(run, ref);
  EXPECT_NEAR(e.rms, 0.003, 8 * kEps);
  EXPECT_NEAR(e.body, 0.005, 8 * kEps);
  EXPECT_NEAR(e.judged(), 0.005, 8 * kEps);
  run.bodies = ref.bodies;
  EXPECT_NEAR(sample_error(run, ref).judged(), 0.003, 8 * kEps);
  run.bodies[0].z() = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_TRUE(std::isnan(sample_error(run, ref).judged()));
  run.bodies.clear();
  EXPECT_THROW(sample_error(run, ref), std::invalid_argument);
}

// A 3x3-particle sheet in the plane y = 0 (2x2 cells, each split into two
// triangles wound so that (b - a) x (c - a) points along +y): a point above
// a triangle's interior is on side +1, below on -1; a point beside the
// sheet, nearest to its border, gets no verdict (0). Pressed into a bowl
// (the centre particle 0.3 m down), a point far below the bowl's lowest
// particle is nearest to that corner: its pseudo-normal still says -1.
TEST(CompareSide, SideOfASheetAndOfABowl) {
  std::vector<Vec3> x;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) x.push_back(Vec3(Real(i), 0, Real(j)));
  std::vector<std::array<xpbd::Index, 3>> tris;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const xpbd::Index a = j * 3 + i, b = a + 1, c = a + 3, d = a + 4;
      // (c - a) x (b - a) = z x x = +y: winding a, c, b.
      tris.push_back({a, c, b});
      tris.push_back({b, c, d});
    }
  EXPECT_EQ(side_of_surface(Vec3(Real(0.3), Real(0.2), Real(0.6)), x, tris, 0), 1);
  EXPECT_EQ(side_of_surface(Vec3(Real(0.3), Real(-0.2), Real(0.6)), x, tris, 0), -1);
  EXPECT_EQ(side_of_surface(Vec3(Real(0.3), Real(0.01), Real(0.6)), x, tris, 0.02), 0);  // within the margin
  EXPECT_EQ(side_of_surface(Vec3(Real(-1), Real(0.1), Real(1)), x, tris, 0), 0);        // beside the border
  x[4].y() = Real(-0.3);  // the centre particle
  EXPECT_EQ(side_of_surface(Vec3(1, -5, 1), x, tris, 0), -1);
  EXPECT_EQ(side_of_surface(Vec3(1, 0, 1), x, tris, 0), 1);  // inside the bowl, above its bottom
  std::vector<std::array<xpbd::Index, 3>> bad = {{0, 1, 99}};
  EXPECT_THROW(side_of_surface(Vec3::Zero(), x, bad, 0), std::out_of_range);

  // A ball (body) above the sheet in the reference, and in a run that
  // passes through it between frames 15 and 30: wrong side from frame 30.
  Snapshots ref, run;
  x[4].y() = 0;
  for (int f : {15, 30, 45}) {
    ref[f] = {x, {Vec3(Real(0.8), Real(0.5), Real(0.9))}};
    run[f] = {x, {Vec3(Real(0.8), f == 15 ? Real(0.4) : Real(-0.4), Real(0.9))}};
  }
  ASSERT_TRUE(wrong_side_frame(run, ref, tris, 0).has_value());
  EXPECT_EQ(*wrong_side_frame(run, ref, tris, 0), 30);
  EXPECT_FALSE(wrong_side_frame(ref, ref, tris, 0).has_value());

  // Lost: the sheet's bounding box has a diagonal of sqrt(8) = 2.83 m. A
  // body 2.5 m from its reference position is still in the scene; 3 m away
  // (frame 45), or non-finite, it is lost.
  Snapshots far = ref;
  far[30].bodies[0].y() += Real(2.5);
  EXPECT_FALSE(lost_body_frame(far, ref).has_value());
  far[45].bodies[0].y() -= Real(3);
  ASSERT_TRUE(lost_body_frame(far, ref).has_value());
  EXPECT_EQ(*lost_body_frame(far, ref), 45);
  far[15].bodies[0].x() = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_EQ(*lost_body_frame(far, ref), 15);
}

// The reference file the float sweep reads: every bit of a double survives
// the round trip (17 significant digits), so a float run is compared with the
// double reference itself; a missing file, another scene's file and another
// particle count are errors naming the file.
TEST(CompareReferenceFile, RoundTripAndErrors) {
  const auto dir = std::filesystem::temp_directory_path() / "xpbd_test_compare_ref";
  std::filesystem::remove_all(dir);
  Snapshots s;
  s[15] = {{Vec3(Real(0.1), Real(-1) / Real(3), Real(2.5e-7)), Vec3(Real(-7), Real(1e3), Real(0))},
           {Vec3(Real(1) / Real(3), 0, 0)}};
  s[120] = {{Vec3(Real(1), Real(2), Real(3)), Vec3(std::numeric_limits<Real>::min(), Real(-0.0), Real(1) / Real(7))},
            {Vec3(0, Real(-2) / Real(7), 1)}};
  write_reference(dir.string(), "scene_a", {s, 77, 0.0123});
  const ReferenceData rd = read_reference(dir.string(), "scene_a", 2, 1);
  EXPECT_EQ(rd.calibration_frame, 77);
  EXPECT_EQ(rd.calibration_strain, 0.0123);
  const Snapshots& back = rd.snaps;
  ASSERT_EQ(back.size(), 2u);
  for (const auto& [f, smp] : s) {
    ASSERT_TRUE(back.count(f));
    for (std::size_t i = 0; i < smp.x.size(); ++i)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(back.at(f).x[i][c], smp.x[i][c]) << "frame " << f << " particle " << i;
    ASSERT_EQ(back.at(f).bodies.size(), 1u);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(back.at(f).bodies[0][c], smp.bodies[0][c]) << "frame " << f << " body";
  }
  auto message = [&](const std::string& scene, std::size_t n, std::size_t nb = 1) {
    try {
      read_reference(dir.string(), scene, n, nb);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("scene_b", 2).find("scene_b.ref: cannot open"), std::string::npos);
  std::filesystem::copy_file(dir / "scene_a.ref", dir / "scene_b.ref");
  EXPECT_NE(message("scene_b", 2).find("not the xpbd-compare reference of scene scene_b"), std::string::npos);
  EXPECT_NE(message("scene_a", 3).find("2 particles, the scene has 3"), std::string::npos);
  EXPECT_NE(message("scene_a", 2, 0).find("1 dynamic bodies, the scene has 0"), std::string::npos);
  {
    std::ofstream o(dir / "scene_c.ref");
    o << "xpbd-compare reference2 scene_c 1 2 1 0 0\nframe 15\n1 2 3\n4 5\n";
  }
  EXPECT_NE(message("scene_c", 2).find("frame 15, particle 1: expected 3 numbers"), std::string::npos);
  {
    std::ofstream o(dir / "scene_d.ref");
    o << "xpbd-compare reference scene_d 1 2 0\nframe 15\n1 2 3\n4 5 6\n";  // the older format
  }
  EXPECT_NE(message("scene_d", 2).find("older format"), std::string::npos);
  std::filesystem::remove_all(dir);
}

// The cheapest setting meeting a target, on hand-made rows whose answer is
// known: the 64x64 run that meets the target is slower than a 32x32 run that
// also meets it, a faster run misses the target, a non-finite run and the
// reference never count, and a method with no qualifying run says so.
TEST(CompareCheapest, PicksTheFastestRunMeetingTheTargetAcrossResolutions) {
  auto row = [](std::string scene, std::string method, int s, int i, double ms, double err,
                std::string status = "ok") {
    Row r;
    r.scene = std::move(scene);
    r.method = std::move(method);
    r.substeps = s;
    r.iterations = i;
    r.status = std::move(status);
    r.wall_ms_median = ms;
    r.projections_per_frame = 1000LL * s * i;
    r.err_mean = err;
    r.err_worst = 3 * err;
    return r;
  };
  const std::vector<Row> rows = {
      row("hanging_cloth_64", "xpbd", 10, 1, 2.0, 0.04),
      row("hanging_cloth_32", "xpbd", 10, 1, 0.5, 0.05),
      row("hanging_cloth_32", "xpbd", 5, 1, 0.3, 0.2),                 // fast, misses
      row("hanging_cloth_32", "xpbd", 1, 1, 0.1, 0.01, "nonfinite"),   // never counts
      row("hanging_cloth_32", "reference", 400, 5, 50, 0.0, "reference"),
      row("hanging_cloth_64", "bullet", 10, 1, 9.0, 0.3),              // misses
      row("other_scene", "xpbd", 1, 1, 0.01, 0.0),                     // another scene
  };
  const std::vector<Cheapest> c = cheapest(rows, "hanging_cloth", 0.06, Judge::mean);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].method, "xpbd");
  ASSERT_TRUE(c[0].row.has_value());
  EXPECT_EQ(c[0].row->scene, "hanging_cloth_32");
  EXPECT_EQ(c[0].row->substeps, 10);
  EXPECT_DOUBLE_EQ(c[0].error, 0.05);
  EXPECT_EQ(c[1].method, "bullet");
  EXPECT_FALSE(c[1].row.has_value());
  // A tighter target moves xpbd to the 64x64 run; an exact scene name keeps
  // the other resolution out.
  const std::vector<Cheapest> t = cheapest(rows, "hanging_cloth", 0.045, Judge::mean);
  ASSERT_TRUE(t[0].row.has_value());
  EXPECT_EQ(t[0].row->scene, "hanging_cloth_64");
  const std::vector<Cheapest> e = cheapest(rows, "hanging_cloth_32", 0.045, Judge::mean);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_FALSE(e[0].row.has_value());
  // Judged by the worst sample (3x the mean here), no run meets 0.06 m.
  const std::vector<Cheapest> w = cheapest(rows, "hanging_cloth", 0.06, Judge::worst);
  EXPECT_FALSE(w[0].row.has_value());
  EXPECT_TRUE(cheapest(rows, "hanging_cloth", 0.15, Judge::worst)[0].row.has_value());
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd_compare

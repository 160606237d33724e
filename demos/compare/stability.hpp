#pragma once
// The stability map of issue 6, item 5 (xpbd-compare stability,
// docs/stability.md): five sweeps run with XPBD, PBD and btSoftBody, every
// run classified as stable, over-stretched, exploded, NaN or tunnelled.
//
//   dt_stiffness  16x16 hanging cloth; time step 1/30 .. 1/1000 s (one
//                 substep per frame) x stiffness level (stiffness_levels()).
//   impact        a 16x16 cloth thrown at 1 .. 100 m/s onto a 1 cm thick
//                 static plate x time step.
//   mass_ratio    a pinned chain of light particles with a heavy last one,
//                 ratio 1 .. 1e5 x budget (substeps x iterations).
//   chain_box     the same chain with a rigid Bullet box attached to its
//                 last particle, box mass / particle mass 1 .. 1e5 x budget.
//   trampoline    the built-in trampoline (0.1 kg cloth pinned at its
//                 corners) with the ball's mass r x 0.1 kg, r = 1 .. 1e5,
//                 x budget.
//
// The classifier is the library's (xpbd/health.hpp, tested in
// tests/unit/test_health.cpp); the tunnelling tracker and the attachment gap
// are plain code on plain data (tests/demos/test_stability.cpp checks them
// on hand-made inputs and frame sequences).
#include <span>
#include <string>
#include <vector>

#include "demos/scene_runner.hpp"
#include "demos/scene_spec.hpp"
#include "xpbd/health.hpp"

namespace xpbd_stability {

using xpbd::Real;
using xpbd::Vec3;

// ---------------------------------------------------------------------------
// Classification.

// The classifier is the library's own (xpbd/health.hpp), as used by
// xpbd-demo's status and the bridge's step statistics; the map only sets
// its thresholds.
using Outcome = xpbd::Health;
using Thresholds = xpbd::HealthThresholds;
using Observation = xpbd::HealthObservation;
using xpbd::classify;

// The map's thresholds (docs/stability.md): over-stretched above 10 % edge
// strain; exploded above 10 x the energy budget (floor 1e-3 J) or farther
// than 10 m + reach outside the initial bounding box.
Thresholds map_thresholds();

// The map's labels, kept from before the classifier moved to the library
// (stability.csv and the charts use them): "stable" for ok, "nan" for
// nonfinite; "over_stretched", "exploded", "tunnelled".
const char* outcome_name(Outcome o);

// Distance (m) of p outside the axis-aligned box [lo, hi] (0 inside).
double outside_distance(const Vec3& p, const Vec3& lo, const Vec3& hi);

// ---------------------------------------------------------------------------
// The sweeps.

// The common stiffness axis: level s in (0, 1] and what each method gets.
struct StiffnessLevel {
  double s = 1;           // the common axis value (= PBD k = btSoftBody kLST)
  Real compliance = 0;    // m/N, XPBD
};
std::vector<StiffnessLevel> stiffness_levels();

// Tunnelling, judged at every frame (TunnelTracker below).
//
// The plate (impact sweep): a static slab whose bottom face is the plane
// y = bottom_y (m), with footprint |x - cx| < half_x, |z - cz| < half_z (m).
// A particle has gone through it when, between two consecutive frames, it
// moves from y >= bottom_y to y < bottom_y and the straight segment between
// its two positions crosses the plane y = bottom_y inside the footprint: the
// only way there is out through the plate's bottom face. A particle that
// falls past the plate's edge (it crosses the plane outside the footprint)
// and then swings in under the plate is not counted; one that goes through
// and comes back, or flies off, is (once).
//
// The ball (trampoline sweep): rigid body `body`, a sphere of radius
// body_radius (m), has passed through the cloth at a frame where its top
// (centre y + radius) is below every cloth particle while its centre is over
// the cloth's initial footprint (the x-z bounding box of the particles at
// frame 0). The cloth is pinned at its corners and the ball starts above it,
// so the ball can only get wholly under the lowest point of the cloth inside
// that footprint by going through the membrane (between the nodes or
// through a stretched-open region); a ball leaving over an edge is outside
// the footprint and not counted.
//
// Both are judged on the frames only (what the callback sees): a particle
// that goes through and comes back within one frame is not seen.
struct TunnelCheck {
  bool enabled = false;  // the plate check
  double bottom_y = 0, cx = 0, cz = 0, half_x = 0, half_z = 0;  // m
  bool body_through = false;  // the ball check
  int body = 0;
  double body_radius = 0;  // m
};

// Fold in every frame, frame 0 first; then read the counts.
class TunnelTracker {
 public:
  explicit TunnelTracker(const TunnelCheck& c) : c_(c) {}
  // x: every particle (m); body_centre: the body's centre (m), used only
  // if c.body_through. Throws std::invalid_argument if the particle count
  // changes between frames.
  void observe(std::span<const Vec3> x, const Vec3& body_centre = Vec3::Zero());
  int particles() const { return through_count_; }  // distinct particles that went through the plate
  bool body() const { return body_through_; }        // the ball passed through the cloth at some frame
  int first_frame() const { return first_; }         // first frame (0 = the first observe) it happened, -1 never
  int count() const { return through_count_ + (body_through_ ? 1 : 0); }

 private:
  TunnelCheck c_;
  int frame_ = -1;
  std::vector<Vec3> prev_;
  std::vector<char> through_;  // per particle: went through the plate
  int through_count_ = 0;
  bool body_through_ = false;
  int first_ = -1;
  double foot_lo_x_ = 0, foot_hi_x_ = 0, foot_lo_z_ = 0, foot_hi_z_ = 0;  // m, the cloth's initial footprint
};

// The attached rigid body of the chain_box sweep: its link to the particle
// is judged like one more chain link (an attachment holds the particle at
// zero distance from the point), its strain being the gap between the
// particle and the attachment point divided by `scale` (m, the chain's link
// length), so that a box that comes loose counts as over-stretched.
struct AttachCheck {
  bool enabled = false;
  int particle = 0, body = 0;
  Vec3 local = Vec3::Zero();  // m, attachment point in the body's frame
  double scale = 1;           // m
};
// The gap (m) between particle position p and the point `local` of a body
// at `pose`.
double attachment_gap(const Vec3& p, const xpbd_demos::BodyPose& pose, const Vec3& local);

struct StabilityRun {
  std::string sweep;    // dt_stiffness | impact | mass_ratio | chain_box | trampoline
  std::string method;   // xpbd | pbd | bullet
  std::string x_label;  // value on the map's x axis, e.g. "dt=1/60"
  std::string y_label;  // value on the map's y axis, e.g. "s=0.01"
  int xi = 0, yi = 0;   // grid cell
  xpbd_demos::SceneSpec spec;
  xpbd_demos::RunOptions options;
  TunnelCheck tunnel;
  AttachCheck attach;
  std::string key() const { return sweep + "/" + method + "/" + x_label + "/" + y_label; }
};
// Every run of the default sweep (quick: a 2x2 corner of each sweep).
std::vector<StabilityRun> stability_runs(bool quick);

struct StabilityRow {
  std::string sweep, method, x_label, y_label;
  int xi = 0, yi = 0;
  std::string outcome;  // outcome_name, "skipped" or "error" (note says why)
  int frames = 0, frames_completed = 0;
  double max_strain = 0, energy_ratio = 0, max_escape = 0;  // 1, 1 (KE_max / budget), m
  int tunnelled = 0;
  double wall_s = 0;  // s, the run
  std::string note;
  std::string key() const { return sweep + "/" + method + "/" + x_label + "/" + y_label; }
};

// Runs one and classifies it.
StabilityRow run_one(const StabilityRun& run, const Thresholds& t = map_thresholds());

// The CSV: text fields quoted where needed (xpbd_compare::quote), so a note
// may hold commas and quotes. read_stability_csv throws std::runtime_error
// naming the file and line for a missing or foreign header or a malformed
// line; `lines` (if given) gets each row's line number.
const char* stability_csv_header();
std::string to_csv(const StabilityRow& r);
std::vector<StabilityRow> read_stability_csv(const std::string& path, std::vector<int>* lines = nullptr);

// Merges CSVs written by `stability run` (shards): one header, rows in the
// sweep's order (rows not in the default sweep after them, as they came).
// A run (key) in more than one input is kept once, its first occurrence,
// if every copy has the same outcome; copies that disagree are an error
// naming both files and lines (which one is right is not the merge's call).
std::vector<StabilityRow> merge_stability(const std::vector<std::string>& inputs);

// v with `prec` significant digits, for labels and messages.
std::string short_num(double v, int prec = 3);

}  // namespace xpbd_stability

namespace xpbd_stability {
// The subcommand `xpbd-compare stability run|merge|report` (compare_main.cpp).
// run: appends one row per run to `out` as it finishes (resume: runs already
// in the file are skipped; --shard i/n: every n-th run from i), progress on
// stderr. report: one gnuplot script per method (four panels, one per
// sweep) into gp_dir, rendering to docs/stability_<method>.png, and the
// grids as text into docs/stability_grids.md.
// sweeps: only these sweeps (empty: all); shards are taken over the whole
// sweep, so the same run is in the same shard either way.
int cmd_run(const std::string& out, bool quick, const std::string& shard, const std::vector<std::string>& sweeps = {});
// merge: merge_stability(inputs) written to out (atomically).
int cmd_merge(const std::vector<std::string>& inputs, const std::string& out);
int cmd_report(const std::string& csv, const std::string& docs, const std::string& gp_dir);
}  // namespace xpbd_stability

#pragma once
// The stability map of issue 6, item 5 (xpbd-compare stability,
// docs/stability.md): three sweeps run with XPBD, PBD and btSoftBody, every
// run classified as stable, over-stretched, exploded, NaN or tunnelled.
//
//   dt_stiffness  16x16 hanging cloth; time step 1/30 .. 1/1000 s (one
//                 substep per frame) x stiffness level (stiffness_levels()).
//   impact        a 16x16 cloth thrown at 1 .. 100 m/s onto a 1 cm thick
//                 static plate x time step.
//   mass_ratio    a pinned chain of light particles with a heavy last one,
//                 ratio 1 .. 1e5 x budget (substeps x iterations).
//   trampoline    the built-in trampoline (0.1 kg cloth pinned at its
//                 corners) with the ball's mass r x 0.1 kg, r = 1 .. 1e5,
//                 x budget.
//
// The classifier is a plain function on plain data (tests/demos/
// test_stability.cpp checks it on hand-made inputs).
#include <span>
#include <string>
#include <vector>

#include "demos/scene_runner.hpp"
#include "demos/scene_spec.hpp"

namespace xpbd_stability {

using xpbd::Real;
using xpbd::Vec3;

// ---------------------------------------------------------------------------
// Classification.

enum class Outcome { stable, over_stretched, exploded, nan, tunnelled };
const char* outcome_name(Outcome o);  // "stable", "over_stretched", "exploded", "nan", "tunnelled"

// The stated thresholds (docs/stability.md lists them).
struct Thresholds {
  double max_strain = 0.1;     // 1: over-stretched above 10 % edge strain (|len/rest - 1|)
  double energy_factor = 10;   // exploded: max KE > factor x (KE_0 + potential energy released)
  double energy_floor = 1e-3;  // J: added to the energy budget (a run starting at rest)
  // m: exploded if a particle gets farther than bound + Observation::reach
  // outside its initial bounding box.
  double bound = 10;
};

// What a run produced (fold frames in with observe_frame, then classify).
struct Observation {
  bool finite = true;
  double max_strain = 0;          // 1, over all frames
  double kinetic0 = 0;            // J, initial kinetic energy
  double potential0 = 0;          // J, initial potential energy
  double potential_min = 0;       // J, smallest potential energy seen
  double kinetic_max = 0;         // J, largest kinetic energy seen
  double max_escape = 0;          // m, largest distance of a particle outside the initial bounding box
  // m, how far a particle can get without energy from the solver: the
  // ballistic reach v0_max T + |g| T^2 / 2 over the run's duration T.
  double reach = 0;
  int tunnelled = 0;              // particles on the wrong side of the thin feature at the end
};

// Order of precedence: NaN, exploded (energy), tunnelled, exploded
// (distance bound), over-stretched, stable.
Outcome classify(const Observation& o, const Thresholds& t = {});

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

// A thin feature to check tunnelling against: particles that end with
// y < below_y and |x - cx| < half_x and |z - cz| < half_z are on the wrong
// side (under the plate / under the support). Disabled if !enabled.
struct TunnelCheck {
  bool enabled = false;
  double below_y = 0, cx = 0, cz = 0, half_x = 0, half_z = 0;  // m
  // The other way round (the trampoline): rigid body `body`, a sphere of
  // radius body_radius (m), has gone through the cloth if at the end its
  // top (centre y + radius) is below every particle.
  bool body_through = false;
  int body = 0;
  double body_radius = 0;
};

// The geometric checks at the last frame: how many of the particles x (m)
// are under the plate (c.below_y, inside the footprint), and whether a
// body whose centre is at height body_y (m) is wholly below every particle.
int particles_through(std::span<const Vec3> x, const TunnelCheck& c);
bool body_through(std::span<const Vec3> x, double body_y, const TunnelCheck& c);

struct StabilityRun {
  std::string sweep;    // dt_stiffness | impact | mass_ratio | trampoline
  std::string method;   // xpbd | pbd | bullet
  std::string x_label;  // value on the map's x axis, e.g. "dt=1/60"
  std::string y_label;  // value on the map's y axis, e.g. "s=0.01"
  int xi = 0, yi = 0;   // grid cell
  xpbd_demos::SceneSpec spec;
  xpbd_demos::RunOptions options;
  TunnelCheck tunnel;
  std::string key() const { return sweep + "/" + method + "/" + x_label + "/" + y_label; }
};
// Every run of the default sweep (quick: a 2x2 corner of each sweep).
std::vector<StabilityRun> stability_runs(bool quick);

struct StabilityRow {
  std::string sweep, method, x_label, y_label;
  int xi = 0, yi = 0;
  std::string outcome;  // outcome_name, or "error" (note says why)
  int frames = 0, frames_completed = 0;
  double max_strain = 0, energy_ratio = 0, max_escape = 0;  // 1, 1 (KE_max / budget), m
  int tunnelled = 0;
  double wall_s = 0;  // s, the run
  std::string note;
  std::string key() const { return sweep + "/" + method + "/" + x_label + "/" + y_label; }
};

// Runs one and classifies it.
StabilityRow run_one(const StabilityRun& run, const Thresholds& t = {});

const char* stability_csv_header();
std::string to_csv(const StabilityRow& r);
std::vector<StabilityRow> read_stability_csv(const std::string& path);

}  // namespace xpbd_stability

namespace xpbd_stability {
// The subcommand `xpbd-compare stability run|report` (compare_main.cpp).
// run: appends one row per run to `out` as it finishes (resume: runs already
// in the file are skipped; --shard i/n: every n-th run from i), progress on
// stderr. report: one gnuplot script per method (four panels, one per
// sweep) into gp_dir, rendering to docs/stability_<method>.png, and the
// grids as text into docs/stability_grids.md.
int cmd_run(const std::string& out, bool quick, const std::string& shard);
int cmd_report(const std::string& csv, const std::string& docs, const std::string& gp_dir);
}  // namespace xpbd_stability

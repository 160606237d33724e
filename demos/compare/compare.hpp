#pragma once
// The comparison harness of issue 6 (xpbd-compare, docs/results.md): the
// benchmark scenes, the budgets, the error metrics against a reference, the
// CSV rows (append, resume, shard, merge) and the Pareto fronts.
//
// Everything here is plain functions on plain data so that
// tests/demos/test_compare.cpp can check the metrics on cases with known
// answers; compare_main.cpp is the program around them.
#include <cstddef>
#include <iosfwd>
#include <array>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "demos/compare/catenary.hpp"
#include "demos/scene_runner.hpp"
#include "demos/scene_spec.hpp"

namespace xpbd_compare {

using xpbd::Real;
using xpbd::Vec3;

// ---------------------------------------------------------------------------
// Budgets: substeps x iterations per frame (btSoftBody: internal steps x
// piterations), i.e. projections per element and frame.
struct Budget {
  int substeps = 1;
  int iterations = 1;
  int per_element() const { return substeps * iterations; }
};

// The default sweep (docs/results.md lists it): s x 1 for s in
// {1,2,5,10,20,50,100}, 1 x i for i in {2,5,10,20,50,100}, and the mixed
// 2x5, 5x2, 5x5, 10x2, 10x5, 20x5. --quick: 1x1, 5x1, 1x5.
std::vector<Budget> sweep_budgets(bool quick);

// ---------------------------------------------------------------------------
// The vertical hanging chain (docs/design.md section 6): n particles of `mass`
// (kg) `spacing` (m) apart, the top one pinned, gravity g (m/s^2) along -y,
// links of compliance `compliance` (m/N). Its static equilibrium is closed
// form: link k (from the top, k = 0 .. n-2) carries the weight below it,
// T_k = (n-1-k) m g, so it is stretched to spacing + compliance T_k, and the
// support force is T_0 = (n-1) m g (190 N for the defaults).
struct ChainParams {
  int n = 20;
  Real mass = 1;            // kg per particle
  Real spacing = Real(0.01);  // m, rest length of a link
  Real g = 10;              // m/s^2
  Real compliance = Real(1e-6);  // m/N
  // m, the pinned particle. At the origin: positions near 0 keep the
  // float build's round-off far below the links' stretch (1.9e-4 m at the top).
  Vec3 top = Vec3::Zero();
  // 1/s: velocity damping so that the run settles to the static state the
  // closed form describes (the equilibrium does not depend on it).
  Real drag = 10;
};

// The chain as a scene (a rope generator; the rope starts unstretched).
xpbd_demos::SceneSpec chain_scene(const ChainParams& p, int frames);
// Closed-form equilibrium positions (m), particle 0 at p.top.
std::vector<Vec3> chain_equilibrium(const ChainParams& p);
// Closed-form support force (N): (n-1) m g.
double chain_support_force(const ChainParams& p);
// The support force (N) the positions imply: the top link's tension from
// its stretch, (|x1 - x0| - spacing) / compliance (Hooke's law of the
// declared compliance; at equilibrium it carries the whole hanging weight).
double support_force_from_positions(std::span<const Vec3> x, const ChainParams& p);

// ---------------------------------------------------------------------------
// The benchmark scenes.
struct CompareScene {
  std::string id;                 // CSV/file key, [a-z0-9_]
  xpbd_demos::SceneSpec spec;     // frames set (spec.solver.frames)
  std::optional<ChainParams> chain;  // set: the reference is the closed form
  std::optional<CatenaryParams> catenary;  // set: the reference is the closed form
  // Otherwise the reference is XPBD in double at this budget (2B), checked
  // against the same at half the substeps (B); substeps must be even.
  Budget reference{4000, 1};
  // The scene has a dynamic rigid body.
  bool dynamic_bodies = false;
  // How often the XPBD/PBD runs and the reference step Bullet. Once per
  // frame (false) where the pre-solve coupling makes that exact: a coupled
  // body that touches only XPBD systems is integrated inside XPBD's substeps
  // (the trampoline's ball). At every substep (true,
  // RunOptions::rigid_steps = substeps) where a coupled body also rests on
  // another Bullet body: that contact is Bullet's, solved once per Bullet
  // step, and at one step per frame cloth_on_sphere's box, pressed by the
  // cloth, sinks into the ground (docs/bridge-limitations.md). Scenes
  // with a dynamic body also run XPBD the other way (alt_rigid_method), to
  // measure the difference in the same sweep.
  bool rigid_substeps = false;
  // "xpbd_rigid_substeps" (Bullet at every substep) or "xpbd_rigid_once"
  // (once per frame): the other stepping than the scene's own.
  const char* alt_rigid_method() const { return rigid_substeps ? "xpbd_rigid_once" : "xpbd_rigid_substeps"; }
};
std::vector<CompareScene> compare_scenes(bool quick);

// The scenes whose reference is a closed-form static equilibrium
// (hanging_chain, catenary): they are judged at the final frame, once they
// have settled, whatever time the other scenes are charted at.
bool static_reference(const std::string& scene);

// ---------------------------------------------------------------------------
// Position error between two snapshots of the same particles (m): RMS and
// maximum over particles of |a_i - b_i|. Throws std::invalid_argument if the
// sizes differ. NaN if any position is not finite.
struct PositionError {
  double rms = 0;
  double max = 0;
};
PositionError position_error(std::span<const Vec3> a, std::span<const Vec3> b);

// The frames at which positions are compared: every `every` frames
// (0.25 s at 60 Hz for every = 15) and the last frame.
std::vector<int> sample_frames(int frames, int every = 15);

// One sample of a run: every particle's position and the centre of mass of
// every dynamic rigid body (m), in scene order.
struct Sample {
  std::vector<Vec3> x;
  std::vector<Vec3> bodies;
};
// The samples of one run, by frame.
using Snapshots = std::map<int, Sample>;

// The error of one sample against the reference's (m): the particles' RMS
// and largest distance, and the largest distance between a dynamic body's
// centre and the reference's. judged() = max(rms, body): a run whose cloth
// matches but whose ball does not is as wrong as the ball. NaN (and
// judged() NaN) if anything is not finite; std::invalid_argument if the
// particle or body counts differ.
struct SampleError {
  double rms = 0, max = 0, body = 0;
  double judged() const;
};
SampleError sample_error(const Sample& run, const Sample& ref);

// Which side of a surface a point is on: +1 or -1 by the normal of the
// surface feature nearest to it (a triangle's (b - a) x (c - a); on an edge
// or a corner the angle-weighted pseudo-normal of Baerentzen and Aanaes,
// which gives the right side of a bowl seen from far below its lowest
// corner); 0 (no verdict) where that feature is on the border (an edge of
// one triangle, or a corner on one) or where the point is not farther from
// the surface than `margin` (m). Indices outside x throw
// std::out_of_range.
int side_of_surface(const Vec3& p, std::span<const Vec3> x, std::span<const std::array<xpbd::Index, 3>> triangles,
                    double margin);

// A rigid body on the wrong side of the cloth: the first sample frame at
// which some dynamic body is on one side of the soft surface in the run
// and on the other in the reference (side_of_surface, both with a
// verdict); nullopt if there is none.
std::optional<int> wrong_side_frame(const Snapshots& run, const Snapshots& ref,
                                    std::span<const std::array<xpbd::Index, 3>> triangles, double margin);

// A rigid body that has left the scene (fallen through and away, or thrown
// out), where the side test may have no verdict: the first sample frame at
// which some dynamic body is farther from its reference position than the
// diagonal of the reference particles' bounding box at that frame; nullopt
// if there is none (a non-finite body counts as lost).
std::optional<int> lost_body_frame(const Snapshots& run, const Snapshots& ref);

// ---------------------------------------------------------------------------
// One CSV row per run (docs/results.md lists the columns).
struct Row {
  std::string scene, method, scalar;
  int substeps = 0, iterations = 0, frames = 0, frames_completed = 0;
  // ok | nonfinite | exploded | wrong_side | lost_body | skipped | error | reference
  std::string status;
  int particles = 0;
  long long projections_per_frame = 0;
  double wall_ms_median = 0, wall_ms_mean = 0;
  double err_rms_final = 0, err_max_final = 0;  // m, at the last frame
  double err_rms_worst = 0, err_max_worst = 0;  // m, worst over the sample times
  double err_body_worst = 0;  // m, dynamic bodies' centres, worst over the sample times
  // m, SampleError::judged() over the sample times: their mean and worst
  // (the charted errors: docs/results.md).
  double err_mean = 0, err_worst = 0;
  std::string err_series;     // "t:rms:max:body;..." (s, m, m, m)
  double max_strain = 0, mean_strain = 0, max_penetration = 0;  // 1, 1, m
  double energy_drift = 0;    // (E_end - E_0) / (M g L), see docs/results.md
  double support_force = 0;   // N, chain only (NaN elsewhere)
  std::string note;

  std::string key() const;  // scene/method/substeps/iterations
};
// The error at time t (s) from r.err_series (the entry whose time is within
// 1e-6 s of t); nullopt if the series has no such entry.
std::optional<SampleError> error_at(const Row& r, double t);

// How a run's error is judged over its samples (the charts, the fronts,
// the ratios, the cheapest settings): the mean or the worst of
// SampleError::judged() over every sample time. The scenes whose reference
// is a static closed form (static_reference) are judged at the final frame
// whatever the choice.
enum class Judge { mean, worst };
double judged_error(const Row& r, Judge j);
// "mean" | "worst"; parse_judge throws std::invalid_argument for anything else.
const char* judge_name(Judge j);
Judge parse_judge(const std::string& s);
const char* csv_header();
std::string to_csv(const Row& r);
// One CSV field: as is, or in double quotes (inner quotes doubled, newlines
// made spaces) if it holds a comma, quote or newline; split_csv undoes it.
// (Also used by the stability map's CSV, stability_cmd.cpp.)
std::string quote(const std::string& s);
std::vector<std::string> split_csv(const std::string& line);
// Parses a file written by to_csv (header first). Throws std::runtime_error
// naming the file and line for a malformed line.
std::vector<Row> read_csv(const std::string& path);

// ---------------------------------------------------------------------------
// The reference of a scene in a text file, so that a float build is
// compared with the double reference and a resumed sweep need not recompute
// it (xpbd-compare run --reference-dir): first line "xpbd-compare
// reference2 <scene> <samples> <particles> <bodies> <calibration frame>
// <mean strain there>", then per sample frame a line "frame F", one line
// "x y z" per particle and one per dynamic body (17 significant digits:
// every bit of a double). write_reference writes dir/<scene>.ref atomically
// (creating dir); read_reference throws std::runtime_error naming the file
// and what is wrong (missing, another scene's or an older format, another
// particle or body count, a short or malformed frame).
struct ReferenceData {
  Snapshots snaps;
  // btSoftBody's kLST calibration (docs/results.md): the frame at which the
  // reference's mean edge strain is largest (for the trampoline, the
  // ball's deepest dip) and that strain.
  int calibration_frame = 0;
  double calibration_strain = 0;
};
void write_reference(const std::string& dir, const std::string& scene, const ReferenceData& ref);
ReferenceData read_reference(const std::string& dir, const std::string& scene, std::size_t particles,
                             std::size_t bodies);
// True if dir/<scene>.ref exists.
bool have_reference(const std::string& dir, const std::string& scene);

// ---------------------------------------------------------------------------
// Pareto fronts (error against ms per frame, lower is better in both).
struct Point {
  double ms = 0;
  double err = 0;
  std::string label;  // e.g. "10x2"
};
// The points not dominated by another (another with ms <= and err <=, one
// strictly), sorted by ms ascending (so err descends). Points with a
// non-finite or non-positive value are left out.
std::vector<Point> pareto_front(std::vector<Point> pts);
// Error at time ms on the front, linear in log-log between neighbouring
// front points; beyond the slowest point the front's best error (more time
// can always buy that error); below the fastest point: nullopt.
std::optional<double> error_at_time(const std::vector<Point>& front, double ms);
// Time to reach error err on the front, linear in log-log; above the largest
// error the fastest point's time; below the smallest error: nullopt (not
// reached).
std::optional<double> time_at_error(const std::vector<Point>& front, double err);

}  // namespace xpbd_compare

#pragma once
// The scene runner: runs one SceneSpec (scene_spec.hpp) headless with XPBD,
// PBD or Bullet's btSoftBody in a Bullet world with the scene's rigid bodies,
// and measures every solver with the same code (docs/metrics.md).
//
//   xpbd, pbd  btDiscreteDynamicsWorld + xpbd_bullet::XpbdWorld; one Bullet
//              internal step per frame (stepSimulation(dt, 1, dt)), in which
//              the particle system runs `substeps` substeps of `iterations`
//              sweeps each;
//   bullet     btSoftRigidDynamicsWorld + the same particle system built as a
//              btSoftBody (xpbd_bullet::build_softbody, docs/design.md section 5):
//              `substeps` internal steps of dt/substeps per frame
//              (stepSimulation(h, 1, h) each) with piterations = `iterations`,
//              so both count substeps x iterations x elements projections.
//
// The rigid bodies are the same in all three (rigid_world.hpp). Elements a
// btSoftBody cannot express make the bullet run refuse the scene
// (bullet_can_express says which and why) rather than run a different scene.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "demos/rigid_world.hpp"
#include "demos/run_forces.hpp"
#include "demos/scene_spec.hpp"
#include "xpbd/health.hpp"

namespace xpbd_demos {

// The effective run settings. Start from run_options(spec) (the scene's own
// solver settings), then apply command-line overrides.
struct RunOptions {
  Solver solver = Solver::xpbd;
  xpbd::Real dt = xpbd::Real(1) / xpbd::Real(60);  // s, frame length (> 0)
  int substeps = 10;   // >= 1: XPBD/PBD substeps per frame; btSoftBody internal steps per frame
  int iterations = 1;  // >= 1: Gauss-Seidel sweeps per substep; btSoftBody piterations
  int frames = 180;    // >= 1: frames to run
  // btSoftBody only: voxel edge of the world's sparse signed-distance field
  // (m). 0 = automatic: min(0.25 m, thinnest rigid feature / 4) (see
  // "The SDF voxel" in docs/metrics.md).
  xpbd::Real bullet_sdf_voxel = 0;
  // xpbd/pbd only: collect the per-stage wall-clock breakdown
  // (RunResult::stage_ms_per_frame, docs/stages.md). Ignored by bullet runs
  // (btSoftBody has no per-stage hooks; the run gets a note saying so).
  bool stage_times = false;
  // xpbd/pbd only: Bullet steps per frame. The frame's `substeps` are split
  // evenly over them (each Bullet step of dt/rigid_steps runs
  // substeps/rigid_steps XPBD substeps), so the rigid bodies are integrated
  // rigid_steps times per frame; rigid_steps = substeps steps them at every
  // substep (the comparison harness's converged reference for coupled
  // scenes). Must divide substeps. Default 1: one Bullet step per frame, the
  // bridge's normal use (docs/metrics.md).
  int rigid_steps = 1;
  // xpbd/pbd only: threads for the coloured sweep and the bridge's contact
  // search (xpbd::Workers; > 1 needs solver.coloured). The results are the
  // same bits at every count.
  int threads = 1;
  // false: RunResult::series and frame_ms stay empty and the summaries are
  // accumulated frame by frame, so memory does not grow with the frames
  // (the frame callback still sees every frame's metrics). The summaries
  // are the same, but wall_ms_median, which then comes from a histogram of
  // 1%-wide bins (within 0.5%).
  bool keep_series = true;
  // What decides RunResult::status (xpbd/health.hpp): max_strain comes
  // from the scene (solver.max_strain); the rest are the library's
  // defaults (energy factor 10, floor 1e-3 J, no distance bound).
  xpbd::HealthThresholds health;
  // xpbd/pbd only: the accuracy target (the scene's solver.tolerance and
  // penetration_tolerance and max_substeps; xpbd_bullet::Tolerance). With
  // either > 0, `substeps` is where the count starts, and the run picks it
  // frame by frame.
  double tolerance = 0;              // largest strain
  ToleranceMeasure tolerance_measure = ToleranceMeasure::strain;  // what `tolerance` measures
  double penetration_tolerance = 0;  // m, deepest contact violation
  int max_substeps = 200;
  bool tolerance_on() const { return tolerance > 0 || penetration_tolerance > 0; }
};

// spec.solver's method, dt, substeps, iterations and frames.
RunOptions run_options(const SceneSpec& spec);

const char* solver_name(Solver s);  // "xpbd", "pbd", "bullet"

// Measurements of one frame (after the frame; entry 0 of RunResult::series
// is the initial state). Units in docs/metrics.md. NaN where the state was
// not finite.
struct FrameMetrics {
  double time = 0;              // s
  double kinetic_energy = 0;    // J, movable particles + dynamic rigid bodies
  double potential_energy = 0;  // J, gravity, -sum m g.x (zero at the origin)
  double max_strain = 0;        // 1, max over Distance elements of |len/rest - 1|
  double mean_strain = 0;       // 1, mean of the same
  double max_penetration = 0;   // m, >= 0 (see docs/metrics.md)
  std::optional<double> min_particle_distance;  // m, when particle collision is on
  // With a tolerance (RunOptions::tolerance): the substeps the frame took
  // (summed over its Bullet steps), and whether every step met it.
  std::optional<int> substeps;
  bool tolerance_met = true;
};

// What the frame callback sees.
struct FrameView {
  int frame = 0;      // 0 = initial state (before the first frame), then 1 .. frames
  double time = 0;    // s
  std::span<const xpbd::Vec3> positions;  // m, every particle, global numbering (scene_spec.hpp)
  std::span<const BodyPose> bodies;       // one per SceneSpec body, in order
  bool finite = true;                     // all particle and body states finite
  const FrameMetrics* metrics = nullptr;  // this frame's measurements
  double wall_ms = 0;                     // ms, the frame's wall-clock time (0 for frame 0)
};
// Called before the first frame and after every frame (also after the frame
// that turned non-finite, which is the last). An exception thrown by the
// callback ends the run and propagates (nothing is leaked).
using FrameCallback = std::function<void(const FrameView&)>;

struct RunResult {
  std::string scene;         // SceneSpec::name
  RunOptions options;        // the settings the run used
  int particles = 0;
  int bodies = 0;
  int distance_constraints = 0;
  int frames_completed = 0;  // frames run; < options.frames if the run went non-finite
  bool finite = true;        // no NaN/Inf in any particle or body state
  xpbd::Vec3 gravity = xpbd::Vec3::Zero();  // m/s^2, the potential energy's reference
  bool particle_collision = false;  // explicit Collision pairs or self_collision: min_particle_distance is measured
  // Wall clock of the stepping only (ms per frame), not of the measurements
  // or the callback.
  std::vector<double> frame_ms;
  double wall_ms_median = 0, wall_ms_mean = 0;
  // Constraint projections per frame: xpbd/pbd substeps x iterations x the
  // model's constraint elements; bullet internal steps x piterations x links.
  long long projections_per_frame = 0;
  // Over frames 1 .. frames_completed (not the initial state; a non-finite
  // last frame does not count):
  double max_strain = 0;       // 1, largest per-frame max_strain
  double mean_strain = 0;      // 1, mean of the per-frame mean_strain
  double max_penetration = 0;  // m, largest per-frame max_penetration
  std::optional<double> min_particle_distance;  // m, smallest per-frame value (when on)
  // The run classified over all its frames (xpbd::classify with
  // options.health; docs/metrics.md, "status"): "ok", "over_stretched",
  // "exploded" or "nonfinite".
  std::string status = "ok";
  // Largest kinetic energy over the energy budget (xpbd::energy_budget):
  // above options.health.energy_factor the run is "exploded".
  double energy_ratio = 0;
  // With a tolerance (xpbd/pbd): substeps per frame, mean and largest over
  // frames 1 .. frames_completed, and the frames that missed it (some step
  // at max_substeps still above it). projections_per_frame is then the mean.
  double mean_substeps = 0;
  int max_substeps_used = 0;
  int frames_tolerance_missed = 0;
  std::vector<FrameMetrics> series;  // frames_completed + 1 entries, entry 0 = initial state
  nlohmann::json solver_settings;    // what the solver was configured with
  std::vector<std::string> notes;    // differences between solvers worth knowing
  // state_hash (demos/state_hash.hpp) of the last state the run reached.
  std::uint64_t state_hash = 0;
  // With RunOptions::stage_times (xpbd/pbd): ms per frame (mean over the
  // completed frames) of every stage that had work, in the order they run
  // (xpbd/profile.hpp, xpbd_bullet::SystemTimes), then "other": the rest of
  // the frames' stepping time (Bullet's rigid-body step and glue). Empty
  // otherwise.
  std::vector<std::pair<std::string, double>> stage_ms_per_frame;
  // Forces of the final frame (demos/run_forces.hpp): --solver xpbd runs that
  // completed at least one frame and stayed finite; empty otherwise.
  std::optional<RunForces> forces;
};

// Runs the scene. Relative file paths (OBJ generators, mesh shapes) are
// resolved against spec.base_dir. Throws xpbd::ConfigError for invalid
// options (naming "solver.<field>"), xpbd::SceneError for an invalid scene
// (naming the element and field) or one the chosen solver cannot express
// ("--solver bullet: dihedral_bends: scene has 12 ..."). A NaN/Inf during the
// run ends it early with finite = false; that is a result, not an error.
RunResult run_scene(const SceneSpec& spec, const RunOptions& opt, const FrameCallback& on_frame = {});

// The same with the particle system already expanded:
// soft = expand(spec.soft, spec.base_dir) (the caller keeps its triangles and
// lines for exports).
RunResult run_scene(const SceneSpec& spec, const ExpandedSoft& soft, const RunOptions& opt,
                    const FrameCallback& on_frame = {});

// True if --solver bullet can run the scene; otherwise *why (if given) gets
// every reason, separated by "; ", each naming the element kind and count,
// e.g. "dihedral_bends: scene has 12 dihedral bending elements; btSoftBody
// cannot express them (its links are distance constraints only)".
bool bullet_can_express(const SceneSpec& spec, std::string* why = nullptr);
bool bullet_can_express(const SceneSpec& spec, const ExpandedSoft& soft, std::string* why = nullptr);

// metrics.json (docs/metrics.md); "per_frame" only if r.series was kept.
nlohmann::json to_json(const RunResult& r);
// One entry of metrics.json's "per_frame" (frame k; wall_ms from frame 1 on).
nlohmann::json frame_json(int frame, const FrameMetrics& f, std::optional<double> wall_ms);

}  // namespace xpbd_demos

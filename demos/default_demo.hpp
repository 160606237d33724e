#pragma once
// The default headless demo (`xpbd-demo` with no arguments): the hanging cloth
// run three ways from one SceneDesc -- XPBD, PBD and Bullet's btSoftBody -- at
// a matched budget of constraint projections per frame, measured by the same
// code. See docs/demo.md for the settings, the fairness rules and the fields.
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "demos/metrics.hpp"
#include "demos/scene_hanging_cloth.hpp"

namespace xpbd_demos {

struct DefaultDemoOptions {
  int frames = 180;                          // frames to simulate (>= 1)
  xpbd::Real dt = xpbd::Real(1) / xpbd::Real(60);  // s, frame length
  // Matched budget: projections per frame = steps x iterations x constraints.
  int xpbd_substeps = 10, xpbd_iterations = 1;   // XPBD: many substeps, one iteration
  int pbd_substeps = 1, pbd_iterations = 10;     // PBD (Algorithm 1): one step, many iterations
  int bullet_internal_steps = 1, bullet_piterations = 10;  // btSoftBody
  xpbd::Real bullet_kLST = 1;                // btSoftBody link stiffness (dimensionless)
  HangingClothParams cloth;
};

// Per-frame samples of one method (one entry per frame, after the frame).
struct Series {
  std::vector<double> time;            // s
  std::vector<double> sag;             // m, pin height - lowest y
  std::vector<double> strain_mean;     // dimensionless
  std::vector<double> strain_max;      // dimensionless
  std::vector<double> kinetic_energy;  // J
  std::vector<double> step_ms;         // ms, wall clock of this frame's stepping
};

struct MethodResult {
  std::string name;      // "XPBD", "PBD", "btSoftBody"
  std::string settings;  // short human-readable description
  nlohmann::json settings_json;
  // Wall clock of the stepping only (ms per frame). The median is what the
  // summary prints: it ignores the frames another process interrupted.
  double ms_per_frame_median = 0;
  double ms_per_frame_mean = 0;
  long long projections_per_frame = 0;
  ClothMetrics end;                 // after the last frame
  double sag = 0;                   // m, pin height - end.lowest_y
  bool finite_all_frames = true;    // every frame finite
  Series series;
};

struct DefaultDemoResult {
  DefaultDemoOptions options;
  int particles = 0;
  int distance_constraints = 0;
  std::vector<MethodResult> methods;  // XPBD, PBD, btSoftBody
  // btSoftBody / XPBD; empty when the XPBD value is 0 or not finite.
  std::optional<double> time_ratio, strain_ratio;
};

// Runs the three methods. Throws xpbd::SceneError / xpbd::ConfigError for
// invalid options.
DefaultDemoResult run_default_demo(const DefaultDemoOptions& opt);

// The short summary table (under 25 lines).
void print_summary(const DefaultDemoResult& r, std::FILE* out);

// Everything, with units in the key names (see docs/demo.md).
nlohmann::json to_json(const DefaultDemoResult& r);

}  // namespace xpbd_demos

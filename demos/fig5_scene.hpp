#pragma once
// The seed report's Fig. 5 experiment (section 3.1, "Stiffness dependance of
// PBD"): a square cloth pinned at the two corners of one edge starts flat
// and horizontal, falls and hangs. The same scene runs under PBD and XPBD at
// several iteration counts with everything else equal; a sag/curvature
// metric is recorded over time. Shared by demos/fig5.cpp (the CSV and chart
// of docs/fig5.md) and tests/validation/test_fig5.cpp, so that both measure
// the same setup. Library xpbd_fig5: xpbd only, no Bullet.
#include <string>
#include <vector>

#include "xpbd/builders.hpp"
#include "xpbd/scene.hpp"
#include "xpbd/step.hpp"

namespace xpbd_demos {

struct Fig5Params {
  int n = 10;                   // particles per side (>= 3)
  xpbd::Real size = 1;          // m, side length
  xpbd::Real mass = 1;          // kg, total over the movable particles
  // XPBD compliance (m/N) of every edge: structural and both shear
  // diagonals. 0.04 m/N makes alpha/h^2 = 144 1/kg, 0.73 times the
  // sum w|grad C|^2 = 2 * 98 1/kg of an edge between two particles of
  // 1/98 kg, so 5 Gauss-Seidel iterations converge (docs/fig5.md, "Why this
  // compliance"); a stiffer cloth needs more iterations or substeps.
  xpbd::Real compliance = xpbd::Real(0.04);
  xpbd::Real pbd_stiffness = 1;  // PBD stiffness k in [0, 1] of every edge
  xpbd::Real dt = xpbd::Real(1) / 60;  // s, one frame
  int substeps = 1;             // per frame, the same for both methods
  xpbd::Real duration = 3;      // s
  xpbd::Real drag = 0;          // 1/s, StepConfig::drag (0 = none)
};

struct Fig5Scene {
  xpbd::SceneDesc scene;
  xpbd::ClothGrid grid;
  xpbd::Index centre = 0;  // particle nearest to the cloth's centre, (n/2, n/2)
};

// The cloth: n x n particles in the plane y = 0, pinned (kinematic) at
// (0, 0) and (n-1, 0), which sit at x = -size/2 and x = +size/2, z = 0; the
// rest of the cloth extends towards +z. Structural and shear edges, no
// bending.
Fig5Scene make_fig5_scene(const Fig5Params& p);

// One sample of the metrics (all in m except where noted).
struct Fig5Sample {
  double t = 0;            // s
  double centre_y = 0;     // height of the centre particle
  double lowest_y = 0;     // height of the lowest particle
  double strain_mean = 0;  // mean over the edges of |len/rest - 1| (dimensionless)
  double strain_max = 0;   // max of the same
  double bend_mean = 0;    // rad, mean |dihedral angle| over the interior edges of the triangulation
  bool finite = true;      // every position finite
};

// Runs the scene for p.duration with the given method and iteration count
// and returns a sample at t = 0 and after every `every` frames.
std::vector<Fig5Sample> run_fig5(const Fig5Params& p, xpbd::Method method, int iterations,
                                 int every = 1);

// (max - min) / |mean| of the values (the spread across iteration counts).
double spread(const std::vector<double>& v);

// The iteration counts of the figure.
inline const std::vector<int> kFig5Iterations = {5, 10, 20, 50, 100};

// One run per iteration count, same method and parameters.
struct Fig5Run {
  int iterations = 0;
  std::vector<Fig5Sample> samples;
};
std::vector<Fig5Run> run_fig5_all(const Fig5Params& p, xpbd::Method method,
                                  const std::vector<int>& iterations = kFig5Iterations,
                                  int every = 1);

// Spread across the runs of `field` at sample k (all runs sample the same
// times), and its maximum over the samples with t >= t_from.
double spread_at(const std::vector<Fig5Run>& runs, double Fig5Sample::*field, std::size_t k);
double max_spread(const std::vector<Fig5Run>& runs, double Fig5Sample::*field, double t_from);

}  // namespace xpbd_demos

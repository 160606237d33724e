#include "demos/fig5_scene.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "xpbd/compile.hpp"
#include "xpbd/constraints.hpp"
#include "xpbd/diagnostics.hpp"
#include "xpbd/state.hpp"

namespace xpbd_demos {

using xpbd::Real;
using xpbd::Vec3;

Fig5Scene make_fig5_scene(const Fig5Params& p) {
  if (p.n < 3) throw std::invalid_argument("fig5.n: need at least 3 particles per side");
  Fig5Scene f;
  xpbd::ClothGridDesc d;
  d.nx = d.ny = p.n;
  d.size_u = d.size_v = p.size;
  d.origin = Vec3(-p.size / 2, 0, 0);
  d.u = Vec3::UnitX();  // along the pinned edge
  d.v = Vec3::UnitZ();  // horizontal: the cloth starts flat
  d.mass = p.mass;
  const xpbd::Material mat{p.compliance, Real(0), p.pbd_stiffness};
  d.stretch = mat;
  d.shear = true;
  d.shear_mat = mat;
  d.set_bending(xpbd::ClothBending::none, {});
  d.pins = xpbd::ClothPins::top_corners;
  f.grid = xpbd::add_cloth_grid(f.scene, d);
  f.centre = f.grid.at(p.n / 2, p.n / 2);
  return f;
}

std::vector<Fig5Sample> run_fig5(const Fig5Params& p, xpbd::Method method, int iterations,
                                 int every) {
  const Fig5Scene f = make_fig5_scene(p);
  const xpbd::Model m = xpbd::compile(f.scene);
  xpbd::State s = xpbd::make_state(m);
  xpbd::StepConfig cfg;
  cfg.dt = p.dt;
  cfg.substeps = p.substeps;
  cfg.iterations = iterations;
  cfg.method = method;
  cfg.gravity = Vec3(0, Real(-9.81), 0);
  cfg.drag = p.drag;
  const std::vector<std::array<xpbd::Index, 4>> hinges = xpbd::mesh_hinges(f.grid.triangles);

  auto sample = [&] {
    Fig5Sample r;
    r.t = double(s.time);
    r.centre_y = double(s.x[std::size_t(f.centre)].y());
    r.lowest_y = r.centre_y;
    for (const Vec3& x : s.x) {
      r.finite = r.finite && x.allFinite();
      r.lowest_y = std::min(r.lowest_y, double(x.y()));
    }
    const xpbd::Strain st = xpbd::distance_strain(m, s);
    r.strain_mean = double(st.mean);
    r.strain_max = double(st.max);
    double sum = 0;
    int count = 0;
    for (const auto& h : hinges) {
      Real phi;
      if (xpbd::DihedralBending::angle(h, s.x.data(), phi)) {
        sum += std::abs(double(phi));
        ++count;
      }
    }
    r.bend_mean = count > 0 ? sum / count : 0;
    return r;
  };

  const int frames = int(std::lround(double(p.duration / p.dt)));
  std::vector<Fig5Sample> out;
  out.push_back(sample());
  for (int k = 1; k <= frames; ++k) {
    xpbd::step(m, s, cfg);
    if (k % every == 0 || k == frames) out.push_back(sample());
  }
  return out;
}

double spread(const std::vector<double>& v) {
  if (v.empty()) return 0;
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  double mean = 0;
  for (double x : v) mean += x;
  mean /= double(v.size());
  return (*hi - *lo) / std::abs(mean);
}

std::vector<Fig5Run> run_fig5_all(const Fig5Params& p, xpbd::Method method,
                                  const std::vector<int>& iterations, int every) {
  std::vector<Fig5Run> runs;
  for (int it : iterations) runs.push_back(Fig5Run{it, run_fig5(p, method, it, every)});
  return runs;
}

double spread_at(const std::vector<Fig5Run>& runs, double Fig5Sample::*field, std::size_t k) {
  std::vector<double> v;
  for (const Fig5Run& r : runs) v.push_back(r.samples.at(k).*field);
  return spread(v);
}

double max_spread(const std::vector<Fig5Run>& runs, double Fig5Sample::*field, double t_from) {
  double m = 0;
  if (runs.empty()) return m;
  for (std::size_t k = 0; k < runs.front().samples.size(); ++k)
    if (runs.front().samples[k].t >= t_from) m = std::max(m, spread_at(runs, field, k));
  return m;
}

}  // namespace xpbd_demos

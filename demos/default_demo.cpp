#include "demos/default_demo.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>
#include <type_traits>

#include "xpbd/xpbd.hpp"
#include "xpbd_bullet/softbody_baseline.hpp"

namespace xpbd_demos {
namespace {

using xpbd::Real;
using xpbd::Vec3;
using Clock = std::chrono::steady_clock;

// Every constraint element the xpbd solver visits per sweep (all types; in
// this scene the distances plus the two kinematic pins, which are evaluated
// and skipped).
long long constraint_elements(const xpbd::Model& m) {
  long long n = 0;
  xpbd::for_each_constraint_type([&]<class T>(std::type_identity<T>) {
    n += static_cast<long long>(m.get<T>().size());
  });
  return n;
}

void record(MethodResult& r, const xpbd::Model& model, Real pin_height, Real t, double ms,
            std::span<const Vec3> x, std::span<const Vec3> v) {
  const ClothMetrics m = measure(model, x, v);
  r.finite_all_frames = r.finite_all_frames && m.finite;
  r.end = m;
  r.sag = pin_height - m.lowest_y;
  r.series.time.push_back(t);
  r.series.sag.push_back(r.sag);
  r.series.strain_mean.push_back(m.strain_mean);
  r.series.strain_max.push_back(m.strain_max);
  r.series.kinetic_energy.push_back(m.kinetic_energy);
  r.series.step_ms.push_back(ms);
}

double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

void finish_timing(MethodResult& r) {
  std::vector<double> t = r.series.step_ms;
  if (t.empty()) return;
  r.ms_per_frame_mean = std::accumulate(t.begin(), t.end(), 0.0) / double(t.size());
  std::sort(t.begin(), t.end());
  const std::size_t n = t.size();
  r.ms_per_frame_median = n % 2 ? t[n / 2] : (t[n / 2 - 1] + t[n / 2]) / 2;
}

MethodResult run_xpbd_solver(const char* name, const xpbd::Model& model, Real pin_height,
                             const xpbd::StepConfig& cfg, int frames) {
  MethodResult r;
  r.name = name;
  const bool is_xpbd = cfg.method == xpbd::Method::xpbd;
  r.settings = std::to_string(cfg.substeps) + " substep" + (cfg.substeps == 1 ? "" : "s") +
               " x " + std::to_string(cfg.iterations) + " it";
  r.settings_json = {{"method", is_xpbd ? "xpbd" : "pbd"},
                     {"substeps", cfg.substeps},
                     {"iterations", cfg.iterations},
                     {"damping", 0}};
  r.projections_per_frame =
      static_cast<long long>(cfg.substeps) * cfg.iterations * constraint_elements(model);
  xpbd::State s = xpbd::make_state(model);
  for (int f = 0; f < frames; ++f) {
    const auto t0 = Clock::now();
    xpbd::step(model, s, cfg);
    const auto t1 = Clock::now();
    record(r, model, pin_height, s.time, ms(t1 - t0), s.x, s.v);
  }
  finish_timing(r);
  return r;
}

MethodResult run_btsoftbody(const xpbd::SceneDesc& scene, const xpbd::Model& model, Real pin_height,
                            const xpbd_bullet::SoftBodyBaselineConfig& cfg, int frames) {
  MethodResult r;
  r.name = "btSoftBody";
  r.settings = std::to_string(cfg.internal_steps) + " step" + (cfg.internal_steps == 1 ? "" : "s") +
               " x " + std::to_string(cfg.piterations) + " piter";
  r.settings_json = {{"internal_steps_per_frame", cfg.internal_steps},
                     {"piterations", cfg.piterations},
                     {"kLST", cfg.kLST},
                     {"kDP", 0},
                     {"kCHR", 1},
                     {"kKHR", 1},
                     {"viterations", 0},
                     {"diterations", 0},
                     {"margin_m", cfg.margin},
                     {"sleeping", false}};
  xpbd_bullet::SoftBodyBaseline sb(scene, cfg);
  r.projections_per_frame = sb.projections_per_frame();
  std::vector<Vec3> x, v;
  for (int f = 0; f < frames; ++f) {
    const auto t0 = Clock::now();
    sb.step_frame();
    const auto t1 = Clock::now();
    sb.positions(x);
    sb.velocities(v);
    record(r, model, pin_height, sb.time(), ms(t1 - t0), x, v);
  }
  finish_timing(r);
  return r;
}

std::optional<double> ratio(double num, double den) {
  if (!(den > 0) || !std::isfinite(den) || !std::isfinite(num)) return std::nullopt;
  return num / den;
}

nlohmann::json series_json(const Series& s) {
  return {{"time_s", s.time},
          {"sag_m", s.sag},
          {"strain_mean", s.strain_mean},
          {"strain_max", s.strain_max},
          {"kinetic_energy_J", s.kinetic_energy},
          {"step_ms", s.step_ms}};
}

}  // namespace

DefaultDemoResult run_default_demo(const DefaultDemoOptions& opt) {
  if (opt.frames < 1)
    throw xpbd::ConfigError("frames: must be >= 1, got " + std::to_string(opt.frames));
  DefaultDemoResult res;
  res.options = opt;
  const HangingCloth cloth = make_hanging_cloth(opt.cloth);
  const xpbd::Model model = xpbd::compile(cloth.scene);
  res.particles = model.num_particles();
  res.distance_constraints = static_cast<int>(model.get<xpbd::Distance>().size());
  const Vec3 gravity(Real(0), Real(-9.81), Real(0));  // m/s^2, all three methods

  xpbd::StepConfig xc;
  xc.dt = opt.dt;
  xc.gravity = gravity;
  xc.method = xpbd::Method::xpbd;
  xc.substeps = opt.xpbd_substeps;
  xc.iterations = opt.xpbd_iterations;
  res.methods.push_back(run_xpbd_solver("XPBD", model, cloth.pin_height, xc, opt.frames));
  res.methods.back().settings_json["compliance_m_per_N"] = opt.cloth.compliance;

  xpbd::StepConfig pc = xc;
  pc.method = xpbd::Method::pbd;
  pc.substeps = opt.pbd_substeps;
  pc.iterations = opt.pbd_iterations;
  res.methods.push_back(run_xpbd_solver("PBD", model, cloth.pin_height, pc, opt.frames));
  res.methods.back().settings_json["stiffness"] = opt.cloth.pbd_stiffness;

  xpbd_bullet::SoftBodyBaselineConfig bc;
  bc.dt = opt.dt;
  bc.gravity = gravity;
  bc.internal_steps = opt.bullet_internal_steps;
  bc.piterations = opt.bullet_piterations;
  bc.kLST = opt.bullet_kLST;
  res.methods.push_back(run_btsoftbody(cloth.scene, model, cloth.pin_height, bc, opt.frames));

  const MethodResult& x = res.methods[0];
  const MethodResult& b = res.methods[2];
  res.time_ratio = ratio(b.ms_per_frame_median, x.ms_per_frame_median);
  res.strain_ratio = ratio(b.end.strain_mean, x.end.strain_mean);
  return res;
}

void print_summary(const DefaultDemoResult& r, std::FILE* out) {
  const DefaultDemoOptions& o = r.options;
  const auto& c = o.cloth;
  std::fprintf(out,
               "xpbd-demo: hanging cloth %d x %d particles, %g m x %g m, %g kg, 2 top corners "
               "pinned, starts flat\n",
               c.n, c.n, double(c.size), double(c.size), double(c.mass));
  std::fprintf(out,
               "%d distance constraints (structural + shear + bending), %d frames at %g Hz "
               "(%g s), %s precision\n",
               r.distance_constraints, o.frames, 1.0 / double(o.dt), o.frames * double(o.dt),
               sizeof(Real) == 8 ? "double" : "float");
  std::fprintf(out, "%-10s  %-18s %9s %11s %11s %10s %8s %8s  %s\n", "method", "budget",
               "ms/frame", "proj/frame", "strain mean", "strain max", "sag [m]", "KE [J]",
               "finite");
  for (const MethodResult& m : r.methods)
    std::fprintf(out, "%-10s  %-18s %9.3f %11lld %11.3e %10.3e %8.4f %8.4f  %s\n",
                 m.name.c_str(), m.settings.c_str(), m.ms_per_frame_median, m.projections_per_frame,
                 double(m.end.strain_mean), double(m.end.strain_max), m.sag,
                 double(m.end.kinetic_energy), m.finite_all_frames ? "yes" : "no");
  std::fprintf(out,
               "XPBD: compliance %g m/N on every edge; PBD: k = %g; btSoftBody: kLST = %g, kDP = 0, "
               "no sleeping\n",
               double(c.compliance), double(c.pbd_stiffness), double(o.bullet_kLST));
  auto show = [](const std::optional<double>& v) {
    char buf[32];
    if (v)
      std::snprintf(buf, sizeof buf, "%.2f", *v);
    else
      std::snprintf(buf, sizeof buf, "n/a");
    return std::string(buf);
  };
  std::fprintf(out, "btSoftBody time / XPBD time     = %s  (median ms per frame)\n",
               show(r.time_ratio).c_str());
  std::fprintf(out, "btSoftBody strain / XPBD strain = %s  (mean edge strain after the last frame)\n",
               show(r.strain_ratio).c_str());
}

nlohmann::json to_json(const DefaultDemoResult& r) {
  using nlohmann::json;
  const DefaultDemoOptions& o = r.options;
  json methods = json::array();
  for (const MethodResult& m : r.methods) {
    methods.push_back({{"name", m.name},
                       {"settings", m.settings_json},
                       {"ms_per_frame_median", m.ms_per_frame_median},
                       {"ms_per_frame_mean", m.ms_per_frame_mean},
                       {"projections_per_frame", m.projections_per_frame},
                       {"end",
                        {{"strain_mean", m.end.strain_mean},
                         {"strain_max", m.end.strain_max},
                         {"lowest_y_m", m.end.lowest_y},
                         {"sag_m", m.sag},
                         {"kinetic_energy_J", m.end.kinetic_energy}}},
                       {"finite", m.finite_all_frames},
                       {"series", series_json(m.series)}});
  }
  auto opt_json = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
  return {
      {"schema", "xpbd-demo/default/1"},
      {"units",
       {{"ms_per_frame_*", "milliseconds of wall clock per frame, stepping only (median or mean over frames)"},
        {"step_ms", "milliseconds of wall clock of each frame's stepping"},
        {"projections_per_frame", "constraint projections per frame: steps x iterations x constraints"},
        {"strain", "dimensionless |length/rest - 1| over distance constraints"},
        {"*_m", "metres"},
        {"*_s", "seconds"},
        {"*_J", "joules"},
        {"*_kg", "kilograms"},
        {"*_m_per_N", "metres per newton"},
        {"*_m_per_s2", "metres per second squared"}}},
      {"scene",
       {{"name", "hanging_cloth"},
        {"particles_per_side", o.cloth.n},
        {"size_m", o.cloth.size},
        {"mass_kg", o.cloth.mass},
        {"pinned", "two corners of the top edge (mass 0)"},
        {"start", "flat, horizontal (plane y = 0)"},
        {"particles", r.particles},
        {"distance_constraints", r.distance_constraints},
        {"edges", "structural + shear + bending-distance"},
        {"gravity_m_per_s2", {0.0, -9.81, 0.0}}}},
      {"run",
       {{"frames", o.frames},
        {"frame_dt_s", o.dt},
        {"duration_s", o.frames * double(o.dt)},
        {"precision", sizeof(Real) == 8 ? "double" : "float"}}},
      {"methods", methods},
      {"ratios",
       {{"btsoftbody_over_xpbd_time", opt_json(r.time_ratio)},
        {"btsoftbody_over_xpbd_strain_mean", opt_json(r.strain_ratio)}}}};
}

}  // namespace xpbd_demos

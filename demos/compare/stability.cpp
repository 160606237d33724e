#include "demos/compare/stability.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <Eigen/Geometry>

#include "demos/builtin_scenes.hpp"
#include "demos/compare/compare.hpp"

namespace xpbd_stability {

using xpbd_demos::RunOptions;
using xpbd_demos::SceneSpec;
using xpbd_demos::Solver;

Thresholds map_thresholds() {
  Thresholds t;
  t.max_strain = 0.1;
  t.energy_factor = 10;
  t.energy_floor = 1e-3;
  t.bound = 10;
  return t;
}

const char* outcome_name(Outcome o) {
  switch (o) {
    case Outcome::ok: return "stable";
    case Outcome::nonfinite: return "nan";
    default: return xpbd::health_name(o);
  }
}

double outside_distance(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double d = std::max({double(lo[k]) - double(p[k]), double(p[k]) - double(hi[k]), 0.0});
    s += d * d;
  }
  return std::sqrt(s);
}

void TunnelTracker::observe(std::span<const Vec3> x, const Vec3& body_centre) {
  ++frame_;
  if (frame_ == 0) {
    prev_.assign(x.begin(), x.end());
    through_.assign(x.size(), 0);
    foot_lo_x_ = foot_lo_z_ = INFINITY;
    foot_hi_x_ = foot_hi_z_ = -INFINITY;
    for (const Vec3& p : x) {
      foot_lo_x_ = std::min(foot_lo_x_, double(p.x()));
      foot_hi_x_ = std::max(foot_hi_x_, double(p.x()));
      foot_lo_z_ = std::min(foot_lo_z_, double(p.z()));
      foot_hi_z_ = std::max(foot_hi_z_, double(p.z()));
    }
  } else if (x.size() != prev_.size()) {
    throw std::invalid_argument("TunnelTracker: " + std::to_string(x.size()) + " particles at frame " +
                                std::to_string(frame_) + ", " + std::to_string(prev_.size()) + " before");
  }
  auto mark = [&] {
    if (first_ < 0) first_ = frame_;
  };
  if (c_.enabled && frame_ > 0) {
    for (std::size_t i = 0; i < x.size(); ++i) {
      const double y0 = double(prev_[i].y()), y1 = double(x[i].y());
      if (through_[i] || !(y0 >= c_.bottom_y && y1 < c_.bottom_y)) continue;
      // Where the segment prev -> x crosses the plane y = bottom_y
      // (y0 > y1 here, so the division is safe).
      const double t = (y0 - c_.bottom_y) / (y0 - y1);
      const double px = double(prev_[i].x()) + t * (double(x[i].x()) - double(prev_[i].x()));
      const double pz = double(prev_[i].z()) + t * (double(x[i].z()) - double(prev_[i].z()));
      if (std::abs(px - c_.cx) < c_.half_x && std::abs(pz - c_.cz) < c_.half_z) {
        through_[i] = 1;
        ++through_count_;
        mark();
      }
    }
  }
  if (c_.body_through && !body_through_ && !x.empty()) {
    double min_y = INFINITY;
    for (const Vec3& p : x) min_y = std::min(min_y, double(p.y()));
    const double bx = double(body_centre.x()), bz = double(body_centre.z());
    const bool over = bx > foot_lo_x_ && bx < foot_hi_x_ && bz > foot_lo_z_ && bz < foot_hi_z_;
    if (over && double(body_centre.y()) + c_.body_radius < min_y) {
      body_through_ = true;
      mark();
    }
  }
  std::copy(x.begin(), x.end(), prev_.begin());
}

double attachment_gap(const Vec3& p, const xpbd_demos::BodyPose& pose, const Vec3& local) {
  const auto& q = pose.orientation;  // (w, x, y, z)
  const Eigen::Quaternion<Real> r(q[0], q[1], q[2], q[3]);
  return double((p - (pose.position + r.normalized() * local)).norm());
}

// ---------------------------------------------------------------------------
// Sweeps.

std::vector<StiffnessLevel> stiffness_levels() {
  // One common axis s: PBD's k and btSoftBody's kLST are s itself; XPBD's
  // compliance goes from the brief's soft end (1e-3 m/N) to alpha = 0 a
  // decade per level (both ends fixed by the brief, the middle by choice).
  return {{0.001, Real(1e-3)}, {0.01, Real(1e-4)}, {0.1, Real(1e-5)},
          {0.5, Real(1e-6)},   {0.9, Real(1e-8)},  {1.0, Real(0)}};
}

std::string short_num(double v, int prec) {
  std::ostringstream o;
  o.precision(prec);
  o << v;
  return o.str();
}

namespace {

struct DtValue {
  const char* label;
  double dt;  // s
};
const std::vector<DtValue>& dt_values() {
  static const std::vector<DtValue> v = {{"1/30", 1.0 / 30},   {"1/60", 1.0 / 60},   {"1/120", 1.0 / 120},
                                         {"1/250", 1.0 / 250}, {"1/500", 1.0 / 500}, {"1/1000", 1.0 / 1000}};
  return v;
}

constexpr int kIterations = 10;  // Gauss-Seidel sweeps (btSoftBody piterations) per step in the dt sweeps

Solver solver_of(const std::string& m) { return m == "xpbd" ? Solver::xpbd : m == "pbd" ? Solver::pbd : Solver::bullet; }

// Sets every distance element's material to level L (XPBD compliance, PBD
// stiffness) and btSoftBody's kLST.
void set_stiffness(SceneSpec& s, const StiffnessLevel& L) {
  for (auto& d : s.soft.particles.distances) {
    d.mat.compliance = L.compliance;
    d.mat.stiffness = Real(L.s);
    d.mat.damping = 0;
  }
  s.solver.bullet_kLST = Real(L.s);
}

// Replaces the generators by their expansion, so that velocities and
// masses can be edited particle by particle.
void flatten(SceneSpec& s) {
  s.soft.particles = xpbd_demos::expand(s.soft, s.base_dir).scene;
  s.soft.generators.clear();
}

RunOptions options(const SceneSpec& s, const std::string& method, double dt, int substeps, int iterations,
                   double seconds) {
  RunOptions o = xpbd_demos::run_options(s);
  o.solver = solver_of(method);
  o.dt = Real(dt);
  o.substeps = substeps;
  o.iterations = iterations;
  o.frames = std::max(1, int(std::lround(seconds / dt)));
  return o;
}

// 16x16 hanging cloth (1 m, 1 kg, pinned at two corners of one edge).
SceneSpec cloth16(const StiffnessLevel& L) {
  const SceneSpec* b = xpbd_demos::find_builtin_scene("hanging_cloth");
  if (!b) throw std::logic_error("stability: no built-in hanging_cloth");
  SceneSpec s = *b;
  auto& c = std::get<xpbd::ClothGridDesc>(s.soft.generators.at(0));
  c.nx = c.ny = 16;
  c.pinned = {{0, 0}, {15, 0}};
  flatten(s);
  set_stiffness(s, L);
  s.name = "stab_hanging_cloth_16";
  return s;
}

// A free 16x16 cloth (0.3 m, 0.1 kg; XPBD 1e-6 m/N, PBD k = 1, kLST = 1),
// its lowest edge 5 cm above a 1 cm thick static plate (2 m x 2 m, top face at y = 0),
// every particle moving down at v (m/s).
constexpr double kPlateHalf = 0.005;  // m, half thickness
SceneSpec impact(double v) {
  SceneSpec s;
  s.name = "stab_impact";
  xpbd::ClothGridDesc c;
  c.nx = c.ny = 16;
  c.size_u = c.size_v = Real(0.3);
  c.origin = Vec3(Real(-0.15), Real(0.05), Real(-0.15));
  c.u = Vec3::UnitX();
  // Tilted by 20 degrees about x, so that one edge hits first and the
  // cloth swings down onto the plate (a flat cloth would stop uniformly).
  c.v = Vec3(0, std::sin(Real(0.35)), std::cos(Real(0.35)));
  c.mass = Real(0.1);
  c.stretch = c.shear_mat = c.bend_mat = xpbd::Material{Real(1e-6), 0, 1};
  s.soft.generators.push_back(c);
  flatten(s);
  s.soft.particles.velocities.assign(s.soft.particles.positions.size(), Vec3(0, Real(-v), 0));
  s.solver.bullet_kLST = 1;
  xpbd_demos::RigidSpec plate;
  plate.name = "plate";
  plate.shape.kind = xpbd_demos::ShapeKind::box;
  plate.shape.half_extents = Vec3(1, Real(kPlateHalf), 1);
  plate.position = Vec3(0, Real(-kPlateHalf), 0);
  plate.mass = 0;
  s.bodies.push_back(plate);
  return s;
}

// The "Small Steps" chain: 10 particles of 10 g, 0.1 m apart, hanging from
// a pin, the last one `ratio` times heavier; inextensible links (XPBD
// alpha = 0, PBD k = 1, kLST = 1). Starts horizontal, so it swings down.
SceneSpec chain(double ratio) {
  SceneSpec s;
  s.name = "stab_chain";
  xpbd::RopeDesc r;
  r.n = 10;
  r.start = Vec3(0, 1, 0);
  r.dir = Vec3::UnitX();
  r.spacing = Real(0.1);
  r.mass = Real(0.01);
  r.pin_first = true;
  r.mat = xpbd::Material{0, 0, 1};
  s.soft.generators.push_back(r);
  flatten(s);
  s.soft.particles.masses.back() = Real(0.01 * ratio);
  s.solver.bullet_kLST = 1;
  return s;
}

// The same chain (every particle 10 g, the last one included) with a rigid
// Bullet box of ratio x 10 g whose hook, a point kHook above the centre of
// its top face, is attached to the chain's last particle: the box hangs below
// the chain's end like a weight on a rope, so its rotation is coupled too. A
// 6 cm cube (half extent 3 cm): small against the 0.1 m links, so the next
// particle stays clear of it. The hook keeps the attached particle out of
// the box's contact range (thickness 5 mm + margin 1 cm): XpbdWorld does
// not exclude an attached particle from contacts with its own body, so a
// particle attached on the surface is pushed off it by the contact while
// the attachment pulls it back (docs/stability.md, "Limits").
constexpr double kBoxHalf = 0.03;  // m
constexpr double kHook = 0.03;     // m
SceneSpec chain_box(double ratio) {
  SceneSpec s = chain(1);
  s.name = "stab_chain_box";
  const Vec3 end = s.soft.particles.positions.back();
  xpbd_demos::RigidSpec box;
  box.name = "box";
  box.shape.kind = xpbd_demos::ShapeKind::box;
  box.shape.half_extents = Vec3::Constant(Real(kBoxHalf));
  box.position = end - Vec3(0, Real(kBoxHalf + kHook), 0);
  box.mass = Real(0.01 * ratio);
  s.bodies.push_back(box);
  xpbd_demos::AttachmentSpec a;
  a.particle = xpbd::Index(s.soft.particles.positions.size() - 1);
  a.body = 0;
  a.local = Vec3(0, Real(kBoxHalf + kHook), 0);
  a.compliance = 0;
  s.attachments.push_back(a);
  return s;
}

// The built-in trampoline with the ball's mass ratio x the cloth's 0.1 kg.
SceneSpec trampoline(double ratio) {
  const SceneSpec* b = xpbd_demos::find_builtin_scene("trampoline");
  if (!b) throw std::logic_error("stability: no built-in trampoline");
  SceneSpec s = *b;
  s.bodies.at(0).mass = Real(0.1 * ratio);
  s.name = "stab_trampoline";
  return s;
}

}  // namespace

std::vector<StabilityRun> stability_runs(bool quick) {
  std::vector<StabilityRun> runs;
  const char* methods[] = {"xpbd", "pbd", "bullet"};
  const auto& dts = dt_values();
  std::vector<int> dt_idx = quick ? std::vector<int>{0, 5} : std::vector<int>{0, 1, 2, 3, 4, 5};
  // dt x stiffness: 1 s of simulated time.
  const auto levels = stiffness_levels();
  for (const char* m : methods)
    for (int xi : dt_idx)
      for (int yi = 0; yi < int(levels.size()); ++yi) {
        if (quick && yi != 0 && yi + 1 != int(levels.size())) continue;
        StabilityRun r;
        r.sweep = "dt_stiffness";
        r.method = m;
        r.x_label = std::string("dt=") + dts[std::size_t(xi)].label;
        r.y_label = "s=" + short_num(levels[std::size_t(yi)].s);
        r.xi = xi;
        r.yi = yi;
        r.spec = cloth16(levels[std::size_t(yi)]);
        r.options = options(r.spec, m, dts[std::size_t(xi)].dt, 1, kIterations, 1.0);
        runs.push_back(std::move(r));
      }
  // Impact speed x dt: 0.3 s.
  const std::vector<double> speeds = quick ? std::vector<double>{1, 100} : std::vector<double>{1, 3, 10, 30, 100};
  for (const char* m : methods)
    for (int xi : dt_idx)
      for (int yi = 0; yi < int(speeds.size()); ++yi) {
        StabilityRun r;
        r.sweep = "impact";
        r.method = m;
        r.x_label = std::string("dt=") + dts[std::size_t(xi)].label;
        r.y_label = "v=" + short_num(speeds[std::size_t(yi)]);
        r.xi = xi;
        r.yi = yi;
        r.spec = impact(speeds[std::size_t(yi)]);
        r.options = options(r.spec, m, dts[std::size_t(xi)].dt, 1, kIterations, 0.3);
        // Out through the plate's bottom face (y = -1 cm) within its
        // 2 m x 2 m footprint.
        r.tunnel.enabled = true;
        r.tunnel.bottom_y = -2 * kPlateHalf;
        r.tunnel.half_x = r.tunnel.half_z = 1;
        runs.push_back(std::move(r));
      }
  // Mass ratio x budget at dt = 1/60: 2 s.
  struct B {
    int s, i;
  };
  const std::vector<B> budgets =
      quick ? std::vector<B>{{1, 1}, {10, 1}} : std::vector<B>{{1, 1}, {1, 10}, {10, 1}, {1, 100}, {10, 10}, {100, 1}};
  const std::vector<double> ratios =
      quick ? std::vector<double>{1, 1e5} : std::vector<double>{1, 10, 100, 1e3, 1e4, 1e5};
  for (const char* m : methods)
    for (int xi = 0; xi < int(budgets.size()); ++xi)
      for (int yi = 0; yi < int(ratios.size()); ++yi) {
        StabilityRun r;
        r.sweep = "mass_ratio";
        r.method = m;
        r.x_label = std::to_string(budgets[std::size_t(xi)].s) + "x" + std::to_string(budgets[std::size_t(xi)].i);
        r.y_label = "r=" + short_num(ratios[std::size_t(yi)]);
        r.xi = xi;
        r.yi = yi;
        r.spec = chain(ratios[std::size_t(yi)]);
        r.options = options(r.spec, m, 1.0 / 60, budgets[std::size_t(xi)].s, budgets[std::size_t(xi)].i, 2.0);
        runs.push_back(std::move(r));
      }
  // Box mass ratio x budget at dt = 1/60: 2 s (the same axes).
  for (const char* m : methods)
    for (int xi = 0; xi < int(budgets.size()); ++xi)
      for (int yi = 0; yi < int(ratios.size()); ++yi) {
        StabilityRun r;
        r.sweep = "chain_box";
        r.method = m;
        r.x_label = std::to_string(budgets[std::size_t(xi)].s) + "x" + std::to_string(budgets[std::size_t(xi)].i);
        r.y_label = "r=" + short_num(ratios[std::size_t(yi)]);
        r.xi = xi;
        r.yi = yi;
        r.spec = chain_box(ratios[std::size_t(yi)]);
        r.options = options(r.spec, m, 1.0 / 60, budgets[std::size_t(xi)].s, budgets[std::size_t(xi)].i, 2.0);
        const auto& a = r.spec.attachments.at(0);
        r.attach = AttachCheck{true, int(a.particle), a.body, *a.local, 0.1};
        runs.push_back(std::move(r));
      }
  // Trampoline ball mass x budget at dt = 1/60: 2 s.
  for (const char* m : methods)
    for (int xi = 0; xi < int(budgets.size()); ++xi)
      for (int yi = 0; yi < int(ratios.size()); ++yi) {
        StabilityRun r;
        r.sweep = "trampoline";
        r.method = m;
        r.x_label = std::to_string(budgets[std::size_t(xi)].s) + "x" + std::to_string(budgets[std::size_t(xi)].i);
        r.y_label = "r=" + short_num(ratios[std::size_t(yi)]);
        r.xi = xi;
        r.yi = yi;
        r.spec = trampoline(ratios[std::size_t(yi)]);
        r.options = options(r.spec, m, 1.0 / 60, budgets[std::size_t(xi)].s, budgets[std::size_t(xi)].i, 2.0);
        r.tunnel.body_through = true;
        r.tunnel.body = 0;
        r.tunnel.body_radius = double(r.spec.bodies.at(0).shape.radius);
        runs.push_back(std::move(r));
      }
  return runs;
}

StabilityRow run_one(const StabilityRun& run, const Thresholds& t) {
  StabilityRow row;
  row.sweep = run.sweep;
  row.method = run.method;
  row.x_label = run.x_label;
  row.y_label = run.y_label;
  row.xi = run.xi;
  row.yi = run.yi;
  row.frames = run.options.frames;
  Observation ob;
  double max_gap = 0;  // m, chain_box: the attachment's largest gap
  {
    double v0 = 0;
    for (const Vec3& v : run.spec.soft.particles.velocities) v0 = std::max(v0, double(v.norm()));
    const double T = double(run.options.frames) * double(run.options.dt);
    ob.reach = v0 * T + 0.5 * double(run.spec.solver.gravity.norm()) * T * T;
  }
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  TunnelTracker tunnel(run.tunnel);
  const bool tracking = run.tunnel.enabled || run.tunnel.body_through;
  const auto t0 = std::chrono::steady_clock::now();
  if (run.options.solver == Solver::bullet) {
    std::string why;
    if (!xpbd_demos::bullet_can_express(run.spec, &why)) {
      row.outcome = "skipped";
      row.note = "btSoftBody cannot express the scene: " + why;
      return row;
    }
  }
  try {
    const auto res = xpbd_demos::run_scene(run.spec, run.options, [&](const xpbd_demos::FrameView& v) {
      if (v.frame == 0) {
        lo = Vec3::Constant(Real(1e30));
        hi = Vec3::Constant(Real(-1e30));
        for (const Vec3& p : v.positions) {
          lo = lo.cwiseMin(p);
          hi = hi.cwiseMax(p);
        }
        ob.kinetic0 = v.metrics->kinetic_energy;
        ob.potential0 = ob.potential_min = v.metrics->potential_energy;
      }
      if (!v.finite) {
        ob.finite = false;
        return;
      }
      const auto& m = *v.metrics;
      ob.max_strain = std::max(ob.max_strain, m.max_strain);
      ob.kinetic_max = std::max(ob.kinetic_max, m.kinetic_energy);
      ob.potential_min = std::min(ob.potential_min, m.potential_energy);
      for (const Vec3& p : v.positions) ob.max_escape = std::max(ob.max_escape, outside_distance(p, lo, hi));
      if (tracking) {
        const bool has_body = run.tunnel.body_through && run.tunnel.body < int(v.bodies.size());
        tunnel.observe(v.positions,
                       has_body ? v.bodies[std::size_t(run.tunnel.body)].position : Vec3(Vec3::Zero()));
      }
      if (run.attach.enabled) {
        const double gap = attachment_gap(v.positions[std::size_t(run.attach.particle)],
                                          v.bodies[std::size_t(run.attach.body)], run.attach.local);
        ob.max_strain = std::max(ob.max_strain, gap / run.attach.scale);
        max_gap = std::max(max_gap, gap);
      }
      ob.tunnelled = tunnel.count();
    });
    ob.finite = ob.finite && res.finite;
    row.frames_completed = res.frames_completed;
    const Outcome o = classify(ob, t);
    row.outcome = outcome_name(o);
    if (tunnel.count() > 0)
      row.note += "first through the " + std::string(run.tunnel.body_through ? "cloth" : "plate") + " at frame " +
                  std::to_string(tunnel.first_frame());
    if (run.attach.enabled) row.note += (row.note.empty() ? "" : "; ") + ("attachment gap max " + short_num(max_gap) + " m");
    for (const auto& n : res.notes) row.note += (row.note.empty() ? "" : "; ") + n;
  } catch (const std::exception& e) {
    // A state that has blown up (finite but ~1e50) can make a query throw
    // before it turns NaN: what was observed up to then decides.
    const Outcome o = classify(ob, t);
    if (o == Outcome::exploded || o == Outcome::nonfinite) {
      row.outcome = outcome_name(o);
      row.note = std::string("the run ended with an error after it blew up: ") + e.what();
    } else {
      row.outcome = "error";
      row.note = e.what();
    }
  }
  row.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  row.max_strain = ob.max_strain;
  row.energy_ratio = ob.kinetic_max / xpbd::energy_budget(ob, t);
  row.max_escape = ob.max_escape;
  row.tunnelled = ob.tunnelled;
  return row;
}

}  // namespace xpbd_stability

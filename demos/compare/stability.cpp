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

#include "demos/builtin_scenes.hpp"

namespace xpbd_stability {

using xpbd_demos::RunOptions;
using xpbd_demos::SceneSpec;
using xpbd_demos::Solver;

const char* outcome_name(Outcome o) {
  switch (o) {
    case Outcome::stable: return "stable";
    case Outcome::over_stretched: return "over_stretched";
    case Outcome::exploded: return "exploded";
    case Outcome::nan: return "nan";
    case Outcome::tunnelled: return "tunnelled";
  }
  return "?";
}

Outcome classify(const Observation& o, const Thresholds& t) {
  if (!o.finite || !std::isfinite(o.max_strain) || !std::isfinite(o.kinetic_max) || !std::isfinite(o.max_escape))
    return Outcome::nan;
  // Energy conservation bounds the kinetic energy by the initial kinetic
  // energy plus the potential energy released so far; solver damping only
  // lowers it. A run whose kinetic energy exceeds that budget many times
  // over has gained energy from the solver.
  const double released = std::max(0.0, o.potential0 - o.potential_min);
  const double budget = o.kinetic0 + released + t.energy_floor;
  if (o.kinetic_max > t.energy_factor * budget) return Outcome::exploded;
  // A particle that went through the plate keeps flying (energy is
  // conserved, but it ends far away): the geometric check comes before the
  // distance bound.
  if (o.tunnelled > 0) return Outcome::tunnelled;
  if (o.max_escape > t.bound + o.reach) return Outcome::exploded;
  if (o.max_strain > t.max_strain) return Outcome::over_stretched;
  return Outcome::stable;
}

double outside_distance(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double d = std::max({double(lo[k]) - double(p[k]), double(p[k]) - double(hi[k]), 0.0});
    s += d * d;
  }
  return std::sqrt(s);
}

int particles_through(std::span<const Vec3> x, const TunnelCheck& c) {
  int n = 0;
  for (const Vec3& p : x)
    if (double(p.y()) < c.below_y && std::abs(double(p.x()) - c.cx) < c.half_x &&
        std::abs(double(p.z()) - c.cz) < c.half_z)
      ++n;
  return n;
}

bool body_through(std::span<const Vec3> x, double body_y, const TunnelCheck& c) {
  double min_y = INFINITY;
  for (const Vec3& p : x) min_y = std::min(min_y, double(p.y()));
  return body_y + c.body_radius < min_y;
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

std::string fmt(double v, int prec = 3) {
  std::ostringstream o;
  o.precision(prec);
  o << v;
  return o.str();
}

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
        r.y_label = "s=" + fmt(levels[std::size_t(yi)].s);
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
        r.y_label = "v=" + fmt(speeds[std::size_t(yi)]);
        r.xi = xi;
        r.yi = yi;
        r.spec = impact(speeds[std::size_t(yi)]);
        r.options = options(r.spec, m, dts[std::size_t(xi)].dt, 1, kIterations, 0.3);
        // Under the plate (below its bottom face) within its footprint.
        r.tunnel = TunnelCheck{true, -2 * kPlateHalf, 0, 0, 1, 1};
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
        r.y_label = "r=" + fmt(ratios[std::size_t(yi)]);
        r.xi = xi;
        r.yi = yi;
        r.spec = chain(ratios[std::size_t(yi)]);
        r.options = options(r.spec, m, 1.0 / 60, budgets[std::size_t(xi)].s, budgets[std::size_t(xi)].i, 2.0);
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
        r.y_label = "r=" + fmt(ratios[std::size_t(yi)]);
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
  {
    double v0 = 0;
    for (const Vec3& v : run.spec.soft.particles.velocities) v0 = std::max(v0, double(v.norm()));
    const double T = double(run.options.frames) * double(run.options.dt);
    ob.reach = v0 * T + 0.5 * double(run.spec.solver.gravity.norm()) * T * T;
  }
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  const auto t0 = std::chrono::steady_clock::now();
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
      if (run.tunnel.enabled && v.frame == run.options.frames) ob.tunnelled = particles_through(v.positions, run.tunnel);
      if (run.tunnel.body_through && v.frame == run.options.frames && run.tunnel.body < int(v.bodies.size()) &&
          body_through(v.positions, double(v.bodies[std::size_t(run.tunnel.body)].position.y()), run.tunnel))
        ++ob.tunnelled;
    });
    ob.finite = ob.finite && res.finite;
    row.frames_completed = res.frames_completed;
    const Outcome o = classify(ob, t);
    row.outcome = outcome_name(o);
    for (const auto& n : res.notes) row.note += (row.note.empty() ? "" : "; ") + n;
  } catch (const std::exception& e) {
    // A state that has blown up (finite but ~1e50) can make a query throw
    // before it turns NaN: what was observed up to then decides.
    const Outcome o = classify(ob, t);
    if (o == Outcome::exploded || o == Outcome::nan) {
      row.outcome = outcome_name(o);
      row.note = std::string("the run ended with an error after it blew up: ") + e.what();
    } else {
      row.outcome = "error";
      row.note = e.what();
    }
  }
  row.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  row.max_strain = ob.max_strain;
  const double budget = ob.kinetic0 + std::max(0.0, ob.potential0 - ob.potential_min) + t.energy_floor;
  row.energy_ratio = ob.kinetic_max / budget;
  row.max_escape = ob.max_escape;
  row.tunnelled = ob.tunnelled;
  // Keep the CSV one field per comma.
  std::replace(row.note.begin(), row.note.end(), ',', ';');
  std::replace(row.note.begin(), row.note.end(), '\n', ' ');
  return row;
}

// ---------------------------------------------------------------------------
// CSV.

const char* stability_csv_header() {
  return "sweep,method,x,y,xi,yi,outcome,frames,frames_completed,max_strain,energy_ratio,max_escape,"
         "tunnelled,wall_s,note";
}

namespace {
std::string num(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream o;
  o.precision(6);
  o << v;
  return o.str();
}
double to_d(const std::string& s) {
  if (s == "nan") return std::nan("");
  if (s == "inf") return INFINITY;
  if (s == "-inf") return -INFINITY;
  return std::stod(s);
}
}  // namespace

std::string to_csv(const StabilityRow& r) {
  std::ostringstream o;
  o << r.sweep << ',' << r.method << ',' << r.x_label << ',' << r.y_label << ',' << r.xi << ',' << r.yi << ','
    << r.outcome << ',' << r.frames << ',' << r.frames_completed << ',' << num(r.max_strain) << ','
    << num(r.energy_ratio) << ',' << num(r.max_escape) << ',' << r.tunnelled << ',' << num(r.wall_s) << ','
    << r.note;
  return o.str();
}

std::vector<StabilityRow> read_stability_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::vector<StabilityRow> rows;
  std::string line;
  int ln = 0;
  while (std::getline(in, line)) {
    ++ln;
    if (line.empty()) continue;
    const std::string where = path + ":" + std::to_string(ln);
    if (ln == 1) {
      if (line != stability_csv_header()) throw std::runtime_error(where + ": not the stability CSV header");
      continue;
    }
    std::vector<std::string> f;
    std::stringstream ss(line);
    std::string cell;
    while (f.size() < 14 && std::getline(ss, cell, ',')) f.push_back(cell);
    std::string rest;
    std::getline(ss, rest);
    f.push_back(rest);
    if (f.size() != 15) throw std::runtime_error(where + ": " + std::to_string(f.size()) + " fields, expected 15");
    try {
      StabilityRow r;
      r.sweep = f[0];
      r.method = f[1];
      r.x_label = f[2];
      r.y_label = f[3];
      r.xi = std::stoi(f[4]);
      r.yi = std::stoi(f[5]);
      r.outcome = f[6];
      r.frames = std::stoi(f[7]);
      r.frames_completed = std::stoi(f[8]);
      r.max_strain = to_d(f[9]);
      r.energy_ratio = to_d(f[10]);
      r.max_escape = to_d(f[11]);
      r.tunnelled = std::stoi(f[12]);
      r.wall_s = to_d(f[13]);
      r.note = f[14];
      rows.push_back(r);
    } catch (const std::logic_error& e) {
      throw std::runtime_error(where + ": malformed field (" + e.what() + ")");
    }
  }
  return rows;
}

// ---------------------------------------------------------------------------
// The subcommand.

int cmd_run(const std::string& out, bool quick, const std::string& shard) {
  int si = 0, sn = 1;
  if (!shard.empty() && (std::sscanf(shard.c_str(), "%d/%d", &si, &sn) != 2 || sn < 1 || si < 0 || si >= sn)) {
    std::cerr << "--shard: expected i/n with 0 <= i < n, got \"" << shard << "\"\n";
    return 2;
  }
  const auto runs = stability_runs(quick);
  // Drop a last line cut off by an interruption (that run is redone).
  if (std::filesystem::exists(out)) {
    std::string text;
    {
      std::ifstream in(out, std::ios::binary);
      text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    if (!text.empty() && text.back() != '\n') {
      const auto nl = text.rfind('\n');
      std::filesystem::resize_file(out, nl == std::string::npos ? 0 : nl + 1);
    }
  }
  const bool exists = std::filesystem::exists(out) && std::filesystem::file_size(out) > 0;
  std::set<std::string> done;
  if (exists)
    for (const auto& r : read_stability_csv(out)) done.insert(r.key());
  std::vector<const StabilityRun*> todo;
  for (std::size_t k = 0; k < runs.size(); ++k)
    if (int(k % std::size_t(sn)) == si && !done.count(runs[k].key())) todo.push_back(&runs[k]);
  std::cerr << "xpbd-compare stability: " << runs.size() << " runs in the sweep, " << todo.size()
            << " to do in this shard (" << done.size() << " already in " << out << ")\n";
  std::ofstream csv(out, std::ios::app);
  if (!csv) {
    std::cerr << out << ": cannot open for appending\n";
    return 1;
  }
  if (!exists) csv << stability_csv_header() << '\n' << std::flush;
  const auto start = std::chrono::steady_clock::now();
  std::size_t n = 0;
  for (const StabilityRun* r : todo) {
    const StabilityRow row = run_one(*r);
    csv << to_csv(row) << '\n' << std::flush;
    std::cerr << "[" << ++n << "/" << todo.size() << "] " << row.key() << ": " << row.outcome << " (strain "
              << fmt(row.max_strain) << ", KE ratio " << fmt(row.energy_ratio) << ", " << fmt(row.wall_s) << " s; "
              << fmt(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()) << " s)\n";
  }
  return 0;
}

int cmd_report(const std::string& csv_path, const std::string& docs, const std::string& gp_dir) {
  const auto rows = read_stability_csv(csv_path);
  std::filesystem::create_directories(gp_dir);
  const char* sweeps[] = {"dt_stiffness", "impact", "mass_ratio", "trampoline"};
  const char* titles[] = {"time step x stiffness (16x16 hanging cloth)", "impact speed (m/s) x time step",
                          "chain mass ratio x budget (substeps x iterations)",
                          "trampoline ball mass ratio x budget"};
  const char* methods[] = {"xpbd", "pbd", "bullet"};
  const std::map<std::string, int> code = {{"stable", 0},   {"over_stretched", 1}, {"exploded", 2},
                                           {"nan", 3},      {"tunnelled", 4},      {"error", 5}};
  std::ostringstream md;
  md << "<!-- generated by `xpbd-compare stability report` from docs/stability.csv -->\n"
     << "Cells: S stable, O over-stretched, E exploded, N NaN, T tunnelled, ! error, . not run.\n\n";
  const char letter[] = {'S', 'O', 'E', 'N', 'T', '!'};
  for (const char* m : methods) {
    std::ofstream gp(gp_dir + "/stability_" + m + ".gp");
    gp << "set terminal pngcairo size 2000,480 noenhanced\nset output '" << docs << "/stability_" << m
       << ".png'\n"
       << "set palette defined (0 '#2ca02c', 1 '#ffbf00', 2 '#d62728', 3 '#000000', 4 '#1f77b4', 5 '#aaaaaa')\n"
       << "set palette maxcolors 6\nset cbrange [-0.5:5.5]\n"
       << "set cbtics ('stable' 0, 'over-stretched' 1, 'exploded' 2, 'NaN' 3, 'tunnelled' 4, 'error' 5)\n"
       << "unset key\nset multiplot layout 1,4 title '" << m << ": stability map'\n";
    for (int s = 0; s < 4; ++s) {
      std::map<int, std::string> xl, yl;
      std::map<std::pair<int, int>, int> cell;
      for (const auto& r : rows)
        if (r.method == m && r.sweep == sweeps[s]) {
          xl[r.xi] = r.x_label;
          yl[r.yi] = r.y_label;
          cell[{r.xi, r.yi}] = code.count(r.outcome) ? code.at(r.outcome) : 5;
        }
      gp << "set title '" << titles[s] << "'\n";
      if (cell.empty()) {
        gp << "unset xtics\nunset ytics\nset xrange [0:1]\nset yrange [0:1]\n"
           << "set label 1 'not run' at 0.4,0.5\nplot 2 with lines\nunset label 1\n";
        continue;
      }
      const int nx = xl.rbegin()->first + 1, ny = yl.rbegin()->first + 1;
      gp << "set xrange [-0.5:" << nx - 0.5 << "]\nset yrange [-0.5:" << ny - 0.5 << "]\nset xtics (";
      bool first = true;
      for (const auto& [i, l] : xl) gp << (std::exchange(first, false) ? "" : ", ") << "'" << l << "' " << i;
      gp << ") rotate by 30 right\nset ytics (";
      first = true;
      for (const auto& [i, l] : yl) gp << (std::exchange(first, false) ? "" : ", ") << "'" << l << "' " << i;
      gp << ")\n$d" << s << " << EOD\n";
      for (int y = 0; y < ny; ++y) {
        for (int x = 0; x < nx; ++x) {
          auto it = cell.find({x, y});
          gp << x << ' ' << y << ' ' << (it == cell.end() ? std::string("NaN") : std::to_string(it->second)) << '\n';
        }
        gp << '\n';
      }
      gp << "EOD\nplot $d" << s << " using 1:2:3 with image\n";
      // The text grid, top row = largest y.
      md << "### " << m << ": " << titles[s] << "\n\n```\n";
      for (int y = ny - 1; y >= 0; --y) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%-10s", yl.count(y) ? yl[y].c_str() : "");
        md << buf;
        for (int x = 0; x < nx; ++x) {
          auto it = cell.find({x, y});
          md << ' ' << (it == cell.end() ? '.' : letter[it->second]);
        }
        md << '\n';
      }
      md << "x: ";
      for (const auto& [i, l] : xl) md << l << ' ';
      md << "\n```\n\n";
    }
    gp << "unset multiplot\n";
  }
  std::ofstream o(docs + "/stability_grids.md");
  o << md.str();
  std::cerr << "xpbd-compare stability report: " << docs << "/stability_grids.md, gnuplot scripts in " << gp_dir
            << "\n";
  return 0;
}

}  // namespace xpbd_stability

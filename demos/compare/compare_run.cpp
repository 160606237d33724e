// xpbd-compare run and merge (compare_cmds.hpp): the sweep of
// docs/results.md. `run` appends one CSV row per run as soon as it finishes
// (flushed), skips runs already in the file (resume), and prints a progress
// line per run on stderr.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "demos/compare/compare.hpp"
#include "demos/compare/compare_cmds.hpp"
#include "demos/scene_runner.hpp"

namespace xpbd_compare {

namespace {

using xpbd_demos::RunOptions;
using xpbd_demos::RunResult;
using xpbd_demos::Solver;

constexpr double kExplodedDrift = 0.1;  // energy_drift above which a finite run is "exploded"
constexpr const char* kScalar = sizeof(xpbd::Real) == sizeof(double) ? "double" : "float";

struct RunSpec {
  std::size_t scene = 0;  // index into the scene list
  std::string method;     // reference, xpbd, xpbd_coloured, xpbd_rigid_substeps, xpbd_rigid_once, pbd, bullet (+ _float)
  Budget budget;
};

struct Captured {
  RunResult result;
  Snapshots snaps;
};

// A body the solvers move (its centre is part of the error).
bool dynamic(const xpbd_demos::RigidSpec& b) { return !b.kinematic && b.mass > 0; }

std::size_t dynamic_count(const CompareScene& cs) {
  return std::size_t(std::count_if(cs.spec.bodies.begin(), cs.spec.bodies.end(), dynamic));
}

Captured run_captured(const CompareScene& cs, Solver solver, Budget b, const std::vector<int>& samples,
                      int rigid_steps = 1) {
  RunOptions o = xpbd_demos::run_options(cs.spec);
  o.solver = solver;
  o.substeps = b.substeps;
  o.iterations = b.iterations;
  o.rigid_steps = rigid_steps;
  Captured c;
  const std::set<int> want(samples.begin(), samples.end());
  c.result = xpbd_demos::run_scene(cs.spec, o, [&](const xpbd_demos::FrameView& v) {
    if (v.frame != 0 && !want.count(v.frame)) return;
    Sample& s = c.snaps[v.frame];
    s.x.assign(v.positions.begin(), v.positions.end());
    for (std::size_t k = 0; k < v.bodies.size() && k < cs.spec.bodies.size(); ++k)
      if (dynamic(cs.spec.bodies[k])) s.bodies.push_back(v.bodies[k].position);
  });
  return c;
}

// Errors of `run` against `ref` at the sample frames (sample_error). A
// frame the run did not reach (non-finite) counts as an infinite error.
void fill_errors(Row& r, const Snapshots& run, const Snapshots& ref, const std::vector<int>& samples, double dt) {
  r.err_rms_worst = r.err_max_worst = r.err_body_worst = r.err_worst = 0;
  double sum = 0;
  std::ostringstream s;
  for (int f : samples) {
    SampleError e{INFINITY, INFINITY, INFINITY};
    auto a = run.find(f);
    auto b = ref.find(f);
    if (a != run.end() && b != ref.end()) e = sample_error(a->second, b->second);
    if (std::isnan(e.judged())) e = {INFINITY, INFINITY, INFINITY};
    if (s.tellp() > 0) s << ';';
    s.precision(4);
    s << double(f) * dt << ':' << e.rms << ':' << e.max << ':' << e.body;
    r.err_rms_worst = std::max(r.err_rms_worst, e.rms);
    r.err_max_worst = std::max(r.err_max_worst, e.max);
    r.err_body_worst = std::max(r.err_body_worst, e.body);
    r.err_worst = std::max(r.err_worst, e.judged());
    sum += e.judged();
    if (f == samples.back()) {
      r.err_rms_final = e.rms;
      r.err_max_final = e.max;
    }
  }
  r.err_mean = samples.empty() ? 0 : sum / double(samples.size());
  r.err_series = s.str();
}

// Energy scale M g L (J): total movable mass (particles and dynamic bodies)
// times |g| times the diagonal of the particles' initial bounding box.
double energy_scale(const CompareScene& cs) {
  const auto soft = xpbd_demos::expand(cs.spec.soft, cs.spec.base_dir);
  double m = 0;
  for (auto w : soft.scene.masses) m += double(w);
  for (const auto& b : cs.spec.bodies) m += b.kinematic ? 0.0 : double(b.mass);
  Vec3 lo = Vec3::Constant(1e30f), hi = Vec3::Constant(-1e30f);
  for (const Vec3& p : soft.scene.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double L = soft.scene.positions.empty() ? 1.0 : double((hi - lo).norm());
  return m * double(cs.spec.solver.gravity.norm()) * std::max(L, 1e-3);
}

Row base_row(const CompareScene& cs, const std::string& method, Budget b) {
  Row r;
  r.scene = cs.id;
  r.method = method;
  r.scalar = kScalar;
  r.substeps = b.substeps;
  r.iterations = b.iterations;
  r.frames = cs.spec.solver.frames;
  r.support_force = std::nan("");
  return r;
}

void fill_run(Row& r, const CompareScene& cs, const Captured& c) {
  const RunResult& res = c.result;
  r.frames_completed = res.frames_completed;
  r.status = res.finite ? "ok" : "nonfinite";
  r.particles = res.particles;
  r.projections_per_frame = res.projections_per_frame;
  r.wall_ms_median = res.wall_ms_median;
  r.wall_ms_mean = res.wall_ms_mean;
  r.max_strain = res.max_strain;
  r.mean_strain = res.mean_strain;
  r.max_penetration = res.max_penetration;
  const auto& s0 = res.series.front();
  const auto& s1 = res.series.back();
  r.energy_drift = res.finite ? ((s1.kinetic_energy + s1.potential_energy) - (s0.kinetic_energy + s0.potential_energy)) /
                                    energy_scale(cs)
                              : std::nan("");
  // A passive scene cannot gain energy: a run that ends with more than 0.1
  // M g L above its start has blown up, even if it stayed finite (the 64x64
  // cloth at 1x1 reaches strains of 1e12). It is kept in the CSV but, like a
  // non-finite run, left off the fronts and the cheapest settings, whatever
  // its error at the charted time.
  if (res.finite && r.energy_drift > kExplodedDrift) r.status = "exploded";
  if ((cs.chain || cs.catenary) && !c.snaps.empty()) {
    auto last = c.snaps.rbegin();
    if (last->first == cs.spec.solver.frames) {
      if (cs.chain) r.support_force = support_force_from_positions(last->second.x, *cs.chain);
      // The catenary's first link (at support a), by the same Hooke's law.
      if (cs.catenary && last->second.x.size() >= 2)
        r.support_force = ((last->second.x[1] - last->second.x[0]).template cast<double>().norm() -
                           double(cs.catenary->spacing)) /
                          double(cs.catenary->compliance);
    }
  }
}

// A run killed while writing its row can leave a last line without its
// newline: cut it off (that run is redone) so that appending stays valid.
void drop_partial_last_line(const std::string& path) {
  if (!std::filesystem::exists(path)) return;
  std::string text;
  {
    std::ifstream in(path, std::ios::binary);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  if (text.empty() || text.back() == '\n') return;
  const auto nl = text.rfind('\n');
  std::filesystem::resize_file(path, nl == std::string::npos ? 0 : nl + 1);
  std::cerr << path << ": dropped an incomplete last line (a run interrupted while writing)\n";
}

// Mean of |length/rest - 1| over the links of a chain of equal rest lengths.
double mean_link_strain(const std::vector<Vec3>& x, double rest) {
  if (x.size() < 2) return 0;
  double sum = 0;
  for (std::size_t k = 0; k + 1 < x.size(); ++k)
    sum += std::abs((x[k + 1] - x[k]).template cast<double>().norm() / rest - 1);
  return sum / double(x.size() - 1);
}

// btSoftBody's kLST is calibrated by measured strain (docs/design.md section
// 5): its links have no compliance, and at kLST = 1 and a large budget they
// end stiffer than the scene's material (the chain's support force falls to
// 5 N of 190 at 100x1). The strain is matched at the moment that matters:
// the frame at which the reference's mean edge strain is largest
// (ReferenceData::calibration_frame: the trampoline's deepest dip; the
// final frame for the static closed forms). Where the run at the scene's
// kLST has a mean edge strain there more than 2% below the reference's,
// kLST is lowered by bisection in log kLST over [1e-4, kLST] (12 runs) to
// the value whose strain at that frame is closest to the reference's, and
// that run is the one reported; the note says so. A run that stretches
// more than the reference keeps kLST: kLST <= 1 cannot make it stiffer.
Captured calibrate_klst(const CompareScene& cs, Budget b, const std::vector<int>& samples, int frame,
                        double target, Captured first, std::string& note) {
  auto strain = [&](const Captured& c) {
    const auto& s = c.result.series;
    return c.result.finite && frame >= 0 && std::size_t(frame) < s.size() ? s[std::size_t(frame)].mean_strain
                                                                           : std::nan("");
  };
  const double k0 = double(cs.spec.solver.bullet_kLST);
  const double s0 = strain(first);
  if (!(s0 < target * 0.98)) return first;
  CompareScene trial = cs;
  double lo = std::log(1e-4), hi = std::log(k0);  // strain falls as kLST rises
  Captured best = std::move(first);
  double best_k = k0, best_gap = std::abs(s0 - target);
  for (int it = 0; it < 12; ++it) {
    const double mid = 0.5 * (lo + hi);
    trial.spec.solver.bullet_kLST = Real(std::exp(mid));
    Captured c = run_captured(trial, Solver::bullet, b, samples);
    const double st = strain(c);
    if (!std::isfinite(st)) {
      lo = mid;  // too soft to stay finite: stiffer
      continue;
    }
    if (std::abs(st - target) < best_gap) {
      best_gap = std::abs(st - target);
      best_k = double(trial.spec.solver.bullet_kLST);
      best = std::move(c);
    }
    (st > target ? lo : hi) = mid;
  }
  std::ostringstream n;
  n.precision(4);
  n << "kLST " << best_k << " (calibrated by strain at frame " << frame << ": mean strain " << strain(best)
    << ", reference " << target << "; at kLST " << k0 << " it was " << s0 << ")";
  note += (note.empty() ? "" : "; ") + n.str();
  return best;
}

// The frame of the largest mean edge strain of a run and that strain.
std::pair<int, double> peak_mean_strain(const RunResult& r) {
  std::pair<int, double> best{0, 0.0};
  for (std::size_t f = 0; f < r.series.size(); ++f)
    if (r.series[f].mean_strain > best.second) best = {int(f), r.series[f].mean_strain};
  return best;
}

// The reference budgets of a scene: B (the check) and 2B (the reference).
std::pair<Budget, Budget> reference_budgets(const CompareScene& cs, bool quick, std::optional<Budget> override_2b) {
  const Budget two_b = override_2b ? *override_2b : quick ? Budget{20, 1} : cs.reference;
  if (two_b.substeps < 2 || two_b.substeps % 2 != 0)
    throw std::logic_error(cs.id + ": reference substeps must be even and >= 2, got " +
                           std::to_string(two_b.substeps));
  return {Budget{two_b.substeps / 2, two_b.iterations}, two_b};
}


}  // namespace

int cmd_run(const RunArgs& args) {
  const std::string& out = args.out;
  const bool quick = args.quick;
  const std::string& shard = args.shard;
  const std::vector<std::string>& only = args.scenes;
  const std::vector<std::string>& methods = args.methods;
  const std::string& ref_dir = args.reference_dir;
  const std::string& ref_budget = args.reference_budget;
  std::optional<Budget> ref_override;
  if (!ref_budget.empty()) {
    Budget b;
    if (std::sscanf(ref_budget.c_str(), "%dx%d", &b.substeps, &b.iterations) != 2 || b.substeps < 2 ||
        b.substeps % 2 != 0 || b.iterations < 1) {
      std::cerr << "--reference: expected SxI with S even and >= 2, I >= 1, got \"" << ref_budget << "\"\n";
      return 2;
    }
    ref_override = b;
  }
  // A float build runs the same methods under the names xpbd_float,
  // pbd_float, bullet_float and compares them with the double reference
  // (read from ref_dir; a float build never makes a reference of its own).
  const bool is_float = sizeof(Real) != sizeof(double);
  const std::string suffix = is_float ? "_float" : "";
  int shard_i = 0, shard_n = 1;
  if (!shard.empty()) {
    if (std::sscanf(shard.c_str(), "%d/%d", &shard_i, &shard_n) != 2 || shard_n < 1 || shard_i < 0 ||
        shard_i >= shard_n) {
      std::cerr << "--shard: expected i/n with 0 <= i < n, got \"" << shard << "\"\n";
      return 2;
    }
  }
  std::vector<CompareScene> scenes = compare_scenes(quick);
  for (const auto& name : only)
    if (std::none_of(scenes.begin(), scenes.end(), [&](const CompareScene& c) { return c.id == name; })) {
      std::cerr << "--scenes: unknown scene \"" << name << "\"\n";
      return 2;
    }
  const char* const kMethods[] = {"reference",       "xpbd", "xpbd_coloured", "xpbd_rigid_substeps",
                                  "xpbd_rigid_once", "pbd",  "bullet"};
  for (const auto& m : methods)
    if (std::find(std::begin(kMethods), std::end(kMethods), m) == std::end(kMethods)) {
      std::cerr << "--methods: unknown method \"" << m
                << "\" (reference, xpbd, xpbd_coloured, xpbd_rigid_substeps, xpbd_rigid_once, pbd, bullet)\n";
      return 2;
    }
  auto wanted = [&](const std::string& m) {
    return methods.empty() || std::find(methods.begin(), methods.end(), m) != methods.end();
  };
  if (is_float && wanted("reference") && !methods.empty()) {
    std::cerr << "--methods reference: the reference runs in the double build only\n";
    return 2;
  }
  if (is_float && ref_dir.empty()) {
    std::cerr << "a float build compares with the double reference: pass --reference-dir (written by the "
                 "double build's run)\n";
    return 2;
  }
  const std::vector<Budget> budgets = sweep_budgets(quick);

  // The whole run list (the same in every shard), then this shard's part.
  std::vector<RunSpec> all;
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    if (!only.empty() && std::find(only.begin(), only.end(), scenes[s].id) == only.end()) continue;
    if (wanted("reference") && !is_float)
      all.push_back({s, "reference",
                     static_reference(scenes[s].id) ? Budget{0, 0}
                                                    : reference_budgets(scenes[s], quick, ref_override).first});
    for (const char* m : {"xpbd", "xpbd_coloured", "xpbd_rigid_substeps", "xpbd_rigid_once", "pbd", "bullet"}) {
      // The other rigid stepping (CompareScene::alt_rigid_method): only where
      // there is a dynamic body to step, and only in double (it measures the
      // coupling, not the precision).
      const std::string ms = m;
      if ((ms == "xpbd_rigid_substeps" || ms == "xpbd_rigid_once") &&
          (!scenes[s].dynamic_bodies || is_float || ms != scenes[s].alt_rigid_method()))
        continue;
      if (wanted(m))
        for (Budget b : budgets) all.push_back({s, m + suffix, b});
    }
  }
  std::set<std::string> done;
  drop_partial_last_line(out);
  const bool exists = std::filesystem::exists(out) && std::filesystem::file_size(out) > 0;
  if (exists)
    for (const Row& r : read_csv(out)) done.insert(r.key());
  std::vector<RunSpec> todo;
  for (std::size_t k = 0; k < all.size(); ++k) {
    if (int(k % std::size_t(shard_n)) != shard_i) continue;
    const RunSpec& rs = all[k];
    if (!done.count(base_row(scenes[rs.scene], rs.method, rs.budget).key())) todo.push_back(rs);
  }
  std::cerr << "xpbd-compare: " << all.size() << " runs in the sweep, " << todo.size()
            << " to do in this shard (" << done.size() << " already in " << out << ")\n";
  std::ofstream csv(out, std::ios::app);
  if (!csv) {
    std::cerr << out << ": cannot open for appending\n";
    return 1;
  }
  if (!exists) csv << csv_header() << '\n' << std::flush;

  const auto t_start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  };
  std::size_t count = 0;
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    std::vector<RunSpec> mine;
    for (const RunSpec& r : todo)
      if (r.scene == s) mine.push_back(r);
    if (mine.empty()) continue;
    const CompareScene& cs = scenes[s];
    const double dt = double(cs.spec.solver.dt);
    const std::vector<int> samples = sample_frames(cs.spec.solver.frames);

    // The reference positions at the sample frames, and the frame and
    // strain btSoftBody's kLST is calibrated to (calibrate_klst).
    Snapshots ref;
    std::optional<std::pair<int, double>> calibration;
    std::optional<CatenaryEquilibrium> cat;
    if (cs.catenary) cat = catenary_equilibrium(*cs.catenary);
    if (cs.chain) {
      const auto eq = chain_equilibrium(*cs.chain);
      for (int f : samples) ref[f].x = eq;
      calibration = {cs.spec.solver.frames, mean_link_strain(eq, double(cs.chain->spacing))};
    } else if (cat) {
      for (int f : samples) ref[f].x = cat->x;
      calibration = {cs.spec.solver.frames, mean_link_strain(cat->x, double(cs.catenary->spacing))};
    } else if (is_float || (have_reference(ref_dir, cs.id) &&
                            done.count(base_row(cs, "reference", reference_budgets(cs, quick, ref_override).first).key()))) {
      // The float build, or a resumed double sweep whose reference row is in
      // the CSV: the reference positions from the file the double run wrote.
      ReferenceData rd = read_reference(ref_dir, cs.id,
                                        xpbd_demos::expand(cs.spec.soft, cs.spec.base_dir).scene.positions.size(),
                                        dynamic_count(cs));
      ref = std::move(rd.snaps);
      calibration = {rd.calibration_frame, rd.calibration_strain};
      std::cerr << "  " << cs.id << ": reference read from " << ref_dir << "\n";
    } else {
      // Bullet stepped as in the XPBD runs (CompareScene::rigid_substeps).
      const auto [ref_b, ref_2b] = reference_budgets(cs, quick, ref_override);
      std::cerr << "  " << cs.id << ": reference runs xpbd " << ref_b.substeps << "x" << ref_b.iterations
                << " and " << ref_2b.substeps << "x" << ref_2b.iterations
                << (cs.rigid_substeps ? " (Bullet stepped at every substep)" : "") << " ...\n";
      Captured b1 = run_captured(cs, Solver::xpbd, ref_b, samples, cs.rigid_substeps ? ref_b.substeps : 1);
      Captured b2 = run_captured(cs, Solver::xpbd, ref_2b, samples, cs.rigid_substeps ? ref_2b.substeps : 1);
      // The finer run is the reference; |B - 2B| estimates its own error
      // (under first-order convergence in h, e(B) = 2 e(2B), so
      // x(B) - x(2B) = e(2B)).
      ref = b2.snaps;
      if (b2.result.finite) calibration = peak_mean_strain(b2.result);
      if (!ref_dir.empty())
        write_reference(ref_dir, cs.id,
                        {ref, calibration ? calibration->first : 0, calibration ? calibration->second : std::nan("")});
      if (std::any_of(mine.begin(), mine.end(), [](const RunSpec& r) { return r.method == "reference"; })) {
        Row r = base_row(cs, "reference", ref_b);
        fill_run(r, cs, b2);
        fill_errors(r, b1.snaps, b2.snaps, samples, dt);
        r.status = b1.result.finite && b2.result.finite ? "reference" : "nonfinite";
        std::ostringstream n;
        n << "reference = xpbd " << ref_2b.substeps << "x" << ref_2b.iterations
          << " (speed columns); err columns = its difference from xpbd " << ref_b.substeps << "x"
          << ref_b.iterations;
        if (cs.rigid_substeps) n << "; Bullet stepped at every substep in both";
        if (calibration) n << "; peak mean strain " << calibration->second << " at frame " << calibration->first;
        r.note = n.str();
        csv << to_csv(r) << '\n' << std::flush;
        std::cerr << "[" << ++count << "/" << todo.size() << "] " << cs.id << " reference: |B - 2B| mean "
                  << r.err_mean << " m, worst " << r.err_worst << " m (" << elapsed() << " s)\n";
      }
    }
    std::string why;
    const bool bullet_ok = xpbd_demos::bullet_can_express(cs.spec, &why);
    const auto triangles = xpbd_demos::expand(cs.spec.soft, cs.spec.base_dir).triangles;
    for (const RunSpec& rs : mine) {
      if (rs.method == "reference") {
        if (cs.chain) {
          Row r = base_row(cs, "reference", rs.budget);
          r.status = "reference";
          r.particles = cs.chain->n;
          r.support_force = chain_support_force(*cs.chain);
          r.note = "closed form: link k carries (n-1-k) m g";
          csv << to_csv(r) << '\n' << std::flush;
          ++count;
        } else if (cat) {
          Row r = base_row(cs, "reference", rs.budget);
          r.status = "reference";
          r.particles = cs.catenary->n;
          r.support_force = cat->support_force_a;
          std::ostringstream n;
          n.precision(6);
          n << "closed form: discrete elastic catenary, H = " << cat->H << " N, V0 = " << cat->V0
            << " N, Newton residual " << cat->residual << " m";
          r.note = n.str();
          csv << to_csv(r) << '\n' << std::flush;
          ++count;
        }
        continue;
      }
      Row r = base_row(cs, rs.method, rs.budget);
      const std::string base = rs.method.substr(0, rs.method.size() - suffix.size());
      // xpbd_coloured: XPBD with the Distance elements projected colour by
      // colour (StepConfig::coloured), the rest as xpbd.
      // xpbd_rigid_substeps / xpbd_rigid_once: XPBD with Bullet stepped at
      // every substep (RunOptions::rigid_steps = substeps) / once per frame
      // instead of as the scene says (CompareScene::rigid_substeps).
      const bool coloured = base == "xpbd_coloured";
      const bool alt = base == "xpbd_rigid_substeps" || base == "xpbd_rigid_once";
      const Solver solver = base == "xpbd" || coloured || alt ? Solver::xpbd
                            : base == "pbd"                  ? Solver::pbd
                                                             : Solver::bullet;
      const bool every_substep = alt ? base == "xpbd_rigid_substeps" : cs.rigid_substeps;
      CompareScene run_cs = cs;
      if (coloured) run_cs.spec.solver.coloured = true;
      if (solver == Solver::bullet && !bullet_ok) {
        r.status = "skipped";
        r.note = "btSoftBody cannot express the scene: " + why;
      } else {
        try {
          Captured c = run_captured(run_cs, solver, rs.budget, samples,
                                    every_substep && solver != Solver::bullet ? rs.budget.substeps : 1);
          if (solver == Solver::bullet && calibration && std::isfinite(calibration->second))
            c = calibrate_klst(cs, rs.budget, samples, calibration->first, calibration->second, std::move(c),
                               r.note);
          fill_run(r, cs, c);
          fill_errors(r, c.snaps, ref, samples, dt);
          // A rigid body on the other side of the cloth than in the
          // reference has failed, however small its error at some instant.
          if (r.status == "ok")
            if (const auto f = wrong_side_frame(c.snaps, ref, triangles, 0)) {
              r.status = "wrong_side";
              r.note += (r.note.empty() ? "" : "; ") + std::string("a dynamic body is on the other side of the cloth "
                                                                   "than in the reference at frame ") +
                        std::to_string(*f);
            }
          if (r.status == "ok")
            if (const auto f = lost_body_frame(c.snaps, ref)) {
              r.status = "lost_body";
              r.note += (r.note.empty() ? "" : "; ") +
                        std::string("a dynamic body is farther from its reference position than the cloth's size at "
                                    "frame ") +
                        std::to_string(*f);
            }
          if (!c.result.notes.empty()) {
            for (const auto& n : c.result.notes) r.note += (r.note.empty() ? "" : "; ") + n;
          }
        } catch (const std::exception& e) {
          r.status = "error";
          r.note = e.what();
        }
      }
      csv << to_csv(r) << '\n' << std::flush;
      std::cerr << "[" << ++count << "/" << todo.size() << "] " << r.key() << ": " << r.status;
      if (r.status == "ok" || r.status == "nonfinite" || r.status == "exploded" || r.status == "wrong_side" ||
          r.status == "lost_body")
        std::cerr << ", " << r.wall_ms_median << " ms/frame, error mean " << r.err_mean << " m, worst "
                  << r.err_worst << " m";
      std::cerr << " (" << elapsed() << " s)\n";
    }
  }
  std::cerr << "xpbd-compare: done in " << elapsed() << " s\n";
  return 0;
}

int cmd_merge(const std::vector<std::string>& inputs, const std::string& out) {
  std::vector<Row> rows;
  std::set<std::string> seen;
  for (const auto& in : inputs)
    for (const Row& r : read_csv(in))
      if (seen.insert(r.key()).second) rows.push_back(r);
  // In sweep order: by scene (compare_scenes order), then as the runs came.
  std::map<std::string, int> order;
  int k = 0;
  for (const auto& cs : compare_scenes(false)) order[cs.id] = k++;
  std::stable_sort(rows.begin(), rows.end(), [&](const Row& a, const Row& b) {
    const int oa = order.count(a.scene) ? order[a.scene] : k, ob = order.count(b.scene) ? order[b.scene] : k;
    return oa < ob;
  });
  const std::string tmp = out + ".tmp";
  {
    std::ofstream o(tmp);
    o << csv_header() << '\n';
    for (const Row& r : rows) o << to_csv(r) << '\n';
    if (!o) {
      std::cerr << tmp << ": write failed\n";
      return 1;
    }
  }
  std::filesystem::rename(tmp, out);
  std::cerr << "xpbd-compare merge: " << rows.size() << " runs -> " << out << "\n";
  return 0;
}

}  // namespace xpbd_compare

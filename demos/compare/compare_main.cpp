// xpbd-compare: the speed-vs-accuracy sweep of issue 6 (docs/results.md).
//
//   xpbd-compare run --out docs/results.csv [--quick] [--shard i/n] [--scenes a,b]
//   xpbd-compare merge a.csv b.csv ... -o out.csv
//   xpbd-compare report --csv docs/results.csv --docs docs --gp-dir DIR
//
// `run` appends one CSV row per run as soon as it finishes (flushed), skips
// runs already in the file (resume), and prints a progress line per run on
// stderr. `report` writes docs/results.md and one gnuplot script per scene
// (scripts/compare.sh renders them to docs/results_<scene>.png).
#include <CLI/CLI.hpp>

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
#include <tuple>
#include <vector>

#include "demos/compare/cheapest.hpp"
#include "demos/compare/compare.hpp"
#include "demos/compare/stability.hpp"
#include "demos/scene_runner.hpp"

namespace {

using namespace xpbd_compare;
using xpbd_demos::RunOptions;
using xpbd_demos::RunResult;
using xpbd_demos::Solver;

constexpr double kExplodedDrift = 0.1;  // energy_drift above which a finite run is "exploded"
constexpr const char* kScalar = sizeof(xpbd::Real) == sizeof(double) ? "double" : "float";

struct RunSpec {
  std::size_t scene = 0;  // index into the scene list
  std::string method;     // xpbd | pbd | bullet | reference
  Budget budget;
};

struct Captured {
  RunResult result;
  Snapshots snaps;
};

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
    if (v.frame == 0 || want.count(v.frame))
      c.snaps[v.frame] = std::vector<Vec3>(v.positions.begin(), v.positions.end());
  });
  return c;
}

// Errors of `run` against `ref` at the sample frames. A frame the run did
// not reach (non-finite) counts as an infinite error.
void fill_errors(Row& r, const Snapshots& run, const Snapshots& ref, const std::vector<int>& samples, double dt) {
  r.err_rms_worst = r.err_max_worst = 0;
  std::ostringstream s;
  for (int f : samples) {
    PositionError e{INFINITY, INFINITY};
    auto a = run.find(f);
    auto b = ref.find(f);
    if (a != run.end() && b != ref.end()) e = position_error(a->second, b->second);
    if (std::isnan(e.rms)) e = {INFINITY, INFINITY};
    if (s.tellp() > 0) s << ';';
    s.precision(4);
    s << double(f) * dt << ':' << e.rms << ':' << e.max;
    r.err_rms_worst = std::max(r.err_rms_worst, e.rms);
    r.err_max_worst = std::max(r.err_max_worst, e.max);
    if (f == samples.back()) {
      r.err_rms_final = e.rms;
      r.err_max_final = e.max;
    }
  }
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
      if (cs.chain) r.support_force = support_force_from_positions(last->second, *cs.chain);
      // The catenary's first link (at support a), by the same Hooke's law.
      if (cs.catenary && last->second.size() >= 2)
        r.support_force = ((last->second[1] - last->second[0]).template cast<double>().norm() -
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

// DESIGN.md section 5: "btSoftBody's kLST depends on the iteration count, so
// calibrate it by measured strain, not by formula." btSoftBody's links have
// no compliance: at kLST = 1 and a large budget they end stiffer than the
// scene's material (the chain's support force falls to 5 N of 190 at 100x1).
// Where the run at the scene's kLST ends with a mean edge strain (final
// frame) more than 2% below the reference's, kLST is lowered by bisection in
// log kLST over [1e-4, kLST] (12 runs) to the value whose final mean strain
// is closest to the reference's, and that run is the one reported; the note
// says so. A run that stretches more than the reference keeps kLST: kLST
// <= 1 cannot make it stiffer.
Captured calibrate_klst(const CompareScene& cs, Budget b, const std::vector<int>& samples, double target,
                        Captured first, std::string& note) {
  auto final_strain = [](const Captured& c) {
    return c.result.finite ? c.result.series.back().mean_strain : std::nan("");
  };
  const double k0 = double(cs.spec.solver.bullet_kLST);
  const double s0 = final_strain(first);
  if (!(s0 < target * 0.98)) return first;
  CompareScene trial = cs;
  double lo = std::log(1e-4), hi = std::log(k0);  // strain falls as kLST rises
  Captured best = std::move(first);
  double best_k = k0, best_gap = std::abs(s0 - target);
  for (int it = 0; it < 12; ++it) {
    const double mid = 0.5 * (lo + hi);
    trial.spec.solver.bullet_kLST = Real(std::exp(mid));
    Captured c = run_captured(trial, Solver::bullet, b, samples);
    const double st = final_strain(c);
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
  n << "kLST " << best_k << " (calibrated by strain: final mean strain " << final_strain(best)
    << ", reference " << target << "; at kLST " << k0 << " it was " << s0 << ")";
  note += (note.empty() ? "" : "; ") + n.str();
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

int cmd_run(const std::string& out, bool quick, const std::string& shard, const std::vector<std::string>& only,
            const std::vector<std::string>& methods, const std::string& ref_dir, const std::string& ref_budget) {
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
  const char* const kMethods[] = {"reference", "xpbd", "xpbd_coloured", "pbd", "bullet"};
  for (const auto& m : methods)
    if (std::find(std::begin(kMethods), std::end(kMethods), m) == std::end(kMethods)) {
      std::cerr << "--methods: unknown method \"" << m << "\" (reference, xpbd, xpbd_coloured, pbd, bullet)\n";
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
    for (const char* m : {"xpbd", "xpbd_coloured", "pbd", "bullet"})
      if (wanted(m))
        for (Budget b : budgets) all.push_back({s, m + suffix, b});
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

    // The reference positions at the sample frames.
    Snapshots ref;
    std::optional<double> ref_final_strain;
    std::optional<CatenaryEquilibrium> cat;
    if (cs.catenary) cat = catenary_equilibrium(*cs.catenary);
    if (cs.chain) {
      const auto eq = chain_equilibrium(*cs.chain);
      for (int f : samples) ref[f] = eq;
    } else if (cat) {
      for (int f : samples) ref[f] = cat->x;
    } else if (is_float || (have_reference(ref_dir, cs.id) &&
                            done.count(base_row(cs, "reference", reference_budgets(cs, quick, ref_override).first).key()))) {
      // The float build, or a resumed double sweep whose reference row is in
      // the CSV: the reference positions from the file the double run wrote.
      ReferenceData rd =
          read_reference(ref_dir, cs.id, xpbd_demos::expand(cs.spec.soft, cs.spec.base_dir).scene.positions.size());
      ref = std::move(rd.snaps);
      ref_final_strain = rd.final_mean_strain;
      std::cerr << "  " << cs.id << ": reference read from " << ref_dir << "\n";
    } else {
      const auto [ref_b, ref_2b] = reference_budgets(cs, quick, ref_override);
      const int rigid_b = cs.rigid_substeps ? ref_b.substeps : 1;
      const int rigid_2b = cs.rigid_substeps ? ref_2b.substeps : 1;
      std::cerr << "  " << cs.id << ": reference runs xpbd " << ref_b.substeps << "x" << ref_b.iterations
                << " and " << ref_2b.substeps << "x" << ref_2b.iterations
                << (cs.rigid_substeps ? " (rigid bodies stepped at every substep)" : "") << " ...\n";
      Captured b1 = run_captured(cs, Solver::xpbd, ref_b, samples, rigid_b);
      Captured b2 = run_captured(cs, Solver::xpbd, ref_2b, samples, rigid_2b);
      // The finer run is the reference; |B - 2B| estimates its own error
      // (under first-order convergence in h, e(B) = 2 e(2B), so
      // x(B) - x(2B) = e(2B)).
      ref = b2.snaps;
      if (b2.result.finite) ref_final_strain = b2.result.series.back().mean_strain;
      if (!ref_dir.empty()) write_reference(ref_dir, cs.id, {ref, ref_final_strain.value_or(std::nan(""))});
      if (std::any_of(mine.begin(), mine.end(), [](const RunSpec& r) { return r.method == "reference"; })) {
        Row r = base_row(cs, "reference", ref_b);
        fill_run(r, cs, b2);
        fill_errors(r, b1.snaps, b2.snaps, samples, dt);
        r.status = b1.result.finite && b2.result.finite ? "reference" : "nonfinite";
        std::ostringstream n;
        n << "reference = xpbd " << ref_2b.substeps << "x" << ref_2b.iterations
          << " (speed columns); err columns = its difference from xpbd " << ref_b.substeps << "x"
          << ref_b.iterations;
        if (cs.rigid_substeps) n << "; rigid bodies stepped at every substep in both";
        r.note = n.str();
        csv << to_csv(r) << '\n' << std::flush;
        std::cerr << "[" << ++count << "/" << todo.size() << "] " << cs.id << " reference: |B - 2B| rms "
                  << r.err_rms_final << " m, max " << r.err_max_final << " m at the final frame ("
                  << elapsed() << " s)\n";
      }
    }
    std::string why;
    const bool bullet_ok = xpbd_demos::bullet_can_express(cs.spec, &why);
    // The reference's mean edge strain at the final frame: btSoftBody's kLST
    // is calibrated to it (calibrate_klst). Closed forms: from their links;
    // a reference run: its own last frame (a float build has no reference
    // run, and runs no btSoftBody calibration).
    double ref_strain = std::nan("");
    if (cs.chain) {
      const auto eq = chain_equilibrium(*cs.chain);
      ref_strain = mean_link_strain(eq, double(cs.chain->spacing));
    } else if (cat) {
      ref_strain = mean_link_strain(cat->x, double(cs.catenary->spacing));
    } else if (ref_final_strain) {
      ref_strain = *ref_final_strain;
    }
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
      const bool coloured = base == "xpbd_coloured";
      const Solver solver = base == "xpbd" || coloured ? Solver::xpbd
                            : base == "pbd"            ? Solver::pbd
                                                       : Solver::bullet;
      CompareScene run_cs = cs;
      if (coloured) run_cs.spec.solver.coloured = true;
      if (solver == Solver::bullet && !bullet_ok) {
        r.status = "skipped";
        r.note = "btSoftBody cannot express the scene: " + why;
      } else {
        try {
          Captured c = run_captured(run_cs, solver, rs.budget, samples,
                                    cs.rigid_substeps && solver != Solver::bullet ? rs.budget.substeps : 1);
          if (solver == Solver::bullet && std::isfinite(ref_strain))
            c = calibrate_klst(cs, rs.budget, samples, ref_strain, std::move(c), r.note);
          fill_run(r, cs, c);
          fill_errors(r, c.snaps, ref, samples, dt);
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
      if (r.status == "ok" || r.status == "nonfinite" || r.status == "exploded")
        std::cerr << ", " << r.wall_ms_median << " ms/frame, error rms " << r.err_rms_final << " m";
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

// ---------------------------------------------------------------------------
// report

std::string fmt(double v, int prec = 3) {
  if (!std::isfinite(v)) return std::isnan(v) ? "n/a" : "inf";
  std::ostringstream o;
  o.precision(prec);
  o << v;
  return o.str();
}

std::string label(const Row& r) { return std::to_string(r.substeps) + "x" + std::to_string(r.iterations); }

// btSoftBody against XPBD on one scene's fronts: for every point of
// btSoftBody's front, XPBD's time at that error and XPBD's error at that
// time (log-log interpolation on XPBD's front), as a markdown table, and the
// ratios whose compared errors are at least twice the reference's
// resolution (NaN resolution: all count).
struct Ratios {
  std::vector<double> time, error;  // bullet/xpbd, resolved points only
  std::string table;
};
Ratios bullet_vs_xpbd(const std::vector<Point>& fx, const std::vector<Point>& fb, double resolution) {
  const double floor = std::isfinite(resolution) ? 2 * resolution : 0;
  Ratios q;
  std::ostringstream t;
  t << "| btSoftBody point | ms | error (m) | XPBD ms at that error | time ratio bullet/xpbd | XPBD error at "
       "that time (m) | error ratio bullet/xpbd |\n|---|---|---|---|---|---|---|\n";
  for (const Point& p : fb) {
    const auto tx = time_at_error(fx, p.err);
    const auto ex = error_at_time(fx, p.ms);
    const bool t_ok = tx && p.err >= floor;
    const bool e_ok = ex && *ex >= floor && p.err >= floor;
    if (t_ok) q.time.push_back(p.ms / *tx);
    if (e_ok) q.error.push_back(p.err / *ex);
    auto cell = [](bool have, bool ok, double v) {
      return have ? fmt(v) + (ok ? "" : " (unresolved)") : std::string("n/a");
    };
    t << "| " << p.label << " | " << fmt(p.ms) << " | " << fmt(p.err) << " | " << (tx ? fmt(*tx) : "n/a") << " | "
      << cell(bool(tx), t_ok, tx ? p.ms / *tx : 0) << " | " << (ex ? fmt(*ex) : "n/a") << " | "
      << cell(bool(ex), e_ok, ex ? p.err / *ex : 0) << " |\n";
  }
  q.table = t.str();
  return q;
}

std::string summary(std::vector<double> v) {
  if (v.empty()) return "n/a";
  std::sort(v.begin(), v.end());
  const double med = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  return "median " + fmt(med) + ", range " + fmt(v.front()) + " .. " + fmt(v.back());
}

int cmd_report(const std::string& csv_path, const std::string& docs, const std::string& gp_dir,
               const std::string& command, double sweep_seconds, double error_time) {
  // The charted error: RMS at error_time (s), or at the final frame if <= 0.
  // The chain's reference is its static closed form, which holds once the
  // chain has settled: it is always charted at the final frame.
  auto final_only = [](const std::string& scene) { return static_reference(scene); };
  auto chart_error = [&](const Row& r) {
    if (error_time <= 0 || final_only(r.scene)) return r.err_rms_final;
    const auto e = rms_error_at(r, error_time);
    return e ? *e : std::nan("");
  };
  auto err_name_of = [&](const std::string& scene) {
    return error_time > 0 && !final_only(scene) ? "RMS error at t = " + fmt(error_time) + " s"
                                                : std::string("RMS error at the final frame");
  };
  const std::string err_name = err_name_of("");
  const std::vector<Row> rows = read_csv(csv_path);
  std::vector<std::string> scene_order;
  for (const Row& r : rows)
    if (std::find(scene_order.begin(), scene_order.end(), r.scene) == scene_order.end())
      scene_order.push_back(r.scene);
  std::filesystem::create_directories(gp_dir);
  std::ostringstream md;
  md << "# Speed against accuracy: XPBD, PBD and btSoftBody\n\n"
     << "Generated by `xpbd-compare report` from `docs/results.csv` (every run, one row each). "
     << "Regenerate everything (build, sweep, CSV, charts, this page) with:\n\n"
     << "    " << command << "\n\n";
  if (sweep_seconds > 0) md << "The sweep took " << fmt(sweep_seconds, 4) << " s of wall clock on this machine.\n\n";
  md << "Where each method fails (time step, stiffness, mass ratio, impact speed): the stability map, "
        "[below](#where-each-method-fails-the-stability-map) and in [stability.md](stability.md).\n\n";
  md << "## How the runs are made\n\n"
     << "- Scenes (`demos/compare/compare.cpp`, `compare_scenes`): hanging cloth 32x32 and 64x64 (built-in "
        "`hanging_cloth`, the 64x64 one through `--set`-style overrides of nx, ny and the pinned corners), "
        "`cloth_on_sphere`, a vertical hanging chain (20 particles of 1 kg, 1 cm links of compliance 1e-6 m/N, "
        "g = 10 m/s^2, pinned at the top, velocity drag 10 1/s so that it settles), a catenary (21 particles "
        "of 0.1 kg, 5 cm links of compliance 1e-5 m/N between two supports 0.8 m apart, released 0.5 rad out "
        "of its plane, drag 10 1/s; demos/compare/catenary.hpp), `trampoline`, and a soft "
        "cube (0.2 m, 4x4x4 cells of 6 tetrahedra, 1 kg, bulk modulus 1 MPa, edges 1e-6 m/N) dropped from "
        "5 cm onto a ground plane. 120 frames of 1/60 s (2 s) each.\n"
     << "- Methods: `xpbd`, `pbd` and `bullet` (btSoftBody) through `xpbd_demos::run_scene` "
        "(and `xpbd_coloured`: XPBD with the Distance elements projected colour by colour, "
        "`StepConfig::coloured`, cheaper per projection but a different Gauss-Seidel order; "
        "docs/benchmarks.md) "
        "(docs/metrics.md): the same scene description, the fairness rules of DESIGN.md section 5. "
        "btSoftBody is skipped where `bullet_can_express` refuses the scene; the reason is in the CSV's "
        "`note` column. btSoftBody's links have a stiffness kLST, not a compliance, so (DESIGN.md section 5: "
        "calibrate kLST by measured strain) every btSoftBody run that ends with a mean edge strain more than "
        "2% below the reference's at the final frame (too stiff: at large budgets kLST = 1 converges to an "
        "inextensible chain) is rerun with kLST found by bisection (12 runs, log scale, 1e-4 .. 1) to match "
        "that strain, and the matched run is the one reported; its note gives the kLST. Runs that stretch "
        "more than the reference keep kLST = 1 (a kLST <= 1 cannot stiffen them).\n"
     << "- Budgets (substeps x iterations; btSoftBody: internal steps x piterations), projections per "
        "element and frame from 1 to 100: s x 1 for s in {1, 2, 5, 10, 20, 50, 100}; 1 x i for i in "
        "{2, 5, 10, 20, 50, 100}; and 2x5, 5x2, 5x5, 10x2, 10x5, 20x5.\n"
     << "- Speed: `wall_ms_median`, the median over frames of the stepping's wall clock, and "
        "`projections_per_frame`, measured in the same run. Single thread, on a 2-core VM that other jobs may "
        "share: the median over frames removes short interruptions but not a slower stretch of the whole "
        "run, so a single point can be off by up to ~2x (look for points that break a method's trend); "
        "rerun on a quiet machine for clean times.\n"
     << "- Accuracy: positions are compared with the reference every 0.25 s and at the final frame "
        "(2 s): `err_rms_*` is the RMS over particles of |x - x_ref|, `err_max_*` the maximum; `_final` at "
        "the final frame, `_worst` the worst sample time, `err_series` all of them (t:rms:max). The charts "
        "and fronts use the RMS error at t = " << fmt(error_time) << " s (`--error-time`): later, the "
        "swinging and falling cloths are too sensitive for any reference to resolve (see the convergence "
        "table). The chain and the catenary are charted at the final frame, where they have settled to the "
        "static state their closed forms describe. `max_strain`/`mean_strain` are the edge strain "
        "|len/rest - 1| (docs/metrics.md), `max_penetration` the contact violation (m), `energy_drift` = "
        "(E_end - E_0) / (M g L) with M the movable mass, g = |g| and L the diagonal of the particles' "
        "initial bounding box. A non-finite run counts as an infinite error and is left off the charts, and "
        "so is a finite run that gained more than 0.1 M g L of energy (status `exploded`: a passive scene "
        "cannot gain energy; the 64x64 cloth at 1x1 reaches strains of 1e12 after the charted time).\n"
     << "- The reference: for the chain, the closed-form static equilibrium (link k stretched by "
        "compliance x (n-1-k) m g; support force (n-1) m g = 190 N); for the catenary, the exact static "
        "equilibrium of the discrete elastic chain (horizontal tension H in every link, vertical tension "
        "V0 - k m g in link k, each link stretched by compliance x its tension; Newton on (H, V0) to a "
        "residual below 1e-12 of the length). Both are judged at the final frame, once the drag has "
        "settled them. Elsewhere a high-budget run, XPBD in "
        "double (2B in the convergence table below, 40x the sweep's largest budget in projections). "
        "Convergence check: the same at half the substeps (B); the `reference` row "
        "of each scene records the difference between the two in its error columns and the 2B run's speed. "
        "An error below that difference cannot be resolved and means \"as good as the reference\"; the "
        "charts draw it as a grey line. On the stiff cloths (every edge 1e-8 m/N) this difference is not "
        "monotone in the budget. 32x32 hanging cloth, |B - 2B| RMS at t = 0.5 s, measured while choosing "
        "the reference (`xpbd-compare run --methods reference --scenes hanging_cloth_32 --reference 2BxI`, "
        "on an earlier build of the same solver): 2B = 100x5: 1.2 cm; 200x1: 1.5 cm; 400x5: 2.0 cm; "
        "200x20: 0.6 cm; 1000x1: 5.5 cm; 2000x1: 1.9 cm; 2000x2: 1.5 cm; 4000x1: 0.73 cm (0.99 cm in this "
        "sweep, table below: a change of round-off alone moves it by millimetres, which is the same "
        "sensitivity). Only past ~2000 substeps per frame does it shrink steadily (the substep then starts "
        "to resolve the links' own vibration, period ~1e-5 s at 1e-8 m/N), so the sweep uses 2B = 4000x1; "
        "the falling, folding cloth stays sensitive to its discretisation at the centimetre level, and on "
        "the 64x64 cloth, whose particles are 4x lighter, 4000x1 is still inside that regime (4 cm).\n"
     << "- Rigid bodies: in the scenes with a dynamic body (cloth_on_sphere's box, the trampoline's ball) "
        "the XPBD and PBD runs and the reference step Bullet at every substep (`RunOptions::rigid_steps` = "
        "substeps), as btSoftBody steps it at every internal step: the same fixed time step for the rigid "
        "world (DESIGN.md section 5). With the bridge's default, one Bullet step per frame, the body's own "
        "integration error dominates: in an earlier sweep with one step per frame (before the sweep-parity "
        "fix of alternate_sweeps, which the trampoline uses), btSoftBody "
        "reached the trampoline's errors 13x faster than XPBD (btSoftBody time / XPBD time at equal error: "
        "median 0.076), while on cloth_on_sphere, with its light box, the ratio was 1.22; stepping Bullet "
        "per substep also costs XPBD the contact generation of every Bullet step (the ratios below).\n"
     << "- Float: the float build runs XPBD over the same budgets (`xpbd_float`, dashed) against the double "
        "reference, read from the files the double sweep writes (`--reference-dir`).\n"
     << "- For the chain, `support_force` is the tension the top link's stretch implies under the declared "
        "compliance, (|x1 - x0| - l) / alpha, at the final frame (N); 190 N is exact. For PBD and btSoftBody "
        "(whose link stiffness is not a compliance) it shows how far their stretch is from the elastic one.\n\n";

  md << "## Interrupting, resuming, sharding\n\n"
     << "`xpbd-compare run` appends one row per run to the CSV as soon as the run ends (flushed), so an "
        "interruption loses at most the run in flight; `RESUME=1 bash scripts/compare.sh` (or "
        "`xpbd-compare run --out docs/results.csv`) skips the runs already in the file (a scene's reference "
        "runs are redone when any of its runs is left). `xpbd-compare run --shard i/n --out part_i.csv` runs "
        "every n-th run of the sweep starting at i; `xpbd-compare merge part_*.csv -o docs/results.csv` "
        "assembles the parts, then `xpbd-compare report` and gnuplot (the end of scripts/compare.sh) draw "
        "them. A progress line per run goes to stderr.\n\n"
     << "CSV columns: scene, method (xpbd, pbd, bullet, reference), scalar, substeps, iterations, frames, "
        "frames_completed, status (ok, nonfinite, exploded (finite, but energy_drift > 0.1), skipped, error, "
        "reference), particles, "
        "projections_per_frame, wall_ms_median, wall_ms_mean (ms), err_rms_final, err_max_final, "
        "err_rms_worst, err_max_worst (m), err_series, max_strain, mean_strain, max_penetration (m), "
        "energy_drift, support_force (N, chain and catenary only), note (for btSoftBody: the calibrated kLST).\n\n";
  md << "## Reference convergence\n\n"
     << "B vs 2B: the reference (2B) against the same at half the substeps (B). Under first-order "
        "convergence in the time step this is the reference's own error, so errors below it are not "
        "resolved.\n\n"
     << "| scene | runs | B vs 2B, " << err_name << " (m) | RMS at the end (m) | max at the end (m) | "
        "t:RMS:max at every sample time (s:m:m) |\n|---|---|---|---|---|---|\n";
  for (const Row& r : rows)
    if (r.method == "reference") {
      if (static_reference(r.scene))
        md << "| " << r.scene << " | " << r.note << "; support force " << fmt(r.support_force, 6)
           << " N | exact | exact | exact | |\n";
      else
        md << "| " << r.scene << " | xpbd " << 2 * r.substeps << "x" << r.iterations << " vs " << label(r)
           << " (" << r.scalar << ") | " << fmt(r.err_series.empty() ? std::nan("") : chart_error(r)) << " | "
           << fmt(r.err_rms_final) << " | " << fmt(r.err_max_final) << " | " << r.err_series << " |\n";
    }
  md << "\n";

  // The methods, then their float-build runs where the CSV has them.
  std::vector<std::string> methods = {"xpbd", "pbd", "bullet", "xpbd_coloured"};
  for (const char* m : {"xpbd_float", "xpbd_coloured_float", "pbd_float", "bullet_float"})
    if (std::any_of(rows.begin(), rows.end(), [&](const Row& r) { return r.method == m; })) methods.push_back(m);
  std::vector<std::tuple<std::string, std::string, Ratios>> ratio_rows;  // scene, XPBD variant, ratios
  for (const std::string& scene : scene_order) {
    std::map<std::string, std::vector<Point>> pts;
    std::vector<std::string> skipped;
    int nonfinite = 0;
    for (const Row& r : rows) {
      if (r.scene != scene || r.method == "reference") continue;
      if (r.status == "ok") pts[r.method].push_back({r.wall_ms_median, chart_error(r), label(r)});
      else if (r.status == "nonfinite" || r.status == "exploded") ++nonfinite;
      else if (r.status == "skipped" && skipped.empty()) skipped.push_back(r.method + ": " + r.note);
      else if (r.status == "error") skipped.push_back(r.method + " " + label(r) + ": " + r.note);
    }
    // gnuplot script with the data inline.
    const std::string png = docs + "/results_" + scene + ".png";
    std::ofstream gp(gp_dir + "/results_" + scene + ".gp");
    gp << "set terminal pngcairo size 900,600 noenhanced\nset output '" << png << "'\n"
       << "set logscale xy\nset grid\nset key top right\n"
       << "set xlabel 'wall time per frame (ms)'\nset ylabel 'position " << err_name_of(scene) << " (m)'\n"
       << "set format xy '%g'\n"
       << "set yrange [:10]\n"
       << "set title '" << scene << ": error against time (line: Pareto front, dots: every run)'\n";
    // The reference's own resolution (its |B - 2B| at the charted time): a
    // grey line; errors below it are not resolved.
    double resolution = std::nan("");
    for (const Row& r : rows)
      if (r.scene == scene && r.method == "reference" && !r.err_series.empty()) resolution = chart_error(r);
    if (std::isfinite(resolution) && resolution > 0)
      gp << "set arrow from graph 0, first " << resolution << " to graph 1, first " << resolution
         << " nohead dt 3 lw 2 lc rgb '#808080'\n"
         << "set label 'reference resolution |B - 2B|' at graph 0.02, first " << resolution * 1.15
         << " tc rgb '#606060'\n";
    std::vector<std::string> plots;
    const char* colour[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#98df8a"};
    for (std::size_t m = 0; m < methods.size() && m < std::size(colour); ++m) {
      auto it = pts.find(methods[m]);
      if (it == pts.end() || it->second.empty()) continue;
      gp << "$all_" << methods[m] << " << EOD\n";
      for (const Point& p : it->second) gp << p.ms << ' ' << p.err << '\n';
      gp << "EOD\n$front_" << methods[m] << " << EOD\n";
      for (const Point& p : pareto_front(it->second)) gp << p.ms << ' ' << p.err << '\n';
      gp << "EOD\n";
      // Float runs dashed, in a lighter shade of their method's colour.
      const bool fl = methods[m].ends_with("_float");
      plots.push_back("$all_" + methods[m] + " with points pt " + (fl ? "6" : "7") + " ps 0.6 lc rgb '" +
                      colour[m] + "' notitle");
      plots.push_back("$front_" + methods[m] + " with linespoints pt " + (fl ? "6" : "7") + " ps 1 lw 2 " +
                      (fl ? "dt 2 " : "") + "lc rgb '" + colour[m] + "' title '" + methods[m] + "'");
    }
    if (!plots.empty()) {
      gp << "plot ";
      for (std::size_t i = 0; i < plots.size(); ++i) gp << (i ? ", \\\n     " : "") << plots[i];
      gp << "\n";
    }
    md << "## " << scene << "\n\n![" << scene << "](results_" << scene << ".png)\n\n";
    md << "Pareto fronts (budget: ms per frame, " << err_name_of(scene) << " in m):\n\n| method | front |\n|---|---|\n";
    for (const std::string& m : methods) {
      auto it = pts.find(m);
      md << "| " << m << " | ";
      if (it == pts.end() || it->second.empty()) {
        const bool any = std::any_of(rows.begin(), rows.end(), [&](const Row& r) {
          return r.scene == scene && r.method == m && (r.status == "ok" || r.status == "nonfinite" || r.status == "exploded");
        });
        md << (any ? "no finite run |\n" : "not run (see below) |\n");
        continue;
      }
      bool first = true;
      for (const Point& p : pareto_front(it->second)) {
        md << (first ? "" : "; ") << p.label << ": " << fmt(p.ms) << " ms, " << fmt(p.err);
        first = false;
      }
      md << " |\n";
    }
    md << "\n";
    // The other measures of the front's runs (the CSV has them for every run).
    md << "The front's runs, every measure (strain: edge |len/rest - 1|, max over the run and mean; "
          "penetration: the largest contact violation, m; energy drift: (E_end - E_0) / (M g L)):\n\n"
          "| method | budget | ms/frame | projections/frame | RMS error (m) | max error (m) | max strain | "
          "mean strain | max penetration (m) | energy drift |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const std::string& m : methods) {
      auto it = pts.find(m);
      if (it == pts.end()) continue;
      for (const Point& p : pareto_front(it->second))
        for (const Row& r : rows)
          if (r.scene == scene && r.method == m && r.status == "ok" && label(r) == p.label) {
            const bool at_t = error_time > 0 && !final_only(scene);
            double max_err = r.err_max_final;
            if (at_t) {
              // The series entry at error_time: "t:rms:max".
              max_err = std::nan("");
              std::istringstream in(r.err_series);
              std::string item;
              while (std::getline(in, item, ';')) {
                double t = 0, rms = 0, mx = 0;
                if (std::sscanf(item.c_str(), "%lf:%lf:%lf", &t, &rms, &mx) == 3 && std::abs(t - error_time) < 1e-6)
                  max_err = mx;
              }
            }
            md << "| " << m << " | " << p.label << " | " << fmt(r.wall_ms_median) << " | " << r.projections_per_frame
               << " | " << fmt(p.err) << " | " << fmt(max_err) << " | " << fmt(r.max_strain) << " | "
               << fmt(r.mean_strain) << " | " << fmt(r.max_penetration) << " | " << fmt(r.energy_drift) << " |\n";
          }
    }
    md << "\n";
    if (nonfinite)
      md << nonfinite << " run(s) went non-finite (NaN/Inf) or exploded (energy gain above 0.1 M g L) and are "
         << "left off; see the CSV's status column.\n\n";
    for (const auto& s : skipped) md << "- " << s << "\n";
    if (!skipped.empty()) md << "\n";

    if (static_reference(scene)) {
      double exact = std::nan("");
      for (const Row& r : rows)
        if (r.scene == scene && r.method == "reference") exact = r.support_force;
      md << "Support force at the final frame from the " << (scene == "catenary" ? "first" : "top")
         << " link's stretch, (|x1 - x0| - l) / alpha (exact: " << fmt(exact, 6)
         << " N). PBD and btSoftBody do not use the compliance, so theirs shows how far their "
            "link's stretch is from the elastic one (btSoftBody's kLST is calibrated to the mean strain, "
            "not to this link's):\n\n| method | budget: force (N) |\n|---|---|\n";
      for (const std::string& m : methods) {
        md << "| " << m << " | ";
        bool first = true;
        for (const Row& r : rows)
          if (r.scene == scene && r.method == m && r.status == "ok") {
            md << (first ? "" : "; ") << label(r) << ": " << fmt(r.support_force, 4);
            first = false;
          }
        md << " |\n";
      }
      md << "\n";
    }
    for (const char* variant : {"xpbd", "xpbd_coloured"}) {
      if (!pts.count(variant) || !pts.count("bullet")) continue;
      const Ratios q = bullet_vs_xpbd(pareto_front(pts[variant]), pareto_front(pts["bullet"]), resolution);
      ratio_rows.push_back({scene, variant, q});
      if (scene == "hanging_cloth_64") {
        md << "### btSoftBody against " << variant << " on the 64x64 hanging cloth\n\n"
           << "Both read off the fronts above (the same run): for every point of btSoftBody's front, "
           << variant << "'s time at btSoftBody's error and its error at btSoftBody's time, interpolated "
              "linearly in log-log between neighbouring points of its front (beyond its slowest point its best "
              "error; an error its front does not reach, or a time below its fastest point, is n/a). A "
              "ratio counts in the summary only where the errors it compares are at least twice the "
              "reference's resolution (" << fmt(resolution) << " m, the grey line): below that the "
              "reference cannot tell the runs apart.\n\n"
           << q.table << "\nOver btSoftBody's front, resolved points only: time ratio at equal error "
           << summary(q.time) << "; error ratio at equal time " << summary(q.error) << ".\n\n";
      }
    }
  }
  md << "## btSoftBody against XPBD, every scene\n\n"
        "The same ratios as for the 64x64 hanging cloth above, over btSoftBody's front on each scene "
        "(resolved points only: errors at least twice the reference's resolution; the chain's and the catenary's references are "
        "exact). Above 1: XPBD is faster at equal error, or more accurate at equal time.\n\n"
        "| scene | XPBD variant | btSoftBody time / XPBD time at equal error | btSoftBody error / XPBD error "
        "at equal time | resolved points (time, error) |\n|---|---|---|---|---|\n";
  for (const auto& [scene, variant, q] : ratio_rows)
    md << "| " << scene << " | " << variant << " | " << summary(q.time) << " | " << summary(q.error) << " | "
       << q.time.size() << ", " << q.error.size() << " |\n";
  md << "\n";
  // The stability map's findings, copied from docs/stability.md (one source
  // for the words), with its heat maps.
  {
    md << "## Where each method fails: the stability map\n\n"
       << "From [stability.md](stability.md) (`bash scripts/stability.sh`), which states the sweeps, the "
          "classification thresholds and the limits of the map.\n\n"
       << "![XPBD](stability_xpbd.png)\n\n![PBD](stability_pbd.png)\n\n![btSoftBody](stability_bullet.png)\n\n";
    std::ifstream in(docs + "/stability.md");
    std::string line;
    bool inside = false, found = false;
    while (std::getline(in, line)) {
      if (line.rfind("## ", 0) == 0) {
        if (inside) break;
        if (line.rfind("## Where each method fails", 0) == 0) {
          inside = found = true;
          continue;
        }
      }
      if (inside) md << (line.rfind("### ", 0) == 0 ? "#" + line : line) << "\n";
    }
    if (!found)
      md << "(" << docs << "/stability.md has no section \"## Where each method fails\": run "
         << "`bash scripts/stability.sh` first.)\n";
    md << "\n";
  }
  // The cheapest setting meeting an error target (cheapest.hpp), for a
  // loose and a tight target per scene: 5x and 1.5x the best error any
  // method reached, so that the targets are reachable and the answer shows
  // what each method pays for it.
  md << "## Cheapest setting for an error target\n\n"
     << "`xpbd-compare cheapest --csv docs/results.csv --scene NAME --target METRES` picks, per method, the "
        "fastest run of the sweep whose error (the charted one) meets the target. With a base name "
        "(`hanging_cloth`) it also chooses the resolution (32x32 or 64x64); each resolution is judged "
        "against its own reference, so that answer is about convergence in time, not in space. Below: "
        "targets of 5x and 1.5x the best error any method reached on the scene.\n\n"
     << "| scene | target (m) | method | cheapest setting | ms/frame | projections/frame | error (m) |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (const std::string& scene : scene_order) {
    double best = std::numeric_limits<double>::infinity();
    for (const Row& r : rows)
      if (r.scene == scene && r.status == "ok") best = std::min(best, chart_error(r));
    if (!std::isfinite(best) || best <= 0) continue;
    for (double factor : {5.0, 1.5}) {
      const double target = factor * best;
      for (const Cheapest& c : cheapest(rows, scene, target, final_only(scene) ? 0 : error_time)) {
        md << "| " << scene << " | " << fmt(target) << " | " << c.method << " | ";
        if (c.row)
          md << c.row->substeps << " x " << c.row->iterations << " | " << fmt(c.row->wall_ms_median) << " | "
             << c.row->projections_per_frame << " | " << fmt(c.error) << " |\n";
        else
          md << "not reached | | | |\n";
      }
    }
  }
  md << "\n";
  const std::string md_path = docs + "/results.md";
  std::ofstream o(md_path + ".tmp");
  o << md.str();
  o.close();
  std::filesystem::rename(md_path + ".tmp", md_path);
  std::cerr << "xpbd-compare report: " << md_path << ", " << scene_order.size() << " gnuplot scripts in " << gp_dir
            << "\n";
  return 0;
}

// xpbd-compare cheapest: the cheapest setting per method meeting an error
// target (cheapest.hpp).
int cmd_cheapest(const std::string& csv_path, const std::string& scene, double target, double error_time) {
  const std::vector<Row> rows = read_csv(csv_path);
  const std::vector<Cheapest> best = cheapest(rows, scene, target, error_time);
  if (best.empty()) {
    std::cerr << "xpbd-compare cheapest: no runs of scene '" << scene << "' in " << csv_path << "\n";
    return 2;
  }
  std::cout << "scene " << scene << ", error target " << target << " m ("
            << (error_time > 0 && !static_reference(scene) ? "RMS position error at t = " + fmt(error_time) + " s"
                                                           : std::string("RMS position error at the final frame"))
            << "), from " << csv_path << ":\n";
  for (const Cheapest& c : best) {
    if (!c.row) {
      std::cout << "  " << c.method << ": no setting in the sweep meets the target\n";
      continue;
    }
    const Row& r = *c.row;
    std::cout << "  " << c.method << ": " << r.scene << " at " << r.substeps << " x " << r.iterations << ", "
              << r.wall_ms_median << " ms/frame, " << r.projections_per_frame << " projections/frame, error "
              << c.error << " m\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"xpbd-compare: XPBD, PBD and btSoftBody, speed against accuracy (docs/results.md)"};
  app.require_subcommand(1);
  std::string out = "docs/results.csv", shard;
  bool quick = false;
  std::vector<std::string> only;
  auto* run = app.add_subcommand("run", "run the sweep, appending to the CSV (resumes)");
  run->add_option("--out", out, "CSV file to append to");
  run->add_flag("--quick", quick, "a tiny sweep (3 budgets, 30 frames, a small reference)");
  run->add_option("--shard", shard, "i/n: run every n-th run of the sweep starting at i");
  run->add_option("--scenes", only, "only these scenes")->delimiter(',');
  std::vector<std::string> methods;
  run->add_option("--methods", methods, "only these methods (reference, xpbd, xpbd_coloured, pbd, bullet)")->delimiter(',');
  std::string ref_dir, ref_budget;
  run->add_option("--reference", ref_budget,
                  "SxI: the reference budget 2B for every scene instead of the scene's own (for convergence "
                  "studies; the check runs S/2 x I)");
  run->add_option("--reference-dir", ref_dir,
                  "double build: also write each scene's reference positions here; float build: read them "
                  "from here (required)");
  std::vector<std::string> inputs;
  std::string merged;
  auto* merge = app.add_subcommand("merge", "merge shard CSVs (first occurrence of a run wins)");
  merge->add_option("inputs", inputs, "CSV files")->required()->check(CLI::ExistingFile);
  merge->add_option("-o,--out", merged, "output CSV")->required();
  std::string csv = "docs/results.csv", docs = "docs", gp_dir = "build/compare", command = "bash scripts/compare.sh";
  double sweep_seconds = 0;
  auto* report = app.add_subcommand("report", "write docs/results.md and the gnuplot scripts");
  report->add_option("--csv", csv, "CSV of the sweep")->check(CLI::ExistingFile);
  report->add_option("--docs", docs, "directory of results.md and the PNGs");
  report->add_option("--gp-dir", gp_dir, "where the gnuplot scripts go");
  report->add_option("--command", command, "the regenerating command, for results.md");
  report->add_option("--sweep-seconds", sweep_seconds, "wall clock of the sweep, for results.md");
  double error_time = 0.5;
  report->add_option("--error-time", error_time,
                     "time (s) of the charted error (a sample time: a multiple of 0.25 up to 2); <= 0: the final frame");
  std::string cheap_scene;
  double target = 0;
  auto* cheap = app.add_subcommand("cheapest", "the cheapest setting per method that meets an error target");
  cheap->add_option("--csv", csv, "CSV of the sweep")->check(CLI::ExistingFile);
  cheap->add_option("--scene", cheap_scene,
                    "scene name, or its base name to include every resolution (hanging_cloth)")
      ->required();
  cheap->add_option("--target", target, "error target (m)")->required()->check(CLI::PositiveNumber);
  cheap->add_option("--error-time", error_time, "time (s) of the judged error; <= 0: the final frame");
  // --- stability map (demos/compare/stability.hpp, docs/stability.md) ---
  auto* stab = app.add_subcommand("stability", "the stability map: run the sweep or draw it");
  stab->require_subcommand(1);
  std::string stab_csv = "docs/stability.csv", stab_shard, stab_docs = "docs", stab_gp = "build/stability";
  bool stab_quick = false;
  auto* stab_run = stab->add_subcommand("run", "run the stability sweep, appending to the CSV (resumes)");
  stab_run->add_option("--out", stab_csv, "CSV file to append to");
  stab_run->add_flag("--quick", stab_quick, "a 2x2 corner of every sweep");
  stab_run->add_option("--shard", stab_shard, "i/n: run every n-th run of the sweep starting at i");
  std::vector<std::string> stab_sweeps;
  stab_run
      ->add_option("--sweeps", stab_sweeps,
                   "only these sweeps (dt_stiffness,impact,mass_ratio,chain_box,trampoline)")
      ->delimiter(',');
  std::vector<std::string> stab_inputs;
  std::string stab_merged;
  auto* stab_merge = stab->add_subcommand(
      "merge", "merge stability CSVs (shards): one header, sweep order, a run kept once (copies must agree)");
  stab_merge->add_option("inputs", stab_inputs, "CSV files")->required()->check(CLI::ExistingFile);
  stab_merge->add_option("-o,--out", stab_merged, "output CSV")->required();
  auto* stab_report = stab->add_subcommand("report", "write the gnuplot scripts and docs/stability_grids.md");
  stab_report->add_option("--csv", stab_csv, "CSV of the sweep")->check(CLI::ExistingFile);
  stab_report->add_option("--docs", stab_docs, "directory of the PNGs and stability_grids.md");
  stab_report->add_option("--gp-dir", stab_gp, "where the gnuplot scripts go");
  // --- end stability map ---
  CLI11_PARSE(app, argc, argv);
  try {
    if (*stab_run) return xpbd_stability::cmd_run(stab_csv, stab_quick, stab_shard, stab_sweeps);
    if (*stab_report) return xpbd_stability::cmd_report(stab_csv, stab_docs, stab_gp);
    if (*stab_merge) return xpbd_stability::cmd_merge(stab_inputs, stab_merged);
    if (*cheap) return cmd_cheapest(csv, cheap_scene, target, error_time);
    if (*run) return cmd_run(out, quick, shard, only, methods, ref_dir, ref_budget);
    if (*merge) return cmd_merge(inputs, merged);
    return cmd_report(csv, docs, gp_dir, command, sweep_seconds, error_time);
  } catch (const std::exception& e) {
    std::cerr << "xpbd-compare: " << e.what() << "\n";
    return 1;
  }
}

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
#include <set>
#include <sstream>
#include <string>
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

Captured run_captured(const CompareScene& cs, Solver solver, Budget b, const std::vector<int>& samples) {
  RunOptions o = xpbd_demos::run_options(cs.spec);
  o.solver = solver;
  o.substeps = b.substeps;
  o.iterations = b.iterations;
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
  if (cs.chain && !c.snaps.empty()) {
    auto last = c.snaps.rbegin();
    if (last->first == cs.spec.solver.frames) r.support_force = support_force_from_positions(last->second, *cs.chain);
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

int cmd_run(const std::string& out, bool quick, const std::string& shard, const std::vector<std::string>& only) {
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
  const std::vector<Budget> budgets = sweep_budgets(quick);
  // The converged reference: XPBD at B and at 2B substeps (same iterations).
  const Budget ref_b = quick ? Budget{10, 2} : Budget{200, 5};
  const Budget ref_2b{2 * ref_b.substeps, ref_b.iterations};

  // The whole run list (the same in every shard), then this shard's part.
  std::vector<RunSpec> all;
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    if (!only.empty() && std::find(only.begin(), only.end(), scenes[s].id) == only.end()) continue;
    all.push_back({s, "reference", scenes[s].chain ? Budget{0, 0} : ref_b});
    for (const char* m : {"xpbd", "pbd", "bullet"})
      for (Budget b : budgets) all.push_back({s, m, b});
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
    if (cs.chain) {
      const auto eq = chain_equilibrium(*cs.chain);
      for (int f : samples) ref[f] = eq;
    } else {
      std::cerr << "  " << cs.id << ": reference runs xpbd " << ref_b.substeps << "x" << ref_b.iterations
                << " and " << ref_2b.substeps << "x" << ref_2b.iterations << " ...\n";
      Captured b1 = run_captured(cs, Solver::xpbd, ref_b, samples);
      Captured b2 = run_captured(cs, Solver::xpbd, ref_2b, samples);
      // The finer run is the reference; |B - 2B| estimates its own error
      // (under first-order convergence in h, e(B) = 2 e(2B), so
      // x(B) - x(2B) = e(2B)).
      ref = b2.snaps;
      if (std::any_of(mine.begin(), mine.end(), [](const RunSpec& r) { return r.method == "reference"; })) {
        Row r = base_row(cs, "reference", ref_b);
        fill_run(r, cs, b2);
        fill_errors(r, b1.snaps, b2.snaps, samples, dt);
        r.status = b1.result.finite && b2.result.finite ? "reference" : "nonfinite";
        std::ostringstream n;
        n << "reference = xpbd " << ref_2b.substeps << "x" << ref_2b.iterations
          << " (speed columns); err columns = its difference from xpbd " << ref_b.substeps << "x"
          << ref_b.iterations;
        r.note = n.str();
        csv << to_csv(r) << '\n' << std::flush;
        std::cerr << "[" << ++count << "/" << todo.size() << "] " << cs.id << " reference: |B - 2B| rms "
                  << r.err_rms_final << " m, max " << r.err_max_final << " m at the final frame ("
                  << elapsed() << " s)\n";
      }
    }
    std::string why;
    const bool bullet_ok = xpbd_demos::bullet_can_express(cs.spec, &why);
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
        }
        continue;
      }
      Row r = base_row(cs, rs.method, rs.budget);
      const Solver solver = rs.method == "xpbd" ? Solver::xpbd : rs.method == "pbd" ? Solver::pbd : Solver::bullet;
      if (solver == Solver::bullet && !bullet_ok) {
        r.status = "skipped";
        r.note = "btSoftBody cannot express the scene: " + why;
      } else {
        try {
          const Captured c = run_captured(cs, solver, rs.budget, samples);
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
      if (r.status == "ok" || r.status == "nonfinite")
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

int cmd_report(const std::string& csv_path, const std::string& docs, const std::string& gp_dir,
               const std::string& command, double sweep_seconds, double error_time) {
  // The charted error: RMS at error_time (s), or at the final frame if <= 0.
  // The chain's reference is its static closed form, which holds once the
  // chain has settled: it is always charted at the final frame.
  auto final_only = [](const std::string& scene) { return scene == "hanging_chain"; };
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
        "[stability.md](stability.md).\n\n";
  md << "## How the runs are made\n\n"
     << "- Scenes (`demos/compare/compare.cpp`, `compare_scenes`): hanging cloth 32x32 and 64x64 (built-in "
        "`hanging_cloth`, the 64x64 one through `--set`-style overrides of nx, ny and the pinned corners), "
        "`cloth_on_sphere`, a vertical hanging chain (20 particles of 1 kg, 1 cm links of compliance 1e-6 m/N, "
        "g = 10 m/s^2, pinned at the top, velocity drag 10 1/s so that it settles), `trampoline`, and a soft "
        "cube (0.2 m, 4x4x4 cells of 6 tetrahedra, 1 kg, bulk modulus 1 MPa, edges 1e-6 m/N) dropped from "
        "5 cm onto a ground plane. 120 frames of 1/60 s (2 s) each.\n"
     << "- Methods: `xpbd`, `pbd` and `bullet` (btSoftBody) through `xpbd_demos::run_scene` "
        "(docs/metrics.md): the same scene description, the fairness rules of DESIGN.md section 5. "
        "btSoftBody is skipped where `bullet_can_express` refuses the scene; the reason is in the CSV's "
        "`note` column.\n"
     << "- Budgets (substeps x iterations; btSoftBody: internal steps x piterations), projections per "
        "element and frame from 1 to 100: s x 1 for s in {1, 2, 5, 10, 20, 50, 100}; 1 x i for i in "
        "{2, 5, 10, 20, 50, 100}; and 2x5, 5x2, 5x5, 10x2, 10x5, 20x5.\n"
     << "- Speed: `wall_ms_median`, the median over frames of the stepping's wall clock, and "
        "`projections_per_frame`, measured in the same run. Single thread, on a 2-core VM that other jobs may "
        "share: the median over frames removes short interruptions but not a slower stretch of the whole "
        "run, so a single point can be off by up to ~2x (look for points that break a method's trend); "
        "rerun on a quiet machine for clean times.\n"
     << "- Accuracy: positions are compared with the reference at t = 0.5, 1, 1.5 s and the final frame "
        "(2 s): `err_rms_*` is the RMS over particles of |x - x_ref|, `err_max_*` the maximum; `_final` at "
        "the final frame (the charts' error), `_worst` the worst sample time, `err_series` all of them "
        "(t:rms:max). The charts and fronts use the RMS error at t = 0.5 s (`--error-time`): at the end (2 s) the "
        "swinging and falling cloths are too sensitive for the reference to resolve (see the convergence table: "
        "|B - 2B| at 2 s exceeds most runs' errors), while at 0.5 s it resolves centimetres. The chain is charted at the final frame, where it has settled "
        "to the static state its closed form describes. `max_strain`/`mean_strain` are the edge strain |len/rest - 1| (docs/metrics.md), "
        "`max_penetration` the contact violation (m), `energy_drift` = (E_end - E_0) / (M g L) with M the "
        "movable mass, g = |g| and L the diagonal of the particles' initial bounding box. A non-finite run "
        "counts as an infinite error and is left off the charts.\n"
     << "- The reference: for the chain, the closed-form static equilibrium (link k stretched by "
        "compliance x (n-1-k) m g; support force (n-1) m g = 190 N). Elsewhere a high-budget run: XPBD in "
        "double at 400 substeps x 5 iterations (2000 projections per element and frame, 20x the sweep's "
        "largest budget). Convergence check: the same at 200 x 5; the `reference` row of each scene records "
        "the difference between the two in its error columns (below) and the 400x5 run's speed. An error below that difference "
        "cannot be resolved and means \"as good as the reference\".\n"
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
        "frames_completed, status (ok, nonfinite, skipped, error, reference), particles, "
        "projections_per_frame, wall_ms_median, wall_ms_mean (ms), err_rms_final, err_max_final, "
        "err_rms_worst, err_max_worst (m), err_series, max_strain, mean_strain, max_penetration (m), "
        "energy_drift, support_force (N, chain only), note.\n\n";
  md << "## Reference convergence\n\n"
     << "B vs 2B: the reference (2B) against the same at half the substeps (B). Under first-order "
        "convergence in the time step this is the reference's own error, so errors below it are not "
        "resolved.\n\n"
     << "| scene | runs | B vs 2B, " << err_name << " (m) | RMS at the end (m) | max at the end (m) | "
        "t:RMS:max at every sample time (s:m:m) |\n|---|---|---|---|---|---|\n";
  for (const Row& r : rows)
    if (r.method == "reference") {
      if (r.scene == "hanging_chain")
        md << "| " << r.scene << " | closed form, support force " << fmt(r.support_force, 6)
           << " N | exact | exact | exact | |\n";
      else
        md << "| " << r.scene << " | xpbd " << 2 * r.substeps << "x" << r.iterations << " vs " << label(r)
           << " (" << r.scalar << ") | " << fmt(r.err_series.empty() ? std::nan("") : chart_error(r)) << " | "
           << fmt(r.err_rms_final) << " | " << fmt(r.err_max_final) << " | " << r.err_series << " |\n";
    }
  md << "\n";

  const char* methods[] = {"xpbd", "pbd", "bullet"};
  for (const std::string& scene : scene_order) {
    std::map<std::string, std::vector<Point>> pts;
    std::vector<std::string> skipped;
    int nonfinite = 0;
    for (const Row& r : rows) {
      if (r.scene != scene || r.method == "reference") continue;
      if (r.status == "ok") pts[r.method].push_back({r.wall_ms_median, chart_error(r), label(r)});
      else if (r.status == "nonfinite") ++nonfinite;
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
    std::vector<std::string> plots;
    const char* colour[] = {"#1f77b4", "#d62728", "#2ca02c"};
    for (int m = 0; m < 3; ++m) {
      auto it = pts.find(methods[m]);
      if (it == pts.end() || it->second.empty()) continue;
      gp << "$all_" << methods[m] << " << EOD\n";
      for (const Point& p : it->second) gp << p.ms << ' ' << p.err << '\n';
      gp << "EOD\n$front_" << methods[m] << " << EOD\n";
      for (const Point& p : pareto_front(it->second)) gp << p.ms << ' ' << p.err << '\n';
      gp << "EOD\n";
      plots.push_back("$all_" + std::string(methods[m]) + " with points pt 7 ps 0.6 lc rgb '" + colour[m] +
                      "' notitle");
      plots.push_back("$front_" + std::string(methods[m]) + " with linespoints pt 7 ps 1 lw 2 lc rgb '" +
                      colour[m] + "' title '" + methods[m] + "'");
    }
    if (!plots.empty()) {
      gp << "plot ";
      for (std::size_t i = 0; i < plots.size(); ++i) gp << (i ? ", \\\n     " : "") << plots[i];
      gp << "\n";
    }
    md << "## " << scene << "\n\n![" << scene << "](results_" << scene << ".png)\n\n";
    md << "Pareto fronts (budget: ms per frame, " << err_name_of(scene) << " in m):\n\n| method | front |\n|---|---|\n";
    for (const char* m : methods) {
      auto it = pts.find(m);
      md << "| " << m << " | ";
      if (it == pts.end() || it->second.empty()) {
        const bool any = std::any_of(rows.begin(), rows.end(), [&](const Row& r) {
          return r.scene == scene && r.method == m && (r.status == "ok" || r.status == "nonfinite");
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
    if (nonfinite) md << nonfinite << " run(s) went non-finite (NaN/Inf); see the CSV.\n\n";
    for (const auto& s : skipped) md << "- " << s << "\n";
    if (!skipped.empty()) md << "\n";

    if (scene == "hanging_chain") {
      md << "Support force at the final frame from the top link's stretch, (|x1 - x0| - l) / alpha "
            "(exact: 190 N). PBD and btSoftBody do not use the compliance, so theirs shows how far their "
            "top link's stretch is from the elastic one:\n\n| method | budget: force (N) |\n|---|---|\n";
      for (const char* m : methods) {
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
    if (scene == "hanging_cloth_64" && pts.count("xpbd") && pts.count("bullet")) {
      const auto fx = pareto_front(pts["xpbd"]);
      const auto fb = pareto_front(pts["bullet"]);
      md << "### btSoftBody against XPBD on the 64x64 hanging cloth\n\n"
         << "Both read off the fronts above (the same run): for every point of btSoftBody's front, "
            "XPBD's time at btSoftBody's error and XPBD's error at btSoftBody's time, interpolated linearly "
            "in log-log between neighbouring points of XPBD's front (beyond XPBD's slowest point its best "
            "error; an error XPBD's front does not reach, or a time below its fastest point, is n/a).\n\n"
         << "| btSoftBody point | ms | error (m) | XPBD ms at that error | time ratio bullet/xpbd | XPBD error at that time (m) | error ratio bullet/xpbd |\n|---|---|---|---|---|---|---|\n";
      std::vector<double> time_ratios, error_ratios;
      for (const Point& p : fb) {
        const auto tx = time_at_error(fx, p.err);
        const auto ex = error_at_time(fx, p.ms);
        if (tx) time_ratios.push_back(p.ms / *tx);
        if (ex) error_ratios.push_back(p.err / *ex);
        md << "| " << p.label << " | " << fmt(p.ms) << " | " << fmt(p.err) << " | " << (tx ? fmt(*tx) : "n/a")
           << " | " << (tx ? fmt(p.ms / *tx) : "n/a") << " | " << (ex ? fmt(*ex) : "n/a") << " | "
           << (ex ? fmt(p.err / *ex) : "n/a") << " |\n";
      }
      auto summary = [](std::vector<double> v) {
        if (v.empty()) return std::string("n/a");
        std::sort(v.begin(), v.end());
        const double med = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
        return "median " + fmt(med) + ", range " + fmt(v.front()) + " .. " + fmt(v.back());
      };
      md << "\nOver btSoftBody's front: time ratio at equal error " << summary(time_ratios)
         << "; error ratio at equal time " << summary(error_ratios)
         << ". Errors near the reference's own (B vs 2B above) are not resolved, so the last rows "
            "understate the error ratio.\n";
      md << "\n";
    }
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
            << (error_time > 0 && scene != "hanging_chain" ? "RMS position error at t = " + fmt(error_time) + " s"
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
                     "time (s) of the charted error (a sample time: 0.5, 1, 1.5, 2); <= 0: the final frame");
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
  auto* stab_report = stab->add_subcommand("report", "write the gnuplot scripts and docs/stability_grids.md");
  stab_report->add_option("--csv", stab_csv, "CSV of the sweep")->check(CLI::ExistingFile);
  stab_report->add_option("--docs", stab_docs, "directory of the PNGs and stability_grids.md");
  stab_report->add_option("--gp-dir", stab_gp, "where the gnuplot scripts go");
  // --- end stability map ---
  CLI11_PARSE(app, argc, argv);
  try {
    if (*stab_run) return xpbd_stability::cmd_run(stab_csv, stab_quick, stab_shard);
    if (*stab_report) return xpbd_stability::cmd_report(stab_csv, stab_docs, stab_gp);
    if (*cheap) return cmd_cheapest(csv, cheap_scene, target, error_time);
    if (*run) return cmd_run(out, quick, shard, only);
    if (*merge) return cmd_merge(inputs, merged);
    return cmd_report(csv, docs, gp_dir, command, sweep_seconds, error_time);
  } catch (const std::exception& e) {
    std::cerr << "xpbd-compare: " << e.what() << "\n";
    return 1;
  }
}

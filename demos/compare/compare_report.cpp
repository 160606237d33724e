// xpbd-compare report and cheapest (compare_cmds.hpp): docs/results.md, one
// gnuplot script per scene (scripts/compare.sh renders them to
// docs/results_<scene>.png), and the cheapest setting for an error target.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "demos/compare/cheapest.hpp"
#include "demos/compare/compare.hpp"
#include "demos/compare/compare_cmds.hpp"

namespace xpbd_compare {

namespace {
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
  // Per entry of `time`: btSoftBody's point (its error in m, its ms).
  std::vector<double> time_err, time_ms;
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
    if (t_ok) {
      q.time.push_back(p.ms / *tx);
      q.time_err.push_back(p.err);
      q.time_ms.push_back(p.ms);
    }
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

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

using RatioRow = std::tuple<std::string, std::string, Ratios, Ratios>;

// Which of btSoftBody's resolved points give a time ratio below 1, and
// where they lie on its front against the others (errors, times, ratios).
void where_below(std::ostringstream& md, const Ratios& q) {
  struct Range {
    double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
    void add(double v) { lo = std::min(lo, v), hi = std::max(hi, v); }
    std::string str() const { return lo == hi ? fmt(lo) : fmt(lo) + "-" + fmt(hi); }
  };
  Range err[2], ms[2], ratio[2];
  int count[2] = {0, 0};
  for (std::size_t i = 0; i < q.time.size(); ++i) {
    const int above = q.time[i] >= 1 ? 1 : 0;
    ++count[above];
    err[above].add(q.time_err[i]);
    ms[above].add(q.time_ms[i]);
    ratio[above].add(q.time[i]);
  }
  if (count[0] == 0) return;
  md << " The time ratio is below 1 at " << count[0] << " of btSoftBody's " << q.time.size()
     << " resolved points: ratios " << ratio[0].str() << ", at its errors of " << err[0].str() << " m and "
     << ms[0].str() << " ms per frame";
  if (count[1] > 0)
    md << "; at the other " << count[1] << " (errors " << err[1].str() << " m, " << ms[1].str() << " ms) it is "
       << ratio[1].str();
  md << ".";
}

// Where an XPBD variant's median ratio against btSoftBody is below 1, the
// measured facts that bear on it, from the same sweep: how far the
// compared errors are above the reference's resolution; for the coupled
// scenes, what stepping Bullet the other way costs and gives (the
// alternative's own ratios and its bodies' error); for xpbd_coloured, its
// error against array-order XPBD at the same budgets.
void below_one(std::ostringstream& md, const std::vector<Row>& rows, const std::vector<RatioRow>& ratio_rows,
               Judge judge) {
  auto find = [&](const std::string& scene, const std::string& method, const std::string& budget) -> const Row* {
    for (const Row& r : rows)
      if (r.scene == scene && r.method == method && label(r) == budget && r.status == "ok") return &r;
    return nullptr;
  };
  bool any = false;
  for (const auto& [scene, variant, q, w] : ratio_rows) {
    if (!(median(q.time) < 1) && !(median(q.error) < 1)) continue;
    if (!any) md << "### Where XPBD's ratio is below 1 (measured in this sweep)\n\n";
    any = true;
    md << "- **" << scene << ", " << variant << "** (time ratio " << fmt(median(q.time)) << ", error ratio "
       << fmt(median(q.error)) << "):";
    double res = std::nan("");
    std::vector<double> over;
    for (const Row& r : rows)
      if (r.scene == scene && r.method == "reference") res = judged_error(r, judge);
    for (const Row& r : rows)
      if (r.scene == scene && r.method == "bullet" && r.status == "ok" && res > 0) over.push_back(judged_error(r, judge) / res);
    if (!over.empty())
      md << " btSoftBody's errors are " << fmt(median(over)) << "x the reference's resolution (median over its runs; "
         << fmt(res) << " m)" << (median(over) < 5 ? ", so the fronts are close to what the reference can tell apart."
                                                   : ".");
    // The other rigid stepping ran with array-order XPBD only.
    for (const char* alt : {"xpbd_rigid_once", "xpbd_rigid_substeps"}) {
      if (variant != "xpbd") continue;
      std::vector<double> cost;
      double body = 0, own_body = 0;
      for (const Row& a : rows)
        if (a.scene == scene && a.method == variant && a.status == "ok" && a.substeps >= 5)
          if (const Row* b = find(scene, alt, label(a))) {
            cost.push_back(a.wall_ms_median / b->wall_ms_median);
            body = std::max(body, b->err_body_worst);
            own_body = std::max(own_body, a.err_body_worst);
          }
      if (cost.empty()) continue;
      const bool once = std::string(alt) == "xpbd_rigid_once";
      md << " XPBD here steps Bullet " << (once ? "at every substep" : "once per frame") << "; stepping it "
         << (once ? "once per frame" : "at every substep") << " (`" << alt << "`) changes XPBD's time per frame by a "
         << "factor " << fmt(1 / median(cost)) << " (median over the budgets of 5 substeps or more), ";
      for (const auto& [s2, v2, q2, w2] : ratio_rows)
        if (s2 == scene && v2 == alt)
          md << "which gives ratios of " << fmt(median(q2.time)) << " (time) and " << fmt(median(q2.error))
             << " (error), ";
      md << "at a worst body error of " << fmt(body) << " m over those runs (" << fmt(own_body) << " m with "
         << (once ? "every substep" : "once per frame") << ").";
    }
    where_below(md, q);
    if (variant == "xpbd_coloured") {
      std::vector<double> e;
      for (const Row& a : rows)
        if (a.scene == scene && a.method == "xpbd_coloured" && a.status == "ok")
          if (const Row* b = find(scene, "xpbd", label(a))) e.push_back(judged_error(a, judge) / judged_error(*b, judge));
      if (!e.empty())
        md << " At the same budgets the coloured order's error is " << fmt(median(e))
           << "x array-order XPBD's (median; a different Gauss-Seidel order, docs/bench-coloured.md).";
    }
    md << "\n";
  }
  if (any) md << "\n";
}

}  // namespace

int cmd_report(const ReportArgs& args) {
  const std::string& docs = args.docs;
  const std::string& gp_dir = args.gp_dir;
  const Judge judge = args.judge;
  const Judge other = judge == Judge::mean ? Judge::worst : Judge::mean;
  // The charted error: judged_error (the mean or the worst over the sample
  // times of max(particle RMS, body error)). The chain's and the catenary's
  // references are static closed forms, which hold once they have settled:
  // they are always charted at the final frame.
  auto final_only = [](const std::string& scene) { return static_reference(scene); };
  auto chart_error = [&](const Row& r) { return judged_error(r, judge); };
  auto err_name_of = [&](const std::string& scene, Judge j) {
    return !final_only(scene) ? std::string("error, ") + judge_name(j) + " over the sample times"
                              : std::string("RMS error at the final frame");
  };
  const std::string err_name = err_name_of("", judge);
  // Runs that failed: non-finite, exploded, or a body on the wrong side of
  // the cloth. They are kept in the CSV, off the fronts.
  auto failed = [](const Row& r) {
    return r.status == "nonfinite" || r.status == "exploded" || r.status == "wrong_side" || r.status == "lost_body";
  };
  const std::vector<Row> rows = read_csv(args.csv);
  std::vector<std::string> scene_order;
  for (const Row& r : rows)
    if (std::find(scene_order.begin(), scene_order.end(), r.scene) == scene_order.end())
      scene_order.push_back(r.scene);
  std::filesystem::create_directories(gp_dir);
  std::ostringstream md;
  md << "# Speed against accuracy: XPBD, PBD and btSoftBody\n\n"
     << "Generated by `xpbd-compare report` from `docs/results.csv` (every run, one row each). "
     << "Regenerate everything (build, sweep, CSV, charts, this page) with:\n\n"
     << "    " << args.command << "\n\n";
  if (args.sweep_seconds > 0)
    md << "The sweep took " << fmt(args.sweep_seconds, 4) << " s of wall clock on this machine.\n\n";
  md << "Where each method fails (time step, stiffness, mass ratio, impact speed): the stability map, "
        "[below](#where-each-method-fails-the-stability-map) and in [stability.md](stability.md).\n\n";
  write_report_method(md, judge, other);
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
  std::vector<std::string> methods = {"xpbd", "pbd", "bullet", "xpbd_coloured", "xpbd_rigid_substeps",
                                      "xpbd_rigid_once"};
  for (const char* m : {"xpbd_float", "xpbd_coloured_float", "pbd_float", "bullet_float"})
    if (std::any_of(rows.begin(), rows.end(), [&](const Row& r) { return r.method == m; })) methods.push_back(m);
  // scene, XPBD variant, ratios under the charted judge and under the other.
  std::vector<std::tuple<std::string, std::string, Ratios, Ratios>> ratio_rows;
  // btSoftBody against an XPBD variant on a scene's fronts under judge j.
  auto ratios_for = [&](const std::string& scene, const std::string& variant, Judge j) {
    std::vector<Point> x, b;
    double res = std::nan("");
    for (const Row& r : rows) {
      if (r.scene != scene) continue;
      if (r.method == "reference" && !r.err_series.empty()) res = judged_error(r, j);
      if (r.status != "ok") continue;
      if (r.method == variant) x.push_back({r.wall_ms_median, judged_error(r, j), label(r)});
      if (r.method == "bullet") b.push_back({r.wall_ms_median, judged_error(r, j), label(r)});
    }
    return bullet_vs_xpbd(pareto_front(x), pareto_front(b), res);
  };
  for (const std::string& scene : scene_order) {
    std::map<std::string, std::vector<Point>> pts;
    std::vector<std::string> skipped;
    int nonfinite = 0;
    for (const Row& r : rows) {
      if (r.scene != scene || r.method == "reference") continue;
      if (r.status == "ok") pts[r.method].push_back({r.wall_ms_median, chart_error(r), label(r)});
      else if (failed(r)) ++nonfinite;
      else if (r.status == "skipped" && skipped.empty()) skipped.push_back(r.method + ": " + r.note);
      else if (r.status == "error") skipped.push_back(r.method + " " + label(r) + ": " + r.note);
    }
    // gnuplot script with the data inline.
    const std::string png = docs + "/results_" + scene + ".png";
    std::ofstream gp(gp_dir + "/results_" + scene + ".gp");
    gp << "set terminal pngcairo size 900,600 noenhanced\nset output '" << png << "'\n"
       << "set logscale xy\nset grid\nset key top right\n"
       << "set xlabel 'wall time per frame (ms)'\nset ylabel 'position " << err_name_of(scene, judge) << " (m)'\n"
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
    md << "Pareto fronts (budget: ms per frame, " << err_name_of(scene, judge) << " in m):\n\n| method | front |\n|---|---|\n";
    for (const std::string& m : methods) {
      if (std::none_of(rows.begin(), rows.end(), [&](const Row& r) { return r.scene == scene && r.method == m; }))
        continue;  // not a method of this scene (the other rigid stepping)
      auto it = pts.find(m);
      md << "| " << m << " | ";
      if (it == pts.end() || it->second.empty()) {
        const bool any = std::any_of(rows.begin(), rows.end(), [&](const Row& r) {
          return r.scene == scene && r.method == m && (r.status == "ok" || failed(r));
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
    md << "The front's runs, every measure (errors: the mean and the worst over the sample times of "
          "max(particle RMS, body error), and the dynamic bodies' worst centre error; strain: edge "
          "|len/rest - 1|, max over the run and mean; penetration: the largest contact violation, m; energy "
          "drift: (E_end - E_0) / (M g L)):\n\n"
          "| method | budget | ms/frame | projections/frame | mean error (m) | worst error (m) | body error (m) | "
          "max strain | mean strain | max penetration (m) | energy drift |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const std::string& m : methods) {
      auto it = pts.find(m);
      if (it == pts.end()) continue;
      for (const Point& p : pareto_front(it->second))
        for (const Row& r : rows)
          if (r.scene == scene && r.method == m && r.status == "ok" && label(r) == p.label)
            md << "| " << m << " | " << p.label << " | " << fmt(r.wall_ms_median) << " | " << r.projections_per_frame
               << " | " << fmt(judged_error(r, Judge::mean)) << " | " << fmt(judged_error(r, Judge::worst)) << " | "
               << fmt(r.err_body_worst) << " | " << fmt(r.max_strain) << " | " << fmt(r.mean_strain) << " | "
               << fmt(r.max_penetration) << " | " << fmt(r.energy_drift) << " |\n";
    }
    md << "\n";
    if (nonfinite) {
      std::map<std::string, std::vector<std::string>> by;  // "method status" -> budgets
      for (const Row& r : rows)
        if (r.scene == scene && failed(r)) by[r.method + " " + r.status].push_back(label(r));
      md << nonfinite << " run(s) failed and are left off the fronts: non-finite (NaN/Inf), exploded (energy "
         << "gain above 0.1 M g L), wrong_side (a dynamic body on the other side of the cloth than in the "
         << "reference) or lost_body (a dynamic body farther from its reference position than the cloth's size):";
      for (const auto& [k, v] : by) {
        md << " " << k << " at";
        for (std::size_t i = 0; i < v.size(); ++i) md << (i ? ", " : " ") << v[i];
        md << ";";
      }
      md << "\n\n";
    }
    // XPBD with the scene's rigid stepping (xpbd) against the other
    // (CompareScene::alt_rigid_method), budget by budget: what the extra
    // Bullet steps cost and what they buy.
    for (const char* alt : {"xpbd_rigid_substeps", "xpbd_rigid_once"}) {
      if (std::none_of(rows.begin(), rows.end(), [&](const Row& r) { return r.scene == scene && r.method == alt; }))
        continue;
      const bool every = std::string(alt) == "xpbd_rigid_substeps";
      const std::string own = every ? "once per frame" : "every substep", other = every ? "every substep" : "once per frame";
      md << "Bullet stepped " << own << " (`xpbd`, this scene's setting) or " << other << " (`" << alt
         << "`), the same sweep; the time ratio is " << alt << " / xpbd:\n\n"
         << "| budget (status) | ms/frame, " << own << " | ms/frame, " << other << " | time ratio | mean error, "
         << own << " (m) | mean error, " << other << " (m) | worst, " << own << " (m) | worst, " << other
         << " (m) | body worst, " << own << " (m) | body worst, " << other << " (m) |\n|---|---|---|---|---|---|---|---|---|---|\n";
      for (const Row& a : rows) {
        if (a.scene != scene || a.method != "xpbd") continue;
        for (const Row& b : rows)
          if (b.scene == scene && b.method == alt && label(b) == label(a))
            md << "| " << label(a) << " (" << a.status << ", " << b.status << ") | " << fmt(a.wall_ms_median) << " | "
               << fmt(b.wall_ms_median) << " | " << fmt(b.wall_ms_median / a.wall_ms_median) << " | "
               << fmt(a.err_mean) << " | " << fmt(b.err_mean) << " | " << fmt(a.err_worst) << " | "
               << fmt(b.err_worst) << " | " << fmt(a.err_body_worst) << " | " << fmt(b.err_body_worst) << " |\n";
      }
      md << "\n";
    }
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
    for (const char* variant : {"xpbd", "xpbd_coloured", "xpbd_rigid_substeps", "xpbd_rigid_once"}) {
      if (!pts.count(variant) || !pts.count("bullet")) continue;
      const Ratios q = bullet_vs_xpbd(pareto_front(pts[variant]), pareto_front(pts["bullet"]), resolution);
      ratio_rows.push_back({scene, variant, q, ratios_for(scene, variant, other)});
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
        "exact), with the error judged by its " << judge_name(judge) << " over the sample times (the charts) and by its "
     << judge_name(other) << ". Above 1: XPBD is faster at equal error, or more accurate at equal time.\n\n"
        "| scene | XPBD variant | time ratio at equal error (" << judge_name(judge) << ") | error ratio at equal "
        "time (" << judge_name(judge) << ") | time ratio (" << judge_name(other) << ") | error ratio ("
     << judge_name(other) << ") | resolved points (time, error; " << judge_name(judge) << ") |\n|---|---|---|---|---|---|---|\n";
  for (const auto& [scene, variant, q, w] : ratio_rows)
    md << "| " << scene << " | " << variant << " | " << summary(q.time) << " | " << summary(q.error) << " | "
       << summary(w.time) << " | " << summary(w.error) << " | " << q.time.size() << ", " << q.error.size() << " |\n";
  md << "\n";
  below_one(md, rows, ratio_rows, judge);
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
      for (const Cheapest& c : cheapest(rows, scene, target, judge)) {
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
int cmd_cheapest(const std::string& csv_path, const std::string& scene, double target, Judge judge) {
  const std::vector<Row> rows = read_csv(csv_path);
  const std::vector<Cheapest> best = cheapest(rows, scene, target, judge);
  if (best.empty()) {
    std::cerr << "xpbd-compare cheapest: no runs of scene '" << scene << "' in " << csv_path << "\n";
    return 2;
  }
  std::cout << "scene " << scene << ", error target " << target << " m ("
            << (!static_reference(scene) ? std::string("error, ") + judge_name(judge) + " over the sample times"
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

}  // namespace xpbd_compare

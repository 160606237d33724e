// xpbd-fig5: the seed report's Fig. 5 (section 3.1), reproduced.
//
//   xpbd-fig5                        writes docs/fig5.csv, prints the tables of docs/fig5.md
//   xpbd-fig5 --csv FILE             the same, CSV to FILE
//   xpbd-fig5 --sweep                spread of XPBD's metrics against the compliance
//   xpbd-fig5 --help
//
// A square cloth pinned at two corners starts horizontal, falls and hangs.
// PBD and XPBD run it at 5, 10, 20, 50 and 100 iterations with everything
// else equal (demos/fig5_scene.hpp); the CSV holds the metrics of every
// frame of every run, for docs/fig5.gp.
//
// Exit status: 0 on success, 1 if a run or the output fails, 2 for bad
// command-line input.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "demos/fig5_scene.hpp"

namespace {

using xpbd::Method;
using xpbd::Real;
using xpbd_demos::Fig5Params;
using xpbd_demos::Fig5Run;
using xpbd_demos::Fig5Sample;

const char* name(Method m) { return m == Method::xpbd ? "XPBD" : "PBD"; }

// Metrics are compared from this time on; before it every height is within
// 5 cm of 0 (free fall) and a spread relative to the mean is not meaningful.
constexpr double kSpreadFrom = 0.1;  // s

void write_csv(const std::string& path, const std::vector<Fig5Run>& pbd,
               const std::vector<Fig5Run>& xpbd) {
  const std::filesystem::path file(path);
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw std::runtime_error("cannot open '" + tmp.string() + "' for writing");
    out << "method,iterations,t_s,centre_y_m,lowest_y_m,strain_mean,strain_max,bend_mean_rad\n";
    char line[256];
    for (const auto* runs : {&pbd, &xpbd})
      for (const Fig5Run& r : *runs)
        for (const Fig5Sample& s : r.samples) {
          std::snprintf(line, sizeof line, "%s,%d,%.6f,%.6f,%.6f,%.6e,%.6e,%.6e\n",
                        name(runs == &pbd ? Method::pbd : Method::xpbd), r.iterations, s.t,
                        s.centre_y, s.lowest_y, s.strain_mean, s.strain_max, s.bend_mean);
          out << line;
        }
    // Two blank-line-separated blocks are not needed: gnuplot filters by column.
    out.flush();
    if (!out) throw std::runtime_error("writing '" + tmp.string() + "' failed");
  }
  std::filesystem::rename(tmp, file);
}

// Sample index nearest to time t.
std::size_t index_at(const Fig5Run& r, double t) {
  std::size_t best = 0;
  for (std::size_t k = 0; k < r.samples.size(); ++k)
    if (std::abs(r.samples[k].t - t) < std::abs(r.samples[best].t - t)) best = k;
  return best;
}

void print_table(const char* title, double Fig5Sample::*field, const std::vector<double>& times,
                 const std::vector<Fig5Run>& pbd, const std::vector<Fig5Run>& xpbd) {
  std::printf("\n%s\n\n| method | iterations |", title);
  for (double t : times) std::printf(" t = %.2f s |", t);
  std::printf(" max spread, t >= %.1f s |\n|---|---|", kSpreadFrom);
  for (std::size_t i = 0; i <= times.size(); ++i) std::printf("---|");
  std::printf("\n");
  for (const auto* runs : {&pbd, &xpbd}) {
    const char* m = name(runs == &pbd ? Method::pbd : Method::xpbd);
    for (const Fig5Run& r : *runs) {
      std::printf("| %s | %d |", m, r.iterations);
      for (double t : times) std::printf(" %.4f |", r.samples[index_at(r, t)].*field);
      std::printf(" |\n");
    }
    std::printf("| %s | **spread** |", m);
    for (double t : times)
      std::printf(" **%.2f%%** |",
                  100 * xpbd_demos::spread_at(*runs, field, index_at(runs->front(), t)));
    std::printf(" **%.2f%%** |\n", 100 * xpbd_demos::max_spread(*runs, field, kSpreadFrom));
  }
}

// XPBD's spread against the compliance (docs/fig5.md, "Why this compliance").
void sweep(Fig5Params p) {
  const int movable = p.n * p.n - 2;
  const double w = double(movable) / double(p.mass);  // 1/kg, inverse mass of one particle
  const double h = double(p.dt) / p.substeps;
  std::printf("| compliance (m/N) | alpha/h^2 / (2w) | XPBD max spread centre | lowest | "
              "PBD max spread centre | lowest | mean strain at 100 it, end | lowest y at 100 "
              "it, end (m) |\n|---|---|---|---|---|---|---|---|\n");
  const auto pbd = xpbd_demos::run_fig5_all(p, Method::pbd);
  const double pc = xpbd_demos::max_spread(pbd, &Fig5Sample::centre_y, kSpreadFrom);
  const double pl = xpbd_demos::max_spread(pbd, &Fig5Sample::lowest_y, kSpreadFrom);
  for (double a : {1e-4, 1e-3, 3e-3, 1e-2, 2e-2, 3e-2, 4e-2, 5e-2, 1e-1}) {
    p.compliance = Real(a);
    const auto runs = xpbd_demos::run_fig5_all(p, Method::xpbd);
    const Fig5Sample& end = runs.back().samples.back();
    std::printf("| %g | %.3f | %.2f%% | %.2f%% | %.2f%% | %.2f%% | %.4f | %.4f |\n", a,
                a / (h * h) / (2 * w),
                100 * xpbd_demos::max_spread(runs, &Fig5Sample::centre_y, kSpreadFrom),
                100 * xpbd_demos::max_spread(runs, &Fig5Sample::lowest_y, kSpreadFrom), 100 * pc,
                100 * pl, end.strain_mean, end.lowest_y);
  }
}

}  // namespace

int main(int argc, char** argv) {
  constexpr int kOk = 0, kRunFailed = 1, kBadInput = 2;
  Fig5Params p;
  std::string csv = "docs/fig5.csv";
  bool do_sweep = false;
  double compliance = double(p.compliance), stiffness = double(p.pbd_stiffness),
         duration = double(p.duration);

  CLI::App app{"xpbd-fig5: the seed report's Fig. 5 -- a hanging cloth under PBD and XPBD at "
               "5, 10, 20, 50 and 100 iterations (docs/fig5.md)."};
  app.add_option("--csv", csv, "output CSV file (every frame of every run)")->capture_default_str();
  app.add_option("--n", p.n, "particles per side")->check(CLI::Range(3, 200))->capture_default_str();
  app.add_option("--compliance", compliance, "XPBD compliance of every edge (m/N)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  app.add_option("--pbd-stiffness", stiffness, "PBD stiffness k of every edge")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--duration", duration, "simulated time (s)")
      ->check(CLI::Range(0.1, 100.0))
      ->capture_default_str();
  app.add_option("--substeps", p.substeps, "substeps per 1/60 s frame (both methods)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_flag("--sweep", do_sweep, "print XPBD's spread against the compliance instead");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kOk : kBadInput;
  }
  p.compliance = Real(compliance);
  p.pbd_stiffness = Real(stiffness);
  p.duration = Real(duration);

  try {
    if (do_sweep) {
      sweep(p);
      return kOk;
    }
    const auto pbd = xpbd_demos::run_fig5_all(p, Method::pbd);
    const auto xpbd = xpbd_demos::run_fig5_all(p, Method::xpbd);
    for (const auto* runs : {&pbd, &xpbd})
      for (const Fig5Run& r : *runs)
        for (const Fig5Sample& s : r.samples)
          if (!s.finite)
            throw std::runtime_error(std::string(name(runs == &pbd ? Method::pbd : Method::xpbd)) +
                                     " at " + std::to_string(r.iterations) +
                                     " iterations produced a non-finite position");
    write_csv(csv, pbd, xpbd);
    std::printf("n = %d, compliance = %g m/N, PBD k = %g, %d substep(s) per 1/60 s, %g s\n", p.n,
                compliance, stiffness, p.substeps, duration);
    const std::vector<double> times = {0.25, 0.5, 1.0, 2.0, double(p.duration)};
    print_table("Height of the centre particle, centre_y (m)", &Fig5Sample::centre_y, times, pbd,
                xpbd);
    print_table("Height of the lowest particle, lowest_y (m)", &Fig5Sample::lowest_y, times, pbd,
                xpbd);
    print_table("Mean edge strain, strain_mean", &Fig5Sample::strain_mean, times, pbd, xpbd);
    print_table("Mean |dihedral angle| over the interior edges, bend_mean (rad)",
                &Fig5Sample::bend_mean, times, pbd, xpbd);
    std::printf("\nwrote %s\n", csv.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "xpbd-fig5: %s\n", e.what());
    return kRunFailed;
  }
  return kOk;
}

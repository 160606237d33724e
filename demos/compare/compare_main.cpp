// xpbd-compare: the speed-vs-accuracy sweep (docs/results.md) and the
// stability map (docs/stability.md).
//
//   xpbd-compare run --out docs/results.csv [--quick] [--shard i/n] [--scenes a,b]
//   xpbd-compare merge a.csv b.csv ... -o out.csv
//   xpbd-compare report --csv docs/results.csv --docs docs --gp-dir DIR [--judge mean|worst]
//   xpbd-compare cheapest --csv docs/results.csv --scene NAME --target METRES
//   xpbd-compare stability run|merge|report ...
//
// This file parses the command line; the commands are in compare_run.cpp,
// compare_report.cpp and stability_cmd.cpp. scripts/compare.sh renders the
// gnuplot scripts `report` writes to docs/results_<scene>.png.
#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "demos/compare/compare_cmds.hpp"
#include "demos/compare/stability.hpp"

using namespace xpbd_compare;

int main(int argc, char** argv) {
  CLI::App app{"xpbd-compare: XPBD, PBD and btSoftBody, speed against accuracy (docs/results.md)"};
  app.require_subcommand(1);
  RunArgs ra;
  auto* run = app.add_subcommand("run", "run the sweep, appending to the CSV (resumes)");
  run->add_option("--out", ra.out, "CSV file to append to");
  run->add_flag("--quick", ra.quick, "a tiny sweep (3 budgets, 30 frames, a small reference)");
  run->add_option("--shard", ra.shard, "i/n: run every n-th run of the sweep starting at i");
  run->add_option("--scenes", ra.scenes, "only these scenes")->delimiter(',');
  run->add_option("--methods", ra.methods,
                  "only these methods (reference, xpbd, xpbd_coloured, xpbd_rigid_substeps, pbd, bullet)")
      ->delimiter(',');
  run->add_option("--reference", ra.reference_budget,
                  "SxI: the reference budget 2B for every scene instead of the scene's own (for convergence "
                  "studies; the check runs S/2 x I)");
  run->add_option("--reference-dir", ra.reference_dir,
                  "double build: also write each scene's reference positions here; float build: read them "
                  "from here (required)");
  std::vector<std::string> inputs;
  std::string merged;
  auto* merge = app.add_subcommand("merge", "merge shard CSVs (first occurrence of a run wins)");
  merge->add_option("inputs", inputs, "CSV files")->required()->check(CLI::ExistingFile);
  merge->add_option("-o,--out", merged, "output CSV")->required();
  ReportArgs rep;
  std::string judge = "mean";
  auto* report = app.add_subcommand("report", "write docs/results.md and the gnuplot scripts");
  report->add_option("--csv", rep.csv, "CSV of the sweep")->check(CLI::ExistingFile);
  report->add_option("--docs", rep.docs, "directory of results.md and the PNGs");
  report->add_option("--gp-dir", rep.gp_dir, "where the gnuplot scripts go");
  report->add_option("--command", rep.command, "the regenerating command, for results.md");
  report->add_option("--sweep-seconds", rep.sweep_seconds, "wall clock of the sweep, for results.md");
  report->add_option("--judge", judge, "the charted error over the sample times: mean or worst")
      ->check(CLI::IsMember({"mean", "worst"}));
  std::string cheap_scene, csv = "docs/results.csv";
  double target = 0;
  auto* cheap = app.add_subcommand("cheapest", "the cheapest setting per method that meets an error target");
  cheap->add_option("--csv", csv, "CSV of the sweep")->check(CLI::ExistingFile);
  cheap->add_option("--scene", cheap_scene,
                    "scene name, or its base name to include every resolution (hanging_cloth)")
      ->required();
  cheap->add_option("--target", target, "error target (m)")->required()->check(CLI::PositiveNumber);
  cheap->add_option("--judge", judge, "the judged error over the sample times: mean or worst")
      ->check(CLI::IsMember({"mean", "worst"}));
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
    if (*cheap) return cmd_cheapest(csv, cheap_scene, target, parse_judge(judge));
    if (*run) return cmd_run(ra);
    if (*merge) return cmd_merge(inputs, merged);
    rep.judge = parse_judge(judge);
    return cmd_report(rep);
  } catch (const std::exception& e) {
    std::cerr << "xpbd-compare: " << e.what() << "\n";
    return 1;
  }
}

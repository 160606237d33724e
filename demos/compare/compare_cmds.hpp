#pragma once
// The subcommands of xpbd-compare (compare_main.cpp parses the command
// line): `run` and `merge` in compare_run.cpp, `report` and `cheapest` in
// compare_report.cpp (the report's fixed text in report_method.cpp). Each
// returns the process exit code; bad arguments are reported on stderr with
// exit code 2.
#include <sstream>
#include <string>
#include <vector>

#include "demos/compare/compare.hpp"

namespace xpbd_compare {

struct RunArgs {
  std::string out = "docs/results.csv";
  bool quick = false;
  std::string shard;                 // "i/n"
  std::vector<std::string> scenes;   // empty: all
  std::vector<std::string> methods;  // empty: all
  std::string reference_dir;
  std::string reference_budget;      // "SxI" overrides every scene's 2B
};
int cmd_run(const RunArgs& a);
int cmd_merge(const std::vector<std::string>& inputs, const std::string& out);

struct ReportArgs {
  std::string csv = "docs/results.csv";
  std::string docs = "docs";
  std::string gp_dir = "build/compare";
  std::string command = "bash scripts/compare.sh";
  double sweep_seconds = 0;
  Judge judge = Judge::mean;
};
int cmd_report(const ReportArgs& a);
// docs/results.md's fixed sections (how the runs are made, what changed,
// interrupting and resuming), judged under `judge` with `other` in the summary.
void write_report_method(std::ostringstream& md, Judge judge, Judge other);
int cmd_cheapest(const std::string& csv_path, const std::string& scene, double target, Judge judge);

}  // namespace xpbd_compare

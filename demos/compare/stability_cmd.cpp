// The stability map's CSV and the subcommand `xpbd-compare stability`
// (stability.hpp).
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
// A whole field as a number / integer, or an error naming where and what.
double to_d(const std::string& s, const std::string& where) {
  if (s == "nan") return std::nan("");
  if (s == "inf") return INFINITY;
  if (s == "-inf") return -INFINITY;
  std::size_t pos = 0;
  double v = 0;
  try {
    v = std::stod(s, &pos);
  } catch (const std::exception&) {
    pos = std::string::npos;
  }
  if (s.empty() || pos != s.size()) throw std::runtime_error(where + ": not a number: \"" + s + "\"");
  return v;
}
int to_i(const std::string& s, const std::string& where) {
  std::size_t pos = 0;
  int v = 0;
  try {
    v = std::stoi(s, &pos);
  } catch (const std::exception&) {
    pos = std::string::npos;
  }
  if (s.empty() || pos != s.size()) throw std::runtime_error(where + ": not an integer: \"" + s + "\"");
  return v;
}
constexpr std::size_t kFields = 15;
}  // namespace

std::string to_csv(const StabilityRow& r) {
  using xpbd_compare::quote;
  std::ostringstream o;
  o << quote(r.sweep) << ',' << quote(r.method) << ',' << quote(r.x_label) << ',' << quote(r.y_label) << ','
    << r.xi << ',' << r.yi << ',' << quote(r.outcome) << ',' << r.frames << ',' << r.frames_completed << ','
    << num(r.max_strain) << ',' << num(r.energy_ratio) << ',' << num(r.max_escape) << ',' << r.tunnelled << ','
    << num(r.wall_s) << ',' << quote(r.note);
  return o.str();
}

std::vector<StabilityRow> read_stability_csv(const std::string& path, std::vector<int>* lines) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::vector<StabilityRow> rows;
  if (lines) lines->clear();
  std::string line;
  int ln = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++ln;
    if (!line.empty() && line.back() == '\r') line.pop_back();  // a file saved with CRLF
    if (line.empty()) continue;
    const std::string where = path + ":" + std::to_string(ln);
    if (!header) {
      if (line == xpbd_compare::csv_header())
        throw std::runtime_error(where + ": this is an `xpbd-compare run` CSV (docs/results.csv), not a stability "
                                         "CSV; use `xpbd-compare merge` for it");
      if (line != stability_csv_header())
        throw std::runtime_error(where + ": not the stability CSV header (expected \"" +
                                 std::string(stability_csv_header()) + "\")");
      header = true;
      continue;
    }
    const auto f = xpbd_compare::split_csv(line);
    if (f.size() != kFields)
      throw std::runtime_error(where + ": " + std::to_string(f.size()) + " fields, expected " +
                               std::to_string(kFields) + " (a truncated last line? delete it)");
    StabilityRow r;
    r.sweep = f[0];
    r.method = f[1];
    r.x_label = f[2];
    r.y_label = f[3];
    r.xi = to_i(f[4], where + " xi");
    r.yi = to_i(f[5], where + " yi");
    r.outcome = f[6];
    r.frames = to_i(f[7], where + " frames");
    r.frames_completed = to_i(f[8], where + " frames_completed");
    r.max_strain = to_d(f[9], where + " max_strain");
    r.energy_ratio = to_d(f[10], where + " energy_ratio");
    r.max_escape = to_d(f[11], where + " max_escape");
    r.tunnelled = to_i(f[12], where + " tunnelled");
    r.wall_s = to_d(f[13], where + " wall_s");
    r.note = f[14];
    if (r.sweep.empty() || r.method.empty() || r.outcome.empty())
      throw std::runtime_error(where + ": empty sweep, method or outcome");
    rows.push_back(std::move(r));
    if (lines) lines->push_back(ln);
  }
  if (!header) throw std::runtime_error(path + ":1: empty file, expected the stability CSV header");
  return rows;
}

std::vector<StabilityRow> merge_stability(const std::vector<std::string>& inputs) {
  struct Seen {
    std::size_t index;  // into rows
    std::string where;  // file:line
  };
  std::vector<StabilityRow> rows;
  std::map<std::string, Seen> seen;
  for (const auto& path : inputs) {
    std::vector<int> lines;
    const auto part = read_stability_csv(path, &lines);
    for (std::size_t k = 0; k < part.size(); ++k) {
      const std::string where = path + ":" + std::to_string(lines[k]);
      const auto it = seen.find(part[k].key());
      if (it == seen.end()) {
        seen.emplace(part[k].key(), Seen{rows.size(), where});
        rows.push_back(part[k]);
      } else if (rows[it->second.index].outcome != part[k].outcome) {
        throw std::runtime_error(where + ": " + part[k].key() + " is " + part[k].outcome + " here but " +
                                 rows[it->second.index].outcome + " at " + it->second.where +
                                 " (the same run twice with different outcomes; drop one)");
      }
    }
  }
  // In the sweep's order; rows not in it (another version's runs) last.
  std::map<std::string, std::size_t> order;
  for (const auto& r : stability_runs(false)) order.emplace(r.key(), order.size());
  auto rank = [&](const StabilityRow& r) {
    const auto it = order.find(r.key());
    return it == order.end() ? order.size() : it->second;
  };
  std::stable_sort(rows.begin(), rows.end(),
                   [&](const StabilityRow& a, const StabilityRow& b) { return rank(a) < rank(b); });
  return rows;
}

// ---------------------------------------------------------------------------
// The subcommand.

int cmd_run(const std::string& out, bool quick, const std::string& shard, const std::vector<std::string>& sweeps) {
  int si = 0, sn = 1;
  if (!shard.empty() && (std::sscanf(shard.c_str(), "%d/%d", &si, &sn) != 2 || sn < 1 || si < 0 || si >= sn)) {
    std::cerr << "--shard: expected i/n with 0 <= i < n, got \"" << shard << "\"\n";
    return 2;
  }
  const auto runs = stability_runs(quick);
  for (const auto& name : sweeps)
    if (std::none_of(runs.begin(), runs.end(), [&](const StabilityRun& r) { return r.sweep == name; })) {
      std::cerr << "--sweeps: unknown sweep \"" << name << "\" (dt_stiffness, impact, mass_ratio, chain_box, "
                   "trampoline)\n";
      return 2;
    }
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
    if (int(k % std::size_t(sn)) == si && !done.count(runs[k].key()) &&
        (sweeps.empty() || std::find(sweeps.begin(), sweeps.end(), runs[k].sweep) != sweeps.end()))
      todo.push_back(&runs[k]);
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
              << short_num(row.max_strain) << ", KE ratio " << short_num(row.energy_ratio) << ", " << short_num(row.wall_s) << " s; "
              << short_num(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()) << " s)\n";
  }
  return 0;
}

int cmd_merge(const std::vector<std::string>& inputs, const std::string& out) {
  const auto rows = merge_stability(inputs);
  const std::string tmp = out + ".tmp";
  {
    std::ofstream o(tmp);
    o << stability_csv_header() << '\n';
    for (const auto& r : rows) o << to_csv(r) << '\n';
    if (!o) {
      std::cerr << tmp << ": write failed\n";
      return 1;
    }
  }
  std::filesystem::rename(tmp, out);
  std::cerr << "xpbd-compare stability merge: " << rows.size() << " runs from " << inputs.size() << " file(s) -> "
            << out << "\n";
  return 0;
}

int cmd_report(const std::string& csv_path, const std::string& docs, const std::string& gp_dir) {
  const auto rows = read_stability_csv(csv_path);
  std::filesystem::create_directories(gp_dir);
  const char* sweeps[] = {"dt_stiffness", "impact", "mass_ratio", "chain_box", "trampoline"};
  const char* titles[] = {"time step x stiffness (16x16 hanging cloth)", "impact speed (m/s) x time step",
                          "chain, heavy end particle: mass ratio x budget",
                          "chain + attached rigid box: mass ratio x budget",
                          "trampoline ball mass ratio x budget"};
  constexpr int kSweeps = sizeof(sweeps) / sizeof(sweeps[0]);
  const char* methods[] = {"xpbd", "pbd", "bullet"};
  const std::map<std::string, int> code = {{"stable", 0},   {"over_stretched", 1}, {"exploded", 2},
                                           {"nan", 3},      {"tunnelled", 4},      {"error", 5},
                                           {"skipped", 6}};
  std::ostringstream md;
  md << "<!-- generated by `xpbd-compare stability report` from docs/stability.csv -->\n"
     << "Cells: S stable, O over-stretched, E exploded, N NaN, T tunnelled, ! error, - skipped (the method "
        "cannot express the scene), . not run.\n\n";
  const char letter[] = {'S', 'O', 'E', 'N', 'T', '!', '-'};
  for (const char* m : methods) {
    std::ofstream gp(gp_dir + "/stability_" + m + ".gp");
    gp << "set terminal pngcairo size " << 500 * kSweeps << ",480 noenhanced\nset output '" << docs << "/stability_" << m
       << ".png'\n"
       << "set palette defined (0 '#2ca02c', 1 '#ffbf00', 2 '#d62728', 3 '#000000', 4 '#1f77b4', 5 '#aaaaaa', "
          "6 '#eeeeee')\n"
       << "set palette maxcolors 7\nset cbrange [-0.5:6.5]\n"
       << "set cbtics ('stable' 0, 'over-stretched' 1, 'exploded' 2, 'NaN' 3, 'tunnelled' 4, 'error' 5, "
          "'skipped' 6)\n"
       << "unset key\nset multiplot layout 1," << kSweeps << " title '" << m << ": stability map'\n";
    for (int s = 0; s < kSweeps; ++s) {
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

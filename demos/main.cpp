// xpbd-demo: headless demo scenes (docs/demo.md).
//
//   xpbd-demo                       the default scene, run with XPBD, PBD and
//                                   btSoftBody, and their comparison
//   xpbd-demo --list                the built-in scenes
//   xpbd-demo --dump NAME           a built-in scene as a scene file
//   xpbd-demo SCENE|FILE [options]  one scene, one solver (or --solver all)
//
// Exit status: 0 success; 1 the run or an output failed (or the state went
// non-finite); 2 bad input (command line or scene); 3 a run diverged (status
// over_stretched or exploded, docs/metrics.md); 130 interrupted.
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "demos/builtin_scenes.hpp"
#include "demos/frame_export.hpp"
#include "demos/output.hpp"
#include "demos/preview.hpp"
#include "demos/scene_file.hpp"
#include "demos/scene_runner.hpp"
#include "xpbd/error.hpp"

namespace {

using namespace xpbd_demos;
namespace fs = std::filesystem;

constexpr int kOk = 0, kRunFailed = 1, kBadInput = 2, kDiverged = 3, kInterrupted = 130;

std::atomic<bool> g_interrupted{false};
extern "C" void on_signal(int) { g_interrupted = true; }
struct Interrupted {};

// Bad input found after the command line parsed (unknown scene, ...).
struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Progress: a bar redrawn in place on a terminal, a plain line per 10% otherwise.
class Progress {
 public:
  Progress(std::string label, int total) : label_(std::move(label)), total_(total), tty_(isatty(2)) {}
  void update(int done) {
    const int pct = total_ > 0 ? done * 100 / total_ : 100;
    if (tty_) {
      if (pct == last_) return;
      const int width = 30, filled = pct * width / 100;
      std::fprintf(stderr, "\r%-28s [%s%s] %3d%% (%d/%d)", label_.c_str(), std::string(filled, '#').c_str(),
                   std::string(width - filled, ' ').c_str(), pct, done, total_);
      if (done == total_) std::fputc('\n', stderr);
    } else {
      if (pct / 10 == last_ / 10 && last_ >= 0) return;
      std::fprintf(stderr, "%s: %d%% (frame %d of %d)\n", label_.c_str(), pct / 10 * 10, done, total_);
    }
    last_ = pct;
    std::fflush(stderr);
  }
  void abort() {
    if (tty_ && last_ >= 0 && last_ < 100) std::fputc('\n', stderr);
  }

 private:
  std::string label_;
  int total_;
  bool tty_;
  int last_ = -1;
};

struct Cli {
  std::string scene;  // built-in name or file; empty = default comparison
  std::string solver;  // xpbd|pbd|bullet|all; empty = the scene's own
  std::optional<int> substeps, iterations, frames;
  std::optional<double> dt;
  std::string out;
  std::vector<std::string> sets;
  std::string export_format;  // "", obj, vtk
  bool preview = true;
  bool stages = false;  // --stages: per-stage time breakdown (xpbd/pbd runs)
  bool hash = false;    // --hash: print each run's final-state hash
  int threads = 1;      // --threads: xpbd/pbd coloured sweep and contact search
};

// The scene named on the command line: a file if it names one (or ends in
// .json), otherwise a built-in scene.
SceneSpec resolve_scene(const std::string& name) {
  std::error_code ec;
  if (fs::is_regular_file(name, ec) || name.ends_with(".json")) return load_scene_file(name);
  if (const SceneSpec* s = find_builtin_scene(name)) return *s;
  throw BadInput("unknown scene '" + name + "': not a built-in scene (see --list) and no such file");
}

Solver parse_solver(const std::string& s) {
  if (s == "xpbd") return Solver::xpbd;
  if (s == "pbd") return Solver::pbd;
  return Solver::bullet;
}

struct RunOutput {
  RunResult result;
  fs::path dir;
  std::vector<std::string> files;
  std::string error;  // an output that failed (the others were written)
};

// Runs one solver on the scene and writes its outputs to `dir`.
RunOutput run_one(const SceneSpec& spec, const ExpandedSoft& soft, const RunOptions& opt, const fs::path& dir,
                  const Cli& cli) {
  RunOutput out;
  out.dir = dir;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create directory '" + dir.string() + "': " + ec.message());

  std::optional<ExportFormat> fmt;
  if (cli.export_format == "obj") fmt = ExportFormat::obj;
  if (cli.export_format == "vtk") fmt = ExportFormat::vtk;
  // Rigid bodies as meshes in their body frames, once (exports, preview).
  std::vector<RigidMesh> body_meshes;
  const bool need_meshes = fmt.has_value() || cli.preview;
  if (need_meshes)
    for (std::size_t k = 0; k < spec.bodies.size(); ++k) {
      body_meshes.push_back(shape_mesh(spec.bodies[k].shape, spec.base_dir));
      body_meshes.back().name = spec.bodies[k].name.empty() ? "body_" + std::to_string(k) : spec.bodies[k].name;
    }
  auto posed = [&](const FrameView& v) {
    std::vector<RigidMesh> m;
    for (std::size_t k = 0; k < body_meshes.size() && k < v.bodies.size(); ++k) {
      if (spec.bodies[k].shape.kind == ShapeKind::plane) {
        // Planes are framed around the world origin (rigid_mesh).
        m.push_back(rigid_mesh(spec.bodies[k].shape, v.bodies[k].position, v.bodies[k].orientation, spec.base_dir));
        m.back().name = body_meshes[k].name;
      } else {
        m.push_back(transform_mesh(body_meshes[k], v.bodies[k].position, v.bodies[k].orientation));
      }
    }
    return m;
  };

  const std::vector<int> shown = preview_frame_numbers(opt.frames + 1, 4);
  PreviewInput preview;
  preview.title = spec.name + " - " + solver_name(opt.solver);
  preview.triangles = soft.triangles;
  preview.lines = soft.lines;
  Progress progress(spec.name + " (" + solver_name(opt.solver) + ")", opt.frames);
  int exported = 0;
  // metrics.json's per-frame entries go to disk as the run makes them, so
  // memory stays flat over any number of frames (docs/reliability.md).
  const fs::path metrics = dir / "metrics.json";
  JsonArraySpool per_frame(metrics);
  RunOptions streamed = opt;
  streamed.keep_series = false;
  auto on_frame = [&](const FrameView& v) {
    if (g_interrupted) throw Interrupted{};
    per_frame.add(frame_json(v.frame, *v.metrics, v.frame >= 1 ? std::optional<double>(v.wall_ms) : std::nullopt));
    if (fmt && v.finite) {
      write_frame(*fmt, frame_file_path(dir, v.frame, *fmt), v.positions, soft.triangles, soft.lines, posed(v));
      ++exported;
    }
    const bool last = v.frame == opt.frames || !v.finite;
    if (cli.preview && v.finite && (std::find(shown.begin(), shown.end(), v.frame) != shown.end() || last)) {
      // Keep the planned frames; if the run stops early, its last finite
      // frame replaces the ones it never reached.
      PreviewFrame f;
      f.time = v.time;
      f.x.assign(v.positions.begin(), v.positions.end());
      f.bodies = posed(v);
      if (preview.frames.size() < shown.size()) preview.frames.push_back(std::move(f));
      else if (last) preview.frames.back() = std::move(f);
    }
    progress.update(v.frame);
  };
  try {
    out.result = run_scene(spec, soft, streamed, on_frame);
  } catch (...) {
    progress.abort();
    throw;
  }
  per_frame.write(to_json(out.result), "per_frame");
  out.files.push_back(metrics.string());
  if (fmt) out.files.push_back((dir / "frames").string() + "/ (" + std::to_string(exported) + " ." +
                               extension(*fmt) + " files)");
  if (cli.preview && !preview.frames.empty()) {
    try {
      render_preview(dir / "preview.png", preview);
      out.files.push_back((dir / "preview.png").string());
    } catch (const std::exception& e) {
      out.error = std::string("preview.png: ") + e.what();
    }
  }
  return out;
}

// "0.05 strain" (or "0.05 residual strain"), "1 mm penetration", or both
// joined by "and".
std::string tolerance_text(const RunOptions& o) {
  char buf[96];
  std::string t;
  if (o.tolerance > 0) {
    std::snprintf(buf, sizeof buf, "%.3g %sstrain", o.tolerance,
                  o.tolerance_measure == ToleranceMeasure::residual ? "residual " : "");
    t = buf;
  }
  if (o.penetration_tolerance > 0) {
    std::snprintf(buf, sizeof buf, "%.3g mm penetration", 1e3 * o.penetration_tolerance);
    t += (t.empty() ? "" : " and ") + std::string(buf);
  }
  return t;
}

void print_run(const RunOutput& o) {
  const RunResult& r = o.result;
  // With a tolerance the budget is the mean substeps per frame, rounded (the
  // line after the table gives it exactly).
  const int substeps = r.mean_substeps > 0 ? int(std::lround(r.mean_substeps)) : r.options.substeps;
  std::printf("%-8s %3d x %-3d %9.3f %11lld %11.3e %11.3e %10.3e  %s\n", solver_name(r.options.solver),
              substeps, r.options.iterations, r.wall_ms_median, r.projections_per_frame,
              r.max_strain, r.mean_strain, r.max_penetration, r.status.c_str());
}

void print_header() {
  std::printf("%-8s %-9s %9s %11s %11s %11s %10s  %s\n", "solver", "budget", "ms/frame", "proj/frame",
              "strain max", "strain mean", "penetr. m", "status");
}

// --stages: ms per frame of every stage the run used (docs/stages.md).
void print_stages(const RunResult& r) {
  if (r.stage_ms_per_frame.empty()) return;
  std::printf("\nstage times, %s %d x %d (ms per frame, mean over %d frames):\n", solver_name(r.options.solver),
              r.options.substeps, r.options.iterations, r.frames_completed);
  for (const auto& [name, ms] : r.stage_ms_per_frame)
    std::printf("  %-24s %10.4f %6.1f%%\n", name.c_str(), ms, r.wall_ms_mean > 0 ? 100 * ms / r.wall_ms_mean : 0.0);
  std::printf("  %-24s %10.4f\n", "total (wall_ms mean)", r.wall_ms_mean);
}

std::string fmt_ratio(double num, double den) {
  if (!(den > 0) || !std::isfinite(num / den)) return "n/a";
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", num / den);
  return b;
}

int run(const Cli& cli) {
  const bool comparison = cli.scene.empty() || cli.solver == "all";
  SceneSpec spec = resolve_scene(cli.scene.empty() ? kDefaultScene : cli.scene);
  const std::string label = cli.scene.empty() ? std::string(kDefaultScene) : cli.scene;
  if (!cli.sets.empty()) spec = apply_sets(spec, cli.sets, label);
  RunOptions base = run_options(spec);
  if (cli.substeps) base.substeps = *cli.substeps;
  if (cli.iterations) base.iterations = *cli.iterations;
  if (cli.frames) base.frames = *cli.frames;
  if (cli.dt) base.dt = static_cast<xpbd::Real>(*cli.dt);
  base.stage_times = cli.stages;
  base.threads = cli.threads;

  // The runs: solver, budget split, output folder. The comparison spends the
  // same budget (projections per frame) four ways: XPBD as the scene says
  // (substeps x iterations); PBD as the seed's Algorithm 1 (one step of
  // substeps x iterations sweeps); btSoftBody as it is usually run (one
  // internal step per frame, piterations = the whole budget) and with
  // XPBD's split (`substeps` internal steps of `iterations` piterations).
  struct Plan {
    Solver solver;
    bool one_step;
    std::string folder;
  };
  std::vector<Plan> plans;
  if (comparison)
    plans = {{Solver::xpbd, false, "xpbd"}, {Solver::pbd, true, "pbd"}, {Solver::bullet, true, "bullet"},
             {Solver::bullet, false, "bullet_substeps"}};
  else
    plans = {{cli.solver.empty() ? base.solver : parse_solver(cli.solver), false, ""}};

  const ExpandedSoft soft = expand(spec.soft, spec.base_dir);
  std::string why;
  const bool bullet_ok = bullet_can_express(spec, soft, &why);
  if (!comparison && plans[0].solver == Solver::bullet && !bullet_ok)
    throw BadInput("--solver bullet: " + spec.name + ": " + why);

  const fs::path root = cli.out.empty() ? fs::path("out") / (cli.scene.empty() ? "default" : spec.name) : fs::path(cli.out);
  std::printf("scene %s: %s\n", spec.name.c_str(), spec.description.c_str());
  std::printf("%d frames of %.4g s; %zu particles, %zu rigid bodies\n", base.frames, double(base.dt),
              soft.scene.positions.size(), spec.bodies.size());
  // Every output directory must take files before anything runs: a bad
  // --out is found now, not after the whole run.
  for (const Plan& p : plans)
    if (p.solver != Solver::bullet || bullet_ok) check_writable_dir(p.folder.empty() ? root : root / p.folder);
  std::vector<RunOutput> outs;
  std::vector<std::string> skipped;
  for (const Plan& p : plans) {
    if (p.solver == Solver::bullet && !bullet_ok) {
      if (p.folder != "bullet_substeps") skipped.push_back(std::string("btSoftBody: ") + why);
      continue;
    }
    RunOptions opt = base;
    opt.solver = p.solver;
    if (p.solver == Solver::bullet) opt.threads = 1;  // btSoftBody has no threads here
    if (p.one_step) {
      opt.iterations = base.substeps * base.iterations;
      opt.substeps = 1;
    }
    outs.push_back(run_one(spec, soft, opt, root / p.folder, cli));
  }

  std::printf("\n");
  print_header();
  for (const RunOutput& o : outs) print_run(o);
  for (const RunOutput& o : outs)
    if (const RunResult& r = o.result; r.options.tolerance_on() && r.options.solver != Solver::bullet)
      std::printf("%-8s tolerance %s: %.3g substeps per frame on average (started at %d), largest %d "
                  "(at most %d), %d frame(s) above it\n",
                  solver_name(r.options.solver), tolerance_text(r.options).c_str(), r.mean_substeps,
                  r.options.substeps, r.max_substeps_used, r.options.max_substeps, r.frames_tolerance_missed);
  for (const std::string& s : skipped) std::printf("skipped %s\n", s.c_str());
  for (const RunOutput& o : outs) print_stages(o.result);
  if (cli.hash) {
    std::printf("\nfinal-state hash (docs/reliability.md):\n");
    for (const RunOutput& o : outs)
      std::printf("  %-8s %3d x %-3d %016llx\n", solver_name(o.result.options.solver), o.result.options.substeps,
                  o.result.options.iterations, static_cast<unsigned long long>(o.result.state_hash));
  }
  if (comparison && outs.size() == 4) {
    std::printf("\nbtSoftBody / XPBD at the same budget:\n");
    const RunResult& x = outs[0].result;
    for (int k : {2, 3}) {
      const RunResult& b = outs[k].result;
      std::printf("  %3d x %-3d time %s, max strain %s, mean strain %s, max penetration %s\n", b.options.substeps,
                  b.options.iterations, fmt_ratio(b.wall_ms_median, x.wall_ms_median).c_str(),
                  fmt_ratio(b.max_strain, x.max_strain).c_str(), fmt_ratio(b.mean_strain, x.mean_strain).c_str(),
                  fmt_ratio(b.max_penetration, x.max_penetration).c_str());
    }
  }
  std::vector<std::string> notes;  // once each, in order
  for (const RunOutput& o : outs)
    for (const std::string& note : o.result.notes)
      if (std::find(notes.begin(), notes.end(), note) == notes.end()) notes.push_back(note);
  for (const std::string& note : notes) std::printf("note: %s\n", note.c_str());
  std::printf("\nfiles:\n");
  int status = kOk;
  for (const RunOutput& o : outs) {
    for (const std::string& f : o.files) std::printf("  %s\n", f.c_str());
    if (!o.error.empty()) {
      std::fprintf(stderr, "xpbd-demo: %s\n", o.error.c_str());
      status = kRunFailed;
    }
    if (!o.result.finite) {
      std::fprintf(stderr, "xpbd-demo: %s (%s): the state became non-finite after frame %d\n", spec.name.c_str(),
                   solver_name(o.result.options.solver), o.result.frames_completed);
      status = kRunFailed;
    } else if (o.result.status != "ok") {
      std::fprintf(stderr,
                   "xpbd-demo: %s (%s %d x %d): %s: largest strain %.3g (bound %.3g), largest kinetic energy %.3g "
                   "times what the scene can have given it (bound %.3g)\n",
                   spec.name.c_str(), solver_name(o.result.options.solver), o.result.options.substeps,
                   o.result.options.iterations, o.result.status.c_str(), o.result.max_strain,
                   o.result.options.health.max_strain, o.result.energy_ratio, o.result.options.health.energy_factor);
      if (status == kOk) status = kDiverged;
    }
  }
  std::printf("metrics fields and units: docs/metrics.md\n");
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  Cli cli;
  bool list = false;
  std::string dump;
  CLI::App app{"xpbd-demo: headless XPBD demo scenes in Bullet (docs/demo.md). Without a scene: the "
               "default scene run with XPBD, PBD and Bullet's btSoftBody, and their comparison."};
  app.add_flag("--list", list, "list the built-in scenes");
  app.add_option("--dump", dump, "print a built-in scene as a scene file (docs/scene-format.md)");
  app.add_option("scene", cli.scene, "built-in scene name or scene file (.json)");
  app.add_option("--solver", cli.solver, "xpbd, pbd, bullet (btSoftBody), or all; default: the scene's")
      ->check(CLI::IsMember({"xpbd", "pbd", "bullet", "all"}));
  app.add_option("--substeps", cli.substeps, "substeps per frame (btSoftBody: internal steps)")->check(CLI::Range(1, 100000));
  app.add_option("--iterations", cli.iterations, "iterations per substep (btSoftBody: piterations)")->check(CLI::Range(1, 100000));
  app.add_option("--frames", cli.frames, "frames to run")->check(CLI::Range(1, 10000000));
  app.add_option("--dt", cli.dt, "frame length in seconds")->check(CLI::PositiveNumber);
  app.add_option("--out", cli.out, "output directory (default: out/<scene>, out/default without a scene)");
  app.add_option("--set", cli.sets, "override a scene field: path=value, e.g. solver.substeps=20 or bodies.0.mass=2")
      ->take_all();
  app.add_option("--export", cli.export_format, "also write every frame as obj (Blender) or vtk (ParaView)")
      ->check(CLI::IsMember({"obj", "vtk"}));
  app.add_flag("!--no-preview", cli.preview, "do not render preview.png");
  app.add_flag("--hash", cli.hash,
               "print a hash of each run's final state, bit for bit (particles and rigid bodies; "
               "docs/reliability.md)");
  app.add_option("--threads", cli.threads, "threads for the coloured sweep and the contact search (xpbd/pbd, needs solver.coloured)")
      ->check(CLI::Range(1, 256));
  app.add_flag("--stages", cli.stages,
               "time every solver stage and print ms per frame per stage (xpbd/pbd; docs/stages.md)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kOk : kBadInput;
  }
  if (list && (!dump.empty() || !cli.scene.empty())) {
    std::fprintf(stderr, "xpbd-demo: --list takes no scene\n");
    return kBadInput;
  }
  if (list) {
    for (const SceneSpec& s : builtin_scenes())
      std::printf("%-24s %s%s\n", s.name.c_str(), s.description.c_str(), s.name == kDefaultScene ? " (default)" : "");
    return kOk;
  }
  if (!dump.empty()) {
    const SceneSpec* s = find_builtin_scene(dump);
    if (!s) {
      std::fprintf(stderr, "xpbd-demo: --dump: unknown scene '%s' (see --list)\n", dump.c_str());
      return kBadInput;
    }
    try {
      std::fputs(scene_text(to_json(*s)).c_str(), stdout);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "xpbd-demo: --dump %s: %s\n", dump.c_str(), e.what());
      return kRunFailed;
    }
    return kOk;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  try {
    return run(cli);
  } catch (const Interrupted&) {
    std::fprintf(stderr, "xpbd-demo: interrupted; files written so far are complete, the run's metrics.json was not written\n");
    return kInterrupted;
  } catch (const SceneFileError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return kBadInput;
  } catch (const BadInput& e) {
    std::fprintf(stderr, "xpbd-demo: %s\n", e.what());
    return kBadInput;
  } catch (const xpbd::SceneError& e) {
    std::fprintf(stderr, "xpbd-demo: %s: %s\n", cli.scene.empty() ? kDefaultScene : cli.scene.c_str(), e.what());
    return kBadInput;
  } catch (const xpbd::ConfigError& e) {
    std::fprintf(stderr, "xpbd-demo: %s\n", e.what());
    return kBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "xpbd-demo: %s\n", e.what());
    return kRunFailed;
  }
}

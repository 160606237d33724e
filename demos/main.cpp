// xpbd-demo: headless demos of the xpbd solver.
//
//   xpbd-demo                          the default demo (docs/demo.md)
//   xpbd-demo --frames N --out DIR     the same, N frames, metrics.json in DIR
//
// Exit status: 0 on success, 1 if the run or the output fails, 2 for bad
// command-line input. Later options (--list, --solver, scene files) hang off
// the same CLI::App.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <system_error>

#include "demos/default_demo.hpp"
#include "demos/output.hpp"

int main(int argc, char** argv) {
  constexpr int kOk = 0, kRunFailed = 1, kBadInput = 2;
  xpbd_demos::DefaultDemoOptions opt;
  std::string out_dir = "out/default";

  CLI::App app{"xpbd-demo: headless XPBD demos. Without options: the hanging-cloth comparison "
               "of XPBD, PBD and Bullet's btSoftBody (docs/demo.md)."};
  app.add_option("--frames", opt.frames, "frames to simulate at 60 Hz")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  app.add_option("--out", out_dir, "output directory (metrics.json goes there)")
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help, or the error and a hint
    return code == 0 ? kOk : kBadInput;
  }
  if (out_dir.empty()) {
    std::fprintf(stderr, "--out: the output directory must not be empty\n");
    return kBadInput;
  }

  try {
    // Fail before the run, not after it, if the output directory is unusable.
    const std::filesystem::path file = std::filesystem::path(out_dir) / "metrics.json";
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) {
      std::fprintf(stderr, "xpbd-demo: cannot create directory '%s': %s\n", out_dir.c_str(),
                   ec.message().c_str());
      return kRunFailed;
    }
    const xpbd_demos::DefaultDemoResult r = xpbd_demos::run_default_demo(opt);
    xpbd_demos::print_summary(r, stdout);
    xpbd_demos::write_json_atomically(file, xpbd_demos::to_json(r));
    std::printf("wrote %s\n", file.string().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "xpbd-demo: %s\n", e.what());
    return kRunFailed;
  }
  return kOk;
}

// Fuzz target: a scene file through the parser, the full validation, and
// (if it is valid and small) one or two frames of the XPBD runner. Bad input must
// be an exception naming it; a crash, a sanitizer report, a leak or a hang
// is a finding (docs/reliability.md, scripts/fuzz.sh).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <string>

#include "demos/scene_file.hpp"
#include "demos/scene_runner.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace xpbd_demos;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    // Relative mesh paths resolve against a folder without OBJ files.
    const SceneSpec spec = parse_scene(parse_json_text(text, "fuzz.json"), "fuzz.json", "/nonexistent");
    const ExpandedSoft soft = expand(spec.soft, spec.base_dir);
    // Keep one input fast: small scenes, small budgets, and a bound on the
    // simulated time: particles x frames x dt at most that of 2000
    // particles over two 1/60 s frames. A long frame is still run, on a
    // small scene: its contact reach grows with the frame, and a large
    // scene with 1 s frames took seconds per input and slowed a campaign
    // to a few tens of inputs a second (docs/reliability.md).
    if (soft.scene.num_particles() > 2000 || spec.bodies.size() > 50) return 0;
    RunOptions opt = run_options(spec);
    opt.frames = opt.dt > 1.0 / 30 ? 1 : 2;
    const double particle_seconds = double(soft.scene.num_particles()) * opt.frames * double(opt.dt);
    if (particle_seconds > 2000.0 * 2 / 60) return 0;
    opt.substeps = std::min(opt.substeps, 10);
    opt.iterations = std::min(opt.iterations, 4);
    opt.max_substeps = std::min(opt.max_substeps, 30);  // the tolerance controller's cap
    opt.keep_series = false;
    (void)run_scene(spec, soft, opt);
  } catch (const std::exception&) {
    // Refused with a message: what bad input must get.
  }
  return 0;
}

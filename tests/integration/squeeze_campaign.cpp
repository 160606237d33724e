// The campaign behind docs/squeeze.md's tables (scripts/squeeze_seeds.sh;
// not a test, and not run by the suite): the bar-squeeze application
// (squeeze_app.hpp) with 49 bodies over wrinkle seeds 1-32 at the defaults,
// one line per seed.
//
//   xpbd_squeeze_campaign [--surface-edges | --no-surface-edges] [--strain S] [--substeps N] [--iterations N]
//                         [--contact-sweeps N] [--hierarchy] [--alternate-sweeps] [--bend C] [--shear C]
//                         [--seeds A-B]
//
// --surface-edges, --no-surface-edges: ContactSettings::surface_edge_contacts
// on (its default since 2026-11-29) or off.
// --strain S: the tolerance's strain target S (SystemSettings::tolerance.strain, > 0).
// --substeps N: SystemSettings::substeps N (1 <= N <= 1000) instead of the default.
// --iterations N: SystemSettings::iterations N (1 <= N <= 1000).
// --contact-sweeps N: SystemSettings::contact_sweeps N (0 <= N <= 1000).
// --hierarchy, --alternate-sweeps: SystemSettings::hierarchy, alternate_sweeps on.
// --bend C, --shear C: the compliance (m/N, >= 0) of the cloth's bending and
// shear distance edges (default 0: rigid; squeeze_app.hpp, add_cloth).
// --seeds A-B: wrinkle seeds A to B (1 <= A <= B), or one seed: --seeds A.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "squeeze_app.hpp"
#include "squeeze_args.hpp"

int main(int argc, char** argv) {
  using namespace xpbd_bullet::test;
  using namespace xpbd_bullet::test::squeeze;
  bool surface_edges = xpbd_bullet::ContactSettings{}.surface_edge_contacts;
  double strain = SystemSettings{}.tolerance.strain;
  ClothAndSeeds cs;  // the cloth's compliances and the seeds
  cs.first = 1;
  cs.last = 32;
  int substeps = 0;  // run(): 0 for the default
  SystemSettings other;  // the settings run() takes from the flags through its tweak
  const auto usage = [](const char* why, const char* arg) {
    std::fprintf(stderr,
                 "xpbd_squeeze_campaign: %s '%s' (usage: [--surface-edges | --no-surface-edges] [--strain S] "
                 "[--substeps N] [--iterations N] [--contact-sweeps N] [--hierarchy] [--alternate-sweeps] "
                 "[--bend C] [--shear C] [--seeds A-B])\n",
                 why, arg);
    return 2;
  };
  for (int a = 1; a < argc; ++a) {
    if (std::strcmp(argv[a], "--surface-edges") == 0) {
      surface_edges = true;
    } else if (std::strcmp(argv[a], "--no-surface-edges") == 0) {
      surface_edges = false;
    } else if (std::strcmp(argv[a], "--strain") == 0 && a + 1 < argc) {
      char* end = nullptr;
      strain = std::strtod(argv[++a], &end);
      if (end == argv[a] || *end != '\0' || !(strain > 0) || !(strain < 1e6))
        return usage("--strain needs a number > 0, got", argv[a]);
    } else if (std::strcmp(argv[a], "--substeps") == 0 && a + 1 < argc) {
      const unsigned n = parse_whole(argv[++a]);
      if (n < 1 || n > 1000) return usage("--substeps needs a whole number from 1 to 1000, got", argv[a]);
      substeps = int(n);
    } else if (std::strcmp(argv[a], "--iterations") == 0 && a + 1 < argc) {
      const unsigned n = parse_whole(argv[++a]);
      if (n < 1 || n > 1000) return usage("--iterations needs a whole number from 1 to 1000, got", argv[a]);
      other.iterations = int(n);
    } else if (std::strcmp(argv[a], "--contact-sweeps") == 0 && a + 1 < argc) {
      const std::string v = argv[++a];
      const unsigned n = v == "0" ? 0 : parse_whole(v);
      if ((n == 0 && v != "0") || n > 1000)
        return usage("--contact-sweeps needs a whole number from 0 to 1000, got", argv[a]);
      other.contact_sweeps = int(n);
    } else if (std::strcmp(argv[a], "--hierarchy") == 0) {
      other.hierarchy = true;
    } else if (std::strcmp(argv[a], "--alternate-sweeps") == 0) {
      other.alternate_sweeps = true;
    } else if (const char* why = nullptr; const int t = take_cloth_and_seeds(argc, argv, a, cs, why)) {
      if (t < 0) return usage(why, argv[a]);
    } else {
      return usage("unknown or incomplete argument", argv[a]);
    }
  }
  for (unsigned seed = cs.first; seed <= cs.last; ++seed) {
    const Result r = run(49, true, other.contact_sweeps, true, substeps, seed, kFrames,
                         SystemSettings{}.tolerance.penetration, true, surface_edges, strain,
                         [&](SystemSettings& set) {
                           set.iterations = other.iterations;
                           set.hierarchy = other.hierarchy;
                           set.alternate_sweeps = other.alternate_sweeps;
                         },
                         cs.bend, cs.shear);
    // The bar's mean speed over the last 100 frames (from its centre's
    // path): whether the pile has come to rest.
    double speed = 0;
    for (std::size_t f = r.bar.size() - 100; f < r.bar.size(); ++f)
      speed += double((r.bar[f] - r.bar[f - 1]).norm()) / (double(kDt) * 100);
    std::printf("seed %u: deepest %.4g mm, %d frames deep, strain %.3g, %.1f sweeps/step, finite %d exploded %d, "
                "%d frames with an edge over 20 %%, %ld such edges, %ld of them through a body (%ld through the "
                "bar, %ld at an attached particle), bar speed over the last 100 frames %.4f m/s\n",
                seed, 1e3 * double(r.deepest), r.frames_deep, double(r.strain), r.sweeps_per_step, int(r.finite),
                int(r.exploded), r.frames_over, r.edges_over, r.edges_through, r.edges_through_bar,
                r.edges_through_attached, speed);
  }
  return 0;
}

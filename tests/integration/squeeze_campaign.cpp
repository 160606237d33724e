// The campaign behind docs/squeeze.md's tables (scripts/squeeze_seeds.sh;
// not a test, and not run by the suite): the bar-squeeze application
// (squeeze_app.hpp) with 49 bodies over wrinkle seeds 1-32 at the defaults,
// one line per seed.
//
//   xpbd_squeeze_campaign [--surface-edges]
//
// --surface-edges: ContactSettings::surface_edge_contacts on.
#include <cstdio>
#include <cstring>

#include "squeeze_app.hpp"

int main(int argc, char** argv) {
  using namespace xpbd_bullet::test;
  using namespace xpbd_bullet::test::squeeze;
  bool surface_edges = xpbd_bullet::ContactSettings{}.surface_edge_contacts;
  for (int a = 1; a < argc; ++a) {
    if (std::strcmp(argv[a], "--surface-edges") == 0) {
      surface_edges = true;
    } else {
      std::fprintf(stderr, "xpbd_squeeze_campaign: unknown argument '%s' (the only one is --surface-edges)\n",
                   argv[a]);
      return 2;
    }
  }
  for (unsigned seed = 1; seed <= 32; ++seed) {
    const Result r = run(49, true, 0, true, 0, seed, kFrames, SystemSettings{}.tolerance.penetration, true,
                         surface_edges);
    // The bar's mean speed over the last 100 frames (from its centre's
    // path): whether the pile has come to rest.
    double speed = 0;
    for (std::size_t f = r.bar.size() - 100; f < r.bar.size(); ++f)
      speed += double((r.bar[f] - r.bar[f - 1]).norm()) / (double(kDt) * 100);
    std::printf("seed %u: deepest %.4g mm, %d frames deep, strain %.3g, %.1f sweeps/step, finite %d exploded %d, "
                "%d frames with an edge over 20 %%, %ld such edges, %ld of them through a body, bar speed over "
                "the last 100 frames %.4f m/s\n",
                seed, 1e3 * double(r.deepest), r.frames_deep, double(r.strain), r.sweeps_per_step, int(r.finite),
                int(r.exploded), r.frames_over, r.edges_over, r.edges_through, speed);
  }
  return 0;
}

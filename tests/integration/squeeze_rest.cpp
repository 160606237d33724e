// The bar-squeeze application (squeeze_app.hpp) without the random bodies:
// the bar lands on its own cloth and comes to rest. What stretch is left at
// rest, whether it is the substep count's, and what the cloth's bending and
// shear compliance change (docs/squeeze-budget.md, "At rest: the substep
// count and the material"; not a test, and not run by the suite).
//
//   xpbd_squeeze_rest [--substeps LO,HI] [--bend C] [--shear C] [--seeds A-B]
//
// Per wrinkle seed, four phases of one run: 600 frames at LO substeps, then
// 300 at HI, 300 at LO and 300 at HI (SystemSettings::substeps, changed with
// set_settings; the defaults otherwise, the contact target included). Per
// phase, one line: the largest edge strain over its last 60 frames, the
// edges over 20 % at its end, the fastest particle and the bar's speed there.
// --substeps LO,HI: the two counts (1 <= LO, HI <= 1000; default 10,50).
// --bend C, --shear C: the compliance (m/N, >= 0) of the cloth's bending and
// shear distance edges (default 0: rigid, as in the application).
// --seeds A-B: wrinkle seeds A to B (default 1-4), or one seed: --seeds A.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "squeeze_app.hpp"
#include "squeeze_args.hpp"

namespace {

using namespace xpbd_bullet::test;
using namespace xpbd_bullet::test::squeeze;

struct Stretch {
  Real largest = 0;  // largest (|x_a - x_b| - rest) / rest
  int over = 0;      // edges over 20 %
};

Stretch stretch(const xpbd::Model& m, const xpbd::State& s) {
  Stretch r;
  for (const xpbd::Distance& d : m.get<xpbd::Distance>()) {
    const Real e = ((s.x[d.p[0]] - s.x[d.p[1]]).norm() - d.rest) / d.rest;
    r.largest = std::max(r.largest, e);
    r.over += e > Real(0.2);
  }
  return r;
}

void run_seed(unsigned seed, int lo, int hi, Real bend, Real shear) {
  BulletWorld bw;
  bw.add_body(new btStaticPlaneShape(btVector3(0, 1, 0), 0), 0, BulletWorld::at(Vec3::Zero()));
  btRigidBody* bar = bw.add_body(new btBoxShape(bt(kBarHalf)), kBarMass, BulletWorld::at(kBarStart));
  XpbdWorld xw(bw.world());
  const auto id = add_cloth(xw, bar, SystemSettings{}, false, seed, bend, shear);
  const int frames[] = {kFrames, 300, 300, 300};
  const int counts[] = {lo, hi, lo, hi};
  int f = 0;
  for (int p = 0; p < 4; ++p) {
    SystemSettings set = xw.settings(id);
    set.substeps = counts[p];
    xw.set_settings(id, set);
    Real late = 0;
    for (int k = 0; k < frames[p]; ++k, ++f) {
      bw.step();
      if (k >= frames[p] - 60) late = std::max(late, stretch(xw.model(id), xw.state(id)).largest);
    }
    const xpbd::State& s = xw.state(id);
    Real fastest = 0;
    for (const Vec3& v : s.v) fastest = std::max(fastest, v.norm());
    std::printf("seed %u, frames %4d-%4d at %3d substeps: largest strain over the last 60 frames %.3f, %3d edges "
                "over 20 %% at the end, fastest particle %.3f m/s, bar %.4f m/s\n",
                seed, f - frames[p], f - 1, counts[p], double(late), stretch(xw.model(id), s).over, double(fastest),
                double(bar->getLinearVelocity().length()));
  }
}

}  // namespace

int main(int argc, char** argv) {
  int lo = 10, hi = 50;
  ClothAndSeeds cs;  // the cloth's compliances and the seeds
  cs.last = 4;
  const auto usage = [](const char* why, const char* arg) {
    std::fprintf(stderr,
                 "xpbd_squeeze_rest: %s '%s' (usage: [--substeps LO,HI] [--bend C] [--shear C] [--seeds A-B])\n",
                 why, arg);
    return 2;
  };
  for (int a = 1; a < argc; ++a) {
    if (std::strcmp(argv[a], "--substeps") == 0 && a + 1 < argc) {
      const std::string v = argv[++a];
      const std::size_t comma = v.find(',');
      const unsigned l = parse_whole(v.substr(0, comma));
      const unsigned h = comma == std::string::npos ? 0 : parse_whole(v.substr(comma + 1));
      if (l < 1 || l > 1000 || h < 1 || h > 1000)
        return usage("--substeps needs LO,HI, two whole numbers from 1 to 1000, got", argv[a]);
      lo = int(l);
      hi = int(h);
    } else if (const char* why = nullptr; const int t = take_cloth_and_seeds(argc, argv, a, cs, why)) {
      if (t < 0) return usage(why, argv[a]);
    } else {
      return usage("unknown or incomplete argument", argv[a]);
    }
  }
  for (unsigned seed = cs.first; seed <= cs.last; ++seed) run_seed(seed, lo, hi, cs.bend, cs.shear);
  return 0;
}

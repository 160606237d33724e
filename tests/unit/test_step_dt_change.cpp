// A time step that shrinks (step.cpp, update_velocities; docs/reliability.md,
// "Variable time steps"). A cloth hanging from its two top corners at 60 Hz
// x 10 substeps sags by the error one sweep per substep leaves. Stepped then
// at 1e-9 s, its hard edges (compliance 0) take up that error within
// substeps 1.7e6 times shorter: v = (x - x_prev)/h turned the removed
// distance into speeds that grew by 0.16 m/s per step, with nothing moving
// that fast over 3e-8 s. Closed form: over 30 steps of 1e-9 s the cloth's
// kinetic energy can change by no more than gravity's work over that time,
// about M g v t = 0.4 kg * 9.81 * 0.002 m/s * 3e-8 s, i.e. nothing at the
// scale of its energy at rest.
#include <gtest/gtest.h>

#include <cstdio>

#include "xpbd/xpbd.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd;

Real kinetic(const Model& m, const State& s) {
  Real e = 0;
  for (std::size_t i = 0; i < s.v.size(); ++i)
    if (m.inv_mass[i] > Real(0)) e += Real(0.5) / m.inv_mass[i] * s.v[i].squaredNorm();
  return e;
}

struct Hanging {
  Model m;
  State s;
  StepConfig cfg;
};

Hanging hanging_cloth() {
  SceneDesc scene;
  ClothGridDesc c;
  c.nx = c.ny = 24;
  c.mass = Real(0.4);
  c.pins = ClothPins::top_corners;
  add_cloth_grid(scene, c);
  Hanging h{compile(scene), {}, {}};
  h.s = make_state(h.m);
  h.cfg.dt = Real(1) / 60;
  h.cfg.substeps = 10;
  for (int k = 0; k < 180; ++k) step(h.m, h.s, h.cfg);  // 3 s: at rest
  return h;
}

TEST(StepDtChange, TinyStepsAfterLargeOnesAddNoKineticEnergy) {
  for (Real dt : {Real(1e-9), Real(1e-6)}) {
    Hanging h = hanging_cloth();
    const Real before = kinetic(h.m, h.s);
    StepConfig small = h.cfg;
    small.dt = dt;
    for (int k = 0; k < 30; ++k) step(h.m, h.s, small);
    const Real after = kinetic(h.m, h.s);
    std::printf("30 steps of %.0e s after 60 Hz x 10: kinetic energy %.3g J -> %.3g J\n", double(dt),
                double(before), double(after));
    // Gravity's work over 30 dt is below 1e-9 J; round-off on top.
    EXPECT_LE(after, before * Real(1.001) + Real(1e-9));
  }
}

// Steps that grow, or stay the same, take the plain update v = (x - x_prev)/h:
// State::velocity_step follows dt, and a run at 1/60 s gives the same bits
// with or without a restart of that bookkeeping; so does a run whose steps
// take more substeps than the last (the bridge's tolerance controller
// changes the count, not the step).
TEST(StepDtChange, ConstantStepIsThePlainUpdate) {
  Hanging a = hanging_cloth();
  Hanging b = hanging_cloth();
  EXPECT_EQ(a.s.velocity_step, a.cfg.dt);
  b.s.velocity_step = 0;  // as a fresh state
  for (int k = 0; k < 10; ++k) {
    a.cfg.substeps = b.cfg.substeps = 10 + 3 * k;
    step(a.m, a.s, a.cfg);
    step(b.m, b.s, b.cfg);
  }
  for (std::size_t i = 0; i < a.s.v.size(); ++i) ASSERT_EQ(a.s.v[i], b.s.v[i]) << "particle " << i;
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

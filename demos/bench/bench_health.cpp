// The cost of the bridge's divergence checks (SystemSettings::check_health).
//
// Scene: a 64 x 64 cloth (1 m, 1 kg, pinned at two corners, edges 1e-8 m/N)
// hanging in a btDiscreteDynamicsWorld with no other body, 60 Hz, the
// default 10 substeps x 1 iteration, array order. Each timed iteration is
// one stepSimulation call (one internal step), after 60 steps of swinging:
//   world_step/checks:0   check_health = false;
//   world_step/checks:1   check_health = true (the default).
// Compare the two within one run (the machine is shared): the checks' cost
// is checks:1 / checks:0 - 1. docs/benchmarks.md runs it as
//   bench_health --benchmark_enable_random_interleaving=true
//                --benchmark_repetitions=10 --benchmark_min_time=0.2
#include <benchmark/benchmark.h>
#include <btBulletDynamicsCommon.h>

#include <memory>

#include "xpbd/xpbd.hpp"
#include "xpbd_bullet/world.hpp"

namespace {

struct Scene {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  std::unique_ptr<xpbd_bullet::XpbdWorld> xw;

  explicit Scene(bool checks) {
    world.setGravity(btVector3(0, btScalar(-9.81), 0));
    xw = std::make_unique<xpbd_bullet::XpbdWorld>(world);
    xpbd::SceneDesc scene;
    xpbd::ClothGridDesc c;
    c.nx = c.ny = 64;
    c.origin = xpbd::Vec3(xpbd::Real(-0.5), 0, 0);
    c.u = xpbd::Vec3::UnitX();
    c.v = xpbd::Vec3::UnitZ();
    c.stretch = c.shear_mat = c.bend_mat = xpbd::Material{xpbd::Real(1e-8), 0, 1};
    c.pinned = {{0, 0}, {63, 0}};
    xpbd::add_cloth_grid(scene, c);
    auto model = std::make_shared<const xpbd::Model>(xpbd::compile(scene));
    xpbd_bullet::SystemSettings set;
    set.check_health = checks;
    xw->add_system(model, xpbd::make_state(*model), set);
    for (int f = 0; f < 60; ++f) step();
  }
  void step() { world.stepSimulation(btScalar(1) / 60, 1, btScalar(1) / 60); }
};

void world_step(benchmark::State& state) {
  Scene s(state.range(0) != 0);
  for (auto _ : state) s.step();
}
BENCHMARK(world_step)->Arg(0)->Arg(1)->ArgName("checks");

}  // namespace

BENCHMARK_MAIN();

// The cost of the bridge's divergence checks (SystemSettings::check_health)
// and of its default contact target (SystemSettings::tolerance.penetration).
//
// Scene: a 64 x 64 cloth (1 m, 1 kg, pinned at two corners, edges 1e-8 m/N)
// hanging in a btDiscreteDynamicsWorld with no other body, 60 Hz, the
// default 10 substeps x 1 iteration, array order. Each timed iteration is
// one stepSimulation call (one internal step), after 60 steps of swinging:
//   world_step/checks:0   check_health = false;
//   world_step/checks:1   check_health = true (the default).
// Both with the contact target off. Then the same cloth draped over a
// static box (0.6 x 0.2 x 0.6 m, its top 0.2 m under the cloth's start;
// about 3,200 particle contacts per step) at the defaults but for the
// contact target:
//   draped_step/target:0  tolerance.penetration = 0 (a fixed 10 substeps);
//   draped_step/target:1  tolerance.penetration = 5 mm (the default): one
//                         copy of the state and one pass over the contacts
//                         per step, and no step solved again (the drape is
//                         within 5 mm at 10 substeps).
// Then the pinned cloth with the coloured sweep, checks off and on, at 1
// and at 20 substeps:
//   coloured_step/checks:C/substeps:S
// where one substep shows what a step costs besides its sweeps.
// Compare within one run (the machine is shared): the checks' cost is
// checks:1 / checks:0 - 1, the target's target:1 / target:0 - 1.
// docs/bench-bridge.md runs it as
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
  btBoxShape box_shape{btVector3(btScalar(0.3), btScalar(0.1), btScalar(0.3))};
  std::unique_ptr<btRigidBody> box;
  std::unique_ptr<xpbd_bullet::XpbdWorld> xw;
  xpbd_bullet::SystemId id;

  // box: the draped variant (the static box under the cloth, no pins).
  Scene(bool checks, bool target, bool with_box, bool coloured = false, int substeps = 10) {
    world.setGravity(btVector3(0, btScalar(-9.81), 0));
    if (with_box) {
      btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, &box_shape);
      info.m_startWorldTransform.setIdentity();
      info.m_startWorldTransform.setOrigin(btVector3(0, btScalar(-0.3), btScalar(0.5)));
      box = std::make_unique<btRigidBody>(info);
      world.addRigidBody(box.get());
    }
    xw = std::make_unique<xpbd_bullet::XpbdWorld>(world);
    xpbd::SceneDesc scene;
    xpbd::ClothGridDesc c;
    c.nx = c.ny = 64;
    c.origin = xpbd::Vec3(xpbd::Real(-0.5), 0, 0);
    c.u = xpbd::Vec3::UnitX();
    c.v = xpbd::Vec3::UnitZ();
    c.stretch = c.shear_mat = c.bend_mat = xpbd::Material{xpbd::Real(1e-8), 0, 1};
    if (!with_box) c.pinned = {{0, 0}, {63, 0}};
    xpbd::add_cloth_grid(scene, c);
    auto model = std::make_shared<const xpbd::Model>(xpbd::compile(scene));
    xpbd_bullet::SystemSettings set;
    set.check_health = checks;
    if (!target) set.tolerance.penetration = 0;
    set.coloured = coloured;
    set.substeps = substeps;
    id = xw->add_system(model, xpbd::make_state(*model), set);
    for (int f = 0; f < 60; ++f) step();
  }
  ~Scene() {
    xw.reset();
    if (box) world.removeRigidBody(box.get());
  }
  void step() { world.stepSimulation(btScalar(1) / 60, 1, btScalar(1) / 60); }
};

void world_step(benchmark::State& state) {
  Scene s(state.range(0) != 0, false, false);
  for (auto _ : state) s.step();
}
BENCHMARK(world_step)->Arg(0)->Arg(1)->ArgName("checks");

void coloured_step(benchmark::State& state) {
  Scene s(state.range(0) != 0, false, false, true, int(state.range(1)));
  for (auto _ : state) s.step();
}
BENCHMARK(coloured_step)->ArgsProduct({{0, 1}, {1, 20}})->ArgNames({"checks", "substeps"});

void draped_step(benchmark::State& state) {
  Scene s(true, state.range(0) != 0, true);
  int resolved = 0, contacts = 0;
  for (auto _ : state) {
    s.step();
    resolved += s.xw->last_stats().resolved;
    contacts = int(s.xw->state(s.id).contacts.size());
  }
  state.counters["resolved"] = resolved;
  state.counters["contacts"] = contacts;
}
BENCHMARK(draped_step)->Arg(0)->Arg(1)->ArgName("target");

}  // namespace

BENCHMARK_MAIN();

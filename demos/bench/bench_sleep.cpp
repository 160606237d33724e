// The cost of a sleeping system (SystemSettings::sleep_speed).
//
// Scene: a static plane and a 32 x 32 cloth (1 m, 0.4 kg) lying on it, in a
// btDiscreteDynamicsWorld, 60 Hz, the default 10 substeps x 1 iteration.
// Each timed iteration is one stepSimulation call (one internal step):
//   world_step/no_system   the Bullet world alone (the plane): the floor;
//   world_step/asleep      with the cloth asleep (it fell asleep before timing);
//   world_step/awake       with the cloth awake (sleeping off).
// Compare the three within one run (the machine is shared): the sleeping
// system's cost is asleep - no_system, as a fraction of awake - no_system.
#include <benchmark/benchmark.h>
#include <btBulletDynamicsCommon.h>

#include <cstdio>
#include <cstdlib>
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
  btStaticPlaneShape plane{btVector3(0, 1, 0), 0};
  std::unique_ptr<btRigidBody> ground;
  std::unique_ptr<xpbd_bullet::XpbdWorld> xw;

  explicit Scene(int mode) {  // 0: no system, 1: asleep, 2: awake
    world.setGravity(btVector3(0, btScalar(-9.81), 0));
    ground = std::make_unique<btRigidBody>(btRigidBody::btRigidBodyConstructionInfo(0, nullptr, &plane));
    world.addRigidBody(ground.get());
    if (mode == 0) return;
    xw = std::make_unique<xpbd_bullet::XpbdWorld>(world);
    xpbd::SceneDesc scene;
    xpbd::ClothGridDesc c;
    c.nx = c.ny = 32;
    c.mass = xpbd::Real(0.4);
    c.origin = xpbd::Vec3(xpbd::Real(-0.5), xpbd_bullet::ContactSettings{}.thickness, xpbd::Real(-0.5));
    c.u = xpbd::Vec3::UnitX();
    c.v = xpbd::Vec3::UnitZ();
    xpbd::add_cloth_grid(scene, c);
    auto model = std::make_shared<const xpbd::Model>(xpbd::compile(scene));
    xpbd_bullet::SystemSettings set;
    if (mode == 1) set.sleep_speed = xpbd::Real(0.01), set.sleep_time = xpbd::Real(0.2);
    const auto id = xw->add_system(model, xpbd::make_state(*model), set);
    for (int f = 0; f < 120; ++f) step();
    if (mode == 1 && !xw->sleeping(id)) {
      std::fprintf(stderr, "bench_sleep: the cloth did not fall asleep in 2 s\n");
      std::exit(1);
    }
  }
  void step() { world.stepSimulation(btScalar(1) / 60, 1, btScalar(1) / 60); }
};

void world_step(benchmark::State& state) {
  Scene s(static_cast<int>(state.range(0)));
  for (auto _ : state) s.step();
}
BENCHMARK(world_step)->Arg(0)->Arg(1)->Arg(2)->ArgName("mode(0=no_system,1=asleep,2=awake)");

}  // namespace

BENCHMARK_MAIN();

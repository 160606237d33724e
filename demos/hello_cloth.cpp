// hello_cloth: the smallest complete program with xpbd_bullet; copy it to start.
//
// A Bullet world (btDiscreteDynamicsWorld) with a static ground plane and a
// dynamic 1 kg box resting on it. A 0.4 m x 0.4 m cloth of 0.1 kg starts
// flat, sticking out from the top edge of the box, and is attached to the box
// at its two top corners on that side (XpbdWorld::attach, two-way): it falls,
// hangs from the edge and lies on the ground. The program steps 2 s at
// 60 Hz, prints the box's height and the cloth's lowest point every 0.5 s,
// and exits with 1 if a position is not finite or the cloth's step failed,
// 0 after printing "hello_cloth: ok".
//
// Built in the source tree as the target hello_cloth (XPBD_BUILD_DEMOS=ON),
// and against the installed package by tests/consumer/CMakeLists.txt
// (docs/embedding.md).
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "xpbd/xpbd.hpp"
#include "xpbd_bullet/world.hpp"

int main() {
  // The Bullet world, gravity along -y (m/s^2).
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
  world.setGravity(btVector3(0, btScalar(-9.81), 0));

  // Static ground: the plane y = 0.
  btStaticPlaneShape ground_shape(btVector3(0, 1, 0), 0);
  btRigidBody ground(btRigidBody::btRigidBodyConstructionInfo(0, nullptr, &ground_shape));
  world.addRigidBody(&ground);

  // Dynamic box: 1 kg, 0.4 x 0.2 x 0.4 m, resting on the ground (centre y = 0.1 m).
  const btVector3 half(btScalar(0.2), btScalar(0.1), btScalar(0.2));
  btBoxShape box_shape(half);
  btVector3 inertia(0, 0, 0);
  box_shape.calculateLocalInertia(1, inertia);
  btDefaultMotionState box_motion(btTransform(btQuaternion::getIdentity(), btVector3(0, btScalar(0.1), 0)));
  btRigidBody box(btRigidBody::btRigidBodyConstructionInfo(1, &box_motion, &box_shape, inertia));
  box.setActivationState(DISABLE_DEACTIVATION);
  world.addRigidBody(&box);

  // The cloth: 9 x 9 particles in the plane of the box's top face (y = 0.2 m),
  // from its edge z = 0.2 m outwards. Particle (i, 0) lies on that edge.
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc cloth;
  cloth.nx = cloth.ny = 9;
  cloth.size_u = cloth.size_v = xpbd::Real(0.4);                        // m
  cloth.origin = xpbd::Vec3(xpbd::Real(-0.2), xpbd::Real(0.2), xpbd::Real(0.2));  // m
  cloth.u = xpbd::Vec3::UnitX();
  cloth.v = xpbd::Vec3::UnitZ();
  cloth.mass = xpbd::Real(0.1);                                         // kg
  cloth.stretch.compliance = xpbd::Real(1e-6);                          // m/N
  const xpbd::ClothGrid grid = xpbd::add_cloth_grid(scene, cloth);
  auto model = std::make_shared<const xpbd::Model>(xpbd::compile(scene));

  // XPBD inside the Bullet world: 10 substeps per Bullet step (the default).
  // The XpbdWorld is declared after the bodies, so it is destroyed first.
  xpbd_bullet::XpbdWorld xpbd_world(world);
  const xpbd_bullet::SystemId id = xpbd_world.add_system(model, xpbd::make_state(*model));
  // The corners (0, 0) and (8, 0) to the box's top corners at z = +0.2 m
  // (points in the box's centre-of-mass frame).
  xpbd_world.attach(id, grid.at(0, 0), &box, btVector3(-half.x(), half.y(), half.z()));
  xpbd_world.attach(id, grid.at(cloth.nx - 1, 0), &box, btVector3(half.x(), half.y(), half.z()));

  bool ok = true;
  const int frames = 120;  // 2 s at 60 Hz
  for (int frame = 1; frame <= frames && ok; ++frame) {
    world.stepSimulation(btScalar(1) / 60, 1, btScalar(1) / 60);
    const btVector3 box_at = box.getCenterOfMassPosition();
    double lowest = std::numeric_limits<double>::infinity();
    for (const xpbd::Vec3& x : xpbd_world.state(id).x) {
      if (!x.allFinite()) ok = false;
      lowest = std::min(lowest, double(x.y()));
    }
    if (!std::isfinite(box_at.x()) || !std::isfinite(box_at.y()) || !std::isfinite(box_at.z()))
      ok = false;
    if (!xpbd_world.error(id).empty()) {
      std::printf("hello_cloth: the cloth's step failed: %s\n", xpbd_world.error(id).c_str());
      ok = false;
    }
    if (frame % 30 == 0 || !ok)
      std::printf("t = %.2f s  box centre y = %.4f m  cloth lowest y = %.4f m\n", frame / 60.0,
                  double(box_at.y()), lowest);
  }

  world.removeRigidBody(&box);
  world.removeRigidBody(&ground);
  if (!ok) {
    std::printf("hello_cloth: FAILED (a position is not finite or the step failed)\n");
    return 1;
  }
  std::printf("hello_cloth: ok\n");
  return 0;
}

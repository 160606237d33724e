// A shared library (an application's plugin) that embeds a cloth: built by
// tests/consumer/CMakeLists.txt to check that the installed libraries can
// be linked into one (they are position-independent code).
#include <btBulletDynamicsCommon.h>

#include <memory>

#include "xpbd/xpbd.hpp"
#include "xpbd_bullet/world.hpp"

extern "C" int hello_plugin_particles(btDiscreteDynamicsWorld* world) {
  xpbd_bullet::XpbdWorld xw(*world);
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc d;
  d.nx = d.ny = 4;
  xpbd::add_cloth_grid(scene, d);
  auto model = std::make_shared<const xpbd::Model>(xpbd::compile(scene));
  const auto id = xw.add_system(model, xpbd::make_state(*model));
  world->stepSimulation(btScalar(1) / 60, 1, btScalar(1) / 60);
  return static_cast<int>(xw.state(id).x.size());
}

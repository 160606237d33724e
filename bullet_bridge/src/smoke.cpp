#include "xpbd_bullet/smoke.hpp"

#include <btBulletDynamicsCommon.h>

#include <type_traits>

#include "xpbd/types.hpp"

namespace xpbd_bullet {

double drop_sphere_on_ground(double y0, double seconds) {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
  world.setGravity(btVector3(0, -9.81, 0));

  btStaticPlaneShape ground_shape(btVector3(0, 1, 0), 0);
  btRigidBody ground(btRigidBody::btRigidBodyConstructionInfo(0, nullptr, &ground_shape));
  world.addRigidBody(&ground);

  btSphereShape sphere_shape(1);
  btVector3 inertia;
  sphere_shape.calculateLocalInertia(1, inertia);
  btDefaultMotionState motion(btTransform(btQuaternion::getIdentity(), btVector3(0, btScalar(y0), 0)));
  btRigidBody sphere(btRigidBody::btRigidBodyConstructionInfo(1, &motion, &sphere_shape, inertia));
  world.addRigidBody(&sphere);

  const int steps = static_cast<int>(seconds * 60);
  for (int i = 0; i < steps; ++i) world.stepSimulation(btScalar(1) / 60, 1, btScalar(1) / 60);
  const double y = sphere.getCenterOfMassPosition().y();
  world.removeRigidBody(&sphere);
  world.removeRigidBody(&ground);
  return y;
}

bool bullet_scalar_matches() { return std::is_same_v<btScalar, xpbd::Real>; }

}  // namespace xpbd_bullet

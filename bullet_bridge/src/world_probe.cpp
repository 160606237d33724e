// The first step of a coupled body: what Bullet's contacts will hold up.
//
// XPBD solves a coupled body before Bullet's solver, against the acceleration
// Bullet's own contacts gave it in the previous step (XpbdWorld::Predicted).
// In the first step it is coupled there is no previous step: a tray hanging
// from compliant attachments with boxes stacked on it was solved as if it
// carried nothing (its springs, set for the whole stack, lift it at 3 g:
// about 4 mm over the step, worked out), and the stack then rang on the
// springs for as long as the run went (0.85 mm at 30 solver iterations;
// docs/bullet-bridge.md section 2, "The first coupled step").
//
// The probe asks Bullet's own constraint solver once: collision detection at
// the bodies' current poses, then one solve of every contact manifold with
// the probed bodies held fixed (their linear and angular factors zero). The
// impulses Bullet's contacts put on a fixed body are the load it must carry;
// divided by its mass and dt they are the first step's contact acceleration.
// Everything the solve writes (every body's velocities and pose, the contact
// points' impulses, the solver's random seed) is put back, so the real step
// starts as it would have. Joints are not probed: their impulses on a body
// with zero factors are not reported (btJointFeedback scales them by the
// factor), so a Bullet joint hanging from a coupled body starts from zero.
#include <vector>

#include "world_impl.hpp"

#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>

namespace xpbd_bullet::detail {

namespace {

bool probed(const std::vector<ProbeLoad>& bodies, const btCollisionObject* o) {
  for (const ProbeLoad& p : bodies)
    if (p.body == o) return true;
  return false;
}

struct SavedBody {
  btRigidBody* body;
  btVector3 v, w;
  btTransform pose;
  int companion;
};

struct SavedPoint {
  btScalar normal, lateral1, lateral2;
  btVector3 dir1, dir2;
};

}  // namespace

void probe_loads(btDiscreteDynamicsWorld& world, std::vector<ProbeLoad>& bodies, btScalar dt) {
  for (ProbeLoad& p : bodies) p.accel = p.ang_accel = btVector3(0, 0, 0);
  if (bodies.empty() || !(dt > 0)) return;
  world.performDiscreteCollisionDetection();
  btDispatcher* disp = world.getDispatcher();
  std::vector<btPersistentManifold*> manifolds;
  bool touched = false;
  for (int m = 0; m < disp->getNumManifolds(); ++m) {
    btPersistentManifold* pm = disp->getManifoldByIndexInternal(m);
    const btCollisionObject *a = pm->getBody0(), *b = pm->getBody1();
    if (pm->getNumContacts() == 0 || !disp->needsResponse(a, b)) continue;
    if (!a->isActive() && !b->isActive()) continue;  // as Bullet's islands
    manifolds.push_back(pm);
    touched = touched || probed(bodies, a) || probed(bodies, b);
  }
  if (!touched) return;

  // Save what the solve writes.
  std::vector<SavedBody> saved;
  std::vector<btCollisionObject*> solver_bodies;
  const btCollisionObjectArray& objects = world.getCollisionObjectArray();
  for (int i = 0; i < objects.size(); ++i) {
    btRigidBody* rb = btRigidBody::upcast(objects[i]);
    if (!rb || rb->isStaticObject()) continue;
    saved.push_back(SavedBody{rb, rb->getLinearVelocity(), rb->getAngularVelocity(), rb->getWorldTransform(),
                              rb->getCompanionId()});
    solver_bodies.push_back(rb);
  }
  std::vector<SavedPoint> points;
  for (btPersistentManifold* pm : manifolds)
    for (int k = 0; k < pm->getNumContacts(); ++k) {
      const btManifoldPoint& pt = pm->getContactPoint(k);
      points.push_back(SavedPoint{pt.m_appliedImpulse, pt.m_appliedImpulseLateral1, pt.m_appliedImpulseLateral2,
                                  pt.m_lateralFrictionDir1, pt.m_lateralFrictionDir2});
    }
  // Held: zero factors, and no forces (Bullet's solver adds a body's
  // forces to its velocity whatever its factors).
  struct Held {
    btVector3 linear, angular, force, torque;
  };
  std::vector<Held> held;
  for (ProbeLoad& p : bodies) {
    btRigidBody* rb = p.body;
    held.push_back(Held{rb->getLinearFactor(), rb->getAngularFactor(), rb->getTotalForce(), rb->getTotalTorque()});
    rb->setLinearFactor(btVector3(0, 0, 0));
    rb->setAngularFactor(btVector3(0, 0, 0));
    rb->clearForces();
  }
  btConstraintSolver* solver = world.getConstraintSolver();
  auto* si = solver->getSolverType() == BT_SEQUENTIAL_IMPULSE_SOLVER
                 ? static_cast<btSequentialImpulseConstraintSolver*>(solver)
                 : nullptr;
  const unsigned long seed = si ? si->getRandSeed() : 0;
  btContactSolverInfo& info = world.getSolverInfo();
  const btScalar info_dt = info.m_timeStep;
  info.m_timeStep = dt;

  solver->prepareSolve(int(solver_bodies.size()), int(manifolds.size()));
  solver->solveGroup(solver_bodies.data(), int(solver_bodies.size()), manifolds.data(), int(manifolds.size()),
                     nullptr, 0, info, world.getDebugDrawer(), disp);
  solver->allSolved(info, world.getDebugDrawer());

  // The load: the contacts' impulses on each probed body (Bullet's solver
  // pushes body 0 along +normalWorldOnB and the friction directions, body 1
  // the other way), through the body's own factors and inverse mass.
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    ProbeLoad& p = bodies[i];
    // applyCentralForce and applyTorque scale by the factors: at one, the
    // forces come back as they were, bit for bit.
    p.body->setLinearFactor(btVector3(1, 1, 1));
    p.body->setAngularFactor(btVector3(1, 1, 1));
    p.body->applyCentralForce(held[i].force);
    p.body->applyTorque(held[i].torque);
    p.body->setLinearFactor(held[i].linear);
    p.body->setAngularFactor(held[i].angular);
    btVector3 j_sum(0, 0, 0), l_sum(0, 0, 0);
    const btVector3 com = p.body->getCenterOfMassPosition();
    for (const btPersistentManifold* pm : manifolds) {
      const bool is_a = pm->getBody0() == p.body, is_b = pm->getBody1() == p.body;
      if (!is_a && !is_b) continue;
      const btCollisionObject* other = is_a ? pm->getBody1() : pm->getBody0();
      if (p.skip_static && other->isStaticObject() && !other->isKinematicObject()) continue;
      for (int k = 0; k < pm->getNumContacts(); ++k) {
        const btManifoldPoint& pt = pm->getContactPoint(k);
        btVector3 j = pt.m_normalWorldOnB * pt.m_appliedImpulse + pt.m_lateralFrictionDir1 * pt.m_appliedImpulseLateral1 +
                      pt.m_lateralFrictionDir2 * pt.m_appliedImpulseLateral2;
        if (!is_a) j = -j;
        const btVector3 r = (is_a ? pt.getPositionWorldOnA() : pt.getPositionWorldOnB()) - com;
        j_sum += j;
        l_sum += r.cross(j);
      }
    }
    p.accel = p.body->getLinearFactor() * j_sum * (p.body->getInvMass() / dt);
    p.ang_accel = p.body->getAngularFactor() * (p.body->getInvInertiaTensorWorld() * l_sum) / dt;
  }

  // Put back what the solve wrote.
  info.m_timeStep = info_dt;
  if (si) si->setRandSeed(seed);
  for (const SavedBody& s : saved) {
    s.body->setLinearVelocity(s.v);
    s.body->setAngularVelocity(s.w);
    s.body->setWorldTransform(s.pose);
    s.body->setCompanionId(s.companion);
  }
  std::size_t n = 0;
  for (btPersistentManifold* pm : manifolds)
    for (int k = 0; k < pm->getNumContacts(); ++k, ++n) {
      btManifoldPoint& pt = pm->getContactPoint(k);
      pt.m_appliedImpulse = points[n].normal;
      pt.m_appliedImpulseLateral1 = points[n].lateral1;
      pt.m_appliedImpulseLateral2 = points[n].lateral2;
      pt.m_lateralFrictionDir1 = points[n].dir1;
      pt.m_lateralFrictionDir2 = points[n].dir2;
    }
}

}  // namespace xpbd_bullet::detail

#pragma once
// Shared pieces of the integration tests of the Bullet bridge (XpbdWorld in a
// real Bullet world): a Bullet world that owns its bodies and shapes, and
// small measurements of particle systems. Nothing here computes an expected
// value: every reference is a closed form written out in the test.
#include <gtest/gtest.h>

#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

#include "xpbd/xpbd.hpp"
#include "xpbd_bullet/world.hpp"

namespace xpbd_bullet::test {

using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;

inline constexpr Real kPi = std::numbers::pi_v<Real>;
inline constexpr Real kG = Real(9.81);  // m/s^2, gravity magnitude used by every test
inline constexpr Real kDt = Real(1) / Real(60);  // s, Bullet's fixed internal step
// Machine epsilon of the build's scalar: round-off tolerances are written as
// multiples of it, so that they mean the same in the float and double builds.
inline constexpr Real kEps = std::numeric_limits<Real>::epsilon();

inline btVector3 bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }
inline Vec3 vec(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }

// A Bullet world (btDiscreteDynamicsWorld, or btSoftRigidDynamicsWorld with
// soft = true) that owns the rigid bodies and shapes added through it.
// Declare an XpbdWorld *after* it, so that the XpbdWorld (which removes its
// action from the world) is destroyed first.
class BulletWorld {
 public:
  explicit BulletWorld(const Vec3& gravity = Vec3(0, -kG, 0), bool soft = false) {
    if (soft)
      config_ = std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>();
    else
      config_ = std::make_unique<btDefaultCollisionConfiguration>();
    dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
    broadphase_ = std::make_unique<btDbvtBroadphase>();
    solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
    if (soft) {
      auto w = std::make_unique<btSoftRigidDynamicsWorld>(dispatcher_.get(), broadphase_.get(),
                                                          solver_.get(), config_.get());
      soft_ = w.get();
      world_ = std::move(w);
      // btSoftBody reads its own copy of gravity (docs/design.md section 3).
      soft_info_ = &soft_->getWorldInfo();
      soft_info_->m_gravity = bt(gravity);
      soft_info_->m_sparsesdf.Initialize();
    } else {
      world_ = std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), broadphase_.get(),
                                                         solver_.get(), config_.get());
    }
    world_->setGravity(bt(gravity));
  }

  ~BulletWorld() {
    for (auto& b : soft_bodies_) soft_->removeSoftBody(b.get());
    for (auto& b : bodies_) world_->removeRigidBody(b.body.get());
  }
  BulletWorld(const BulletWorld&) = delete;
  BulletWorld& operator=(const BulletWorld&) = delete;

  btDiscreteDynamicsWorld& world() { return *world_; }
  btSoftRigidDynamicsWorld& soft_world() { return *soft_; }
  btSoftBodyWorldInfo& soft_info() { return *soft_info_; }

  // Adds a rigid body of `mass` kg (0 = static) with centre of mass at `pose`,
  // taking ownership of `shape`. Sleeping is turned off, so that Bullet
  // integrates every dynamic body every step (docs/design.md section 5).
  btRigidBody* add_body(btCollisionShape* shape, Real mass, const btTransform& pose,
                        const Vec3& velocity = Vec3::Zero(), Real friction = 1,
                        Real restitution = 0) {
    shapes_.emplace_back(shape);
    btVector3 inertia(0, 0, 0);
    if (mass > 0) shape->calculateLocalInertia(mass, inertia);
    Owned o;
    o.motion = std::make_unique<btDefaultMotionState>(pose);
    btRigidBody::btRigidBodyConstructionInfo info(mass, o.motion.get(), shape, inertia);
    info.m_friction = friction;
    info.m_restitution = restitution;
    o.body = std::make_unique<btRigidBody>(info);
    o.body->setLinearVelocity(bt(velocity));
    if (mass > 0) o.body->setActivationState(DISABLE_DEACTIVATION);
    world_->addRigidBody(o.body.get());
    bodies_.push_back(std::move(o));
    return bodies_.back().body.get();
  }

  btRigidBody* add_static_box(const Vec3& half, const btTransform& pose, Real friction = 1) {
    return add_body(new btBoxShape(bt(half)), 0, pose, Vec3::Zero(), friction);
  }
  btRigidBody* add_static_sphere(Real radius, const Vec3& centre, Real friction = 1) {
    return add_body(new btSphereShape(radius), 0, at(centre), Vec3::Zero(), friction);
  }

  // Adds a btSoftBody to the (soft) world, taking ownership.
  btSoftBody* add_soft_body(btSoftBody* body) {
    soft_bodies_.emplace_back(body);
    soft_->addSoftBody(body);
    return body;
  }

  // Removes the body from the world and deletes it (its shape stays owned).
  void remove_and_delete(btRigidBody* body) {
    auto it = std::find_if(bodies_.begin(), bodies_.end(),
                           [&](const Owned& o) { return o.body.get() == body; });
    ASSERT_NE(it, bodies_.end());
    world_->removeRigidBody(body);
    bodies_.erase(it);
  }

  // One Bullet internal step of kDt (or dt): stepSimulation(dt, 1, dt) runs
  // exactly one internal step per call.
  void step(Real dt = kDt) { world_->stepSimulation(dt, 1, dt); }

  static btTransform at(const Vec3& x) { return btTransform(btQuaternion::getIdentity(), bt(x)); }

 private:
  struct Owned {
    std::unique_ptr<btDefaultMotionState> motion;
    std::unique_ptr<btRigidBody> body;
  };
  std::unique_ptr<btCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btBroadphaseInterface> broadphase_;
  std::unique_ptr<btConstraintSolver> solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  btSoftRigidDynamicsWorld* soft_ = nullptr;
  btSoftBodyWorldInfo* soft_info_ = nullptr;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<Owned> bodies_;
  std::vector<std::unique_ptr<btSoftBody>> soft_bodies_;
};

// A compiled particle system, ready for XpbdWorld::add_system.
struct System {
  std::shared_ptr<const xpbd::Model> model;
  xpbd::State state;
};
inline System make_system(const xpbd::SceneDesc& scene) {
  auto m = std::make_shared<xpbd::Model>(xpbd::compile(scene));
  System s{m, xpbd::make_state(*m)};
  return s;
}

// A 24 x 24 cloth of 0.4 kg, size_u (along x) by size_v (along z) m,
// centred on the origin and lying flat at height y (the contact thickness
// above a ground plane at 0).
inline System lying_cloth(Real size_u, Real size_v, Real y) {
  xpbd::SceneDesc scene;
  xpbd::ClothGridDesc c;
  c.nx = c.ny = 24;
  c.size_u = size_u;
  c.size_v = size_v;
  c.mass = Real(0.4);
  c.origin = Vec3(-size_u / 2, y, -size_v / 2);
  c.u = Vec3::UnitX();
  c.v = Vec3::UnitZ();
  xpbd::add_cloth_grid(scene, c);
  return make_system(scene);
}

// A 4-particle rope, 0.1 m links, 0.04 kg, pinned at its first particle at
// (0, 2, 0) and lying along +x: stepped, its free end falls.
inline System hanging_rope() {
  xpbd::SceneDesc scene;
  xpbd::RopeDesc r;
  r.n = 4;
  r.start = Vec3(0, 2, 0);
  r.dir = Vec3(1, 0, 0);
  r.spacing = Real(0.1);
  r.mass = Real(0.04);
  r.pin_first = true;
  xpbd::add_rope(scene, r);
  return make_system(scene);
}

// Centre of mass (m) of the movable particles of a system.
inline Vec3 centre_of_mass(const xpbd::Model& m, const xpbd::State& s) {
  Vec3 c = Vec3::Zero();
  Real total = 0;
  for (Index i = 0; i < m.num_particles(); ++i) {
    if (m.inv_mass[i] == Real(0)) continue;
    const Real mass = Real(1) / m.inv_mass[i];
    c += mass * s.x[i];
    total += mass;
  }
  return c / total;
}

// Linear momentum (kg m/s) of a Bullet rigid body.
inline Vec3 momentum(const btRigidBody& b) { return vec(b.getLinearVelocity()) / b.getInvMass(); }

}  // namespace xpbd_bullet::test

#pragma once
// RigidWorld: the Bullet world of a SceneSpec (scene_spec.hpp) with its rigid
// bodies, owned in one place. Used by the scene runner for all three solvers:
// a btDiscreteDynamicsWorld for XPBD/PBD, a btSoftRigidDynamicsWorld for
// btSoftBody, built from the same RigidSpecs.
//
// Shapes (ShapeSpec): sphere btSphereShape; box btBoxShape; capsule
// btCapsuleShape (along the local y axis, `height` between the cap centres);
// cylinder btCylinderShape (along y, total height `height`); plane
// btStaticPlaneShape (normal normalised, `offset` = signed distance of the
// plane from the body origin along it, m); convex hull btConvexHullShape
// (Bullet's default collision margin of 0.04 m, which rounds and grows the
// hull, as Bullet's own collisions see it); mesh btBvhTriangleMeshShape over
// a btTriangleMesh copy of body_mesh(shape, base_dir) (scene_spec.hpp: the
// OBJ file or the inline vertices, times `scale`).
//
// Bodies: mass 0 = static, kinematic = moved by its velocity and angular
// velocity (constant, world frame) whatever its mass, otherwise dynamic
// with the shape's inertia (calculateLocalInertia, about the body origin,
// which is the centre of mass) and Bullet's linear/angular damping as given
// (0 by default). Sleeping is off for every movable body
// (DISABLE_DEACTIVATION), so runs are deterministic. The body frame's
// origin is the centre of mass (RigidSpec::position).
#include <btBulletDynamicsCommon.h>

#include <array>
#include <filesystem>
#include <memory>
#include <vector>

#include "demos/scene_spec.hpp"

class btSoftRigidDynamicsWorld;

namespace xpbd_demos {

// Pose of one rigid body: centre of mass (m, world) and orientation as a unit
// quaternion (w, x, y, z), body to world, as in RigidSpec.
struct BodyPose {
  xpbd::Vec3 position = xpbd::Vec3::Zero();
  std::array<xpbd::Real, 4> orientation{1, 0, 0, 0};
};

// Checks one RigidSpec; throws xpbd::SceneError naming "bodies[<index>].<field>"
// and the value. Does not read mesh files (RigidWorld does).
void validate_body(const RigidSpec& b, int index);

class RigidWorld {
 public:
  // Builds the world (soft = true: a btSoftRigidDynamicsWorld whose
  // btSoftBodyWorldInfo has the same gravity and an initialised sparse SDF)
  // and adds the bodies in order. Throws xpbd::SceneError for an invalid
  // body (validate_body) or an unreadable mesh file.
  RigidWorld(const std::vector<RigidSpec>& bodies, const xpbd::Vec3& gravity, bool soft,
             const std::filesystem::path& base_dir);
  ~RigidWorld();
  RigidWorld(const RigidWorld&) = delete;
  RigidWorld& operator=(const RigidWorld&) = delete;

  btDiscreteDynamicsWorld& world() { return *world_; }
  btSoftRigidDynamicsWorld* soft_world() { return soft_; }  // null unless soft
  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  btRigidBody& body(int i) { return *bodies_[static_cast<std::size_t>(i)].body; }
  const btRigidBody& body(int i) const { return *bodies_[static_cast<std::size_t>(i)].body; }
  bool is_dynamic(int i) const;  // mass > 0 and not kinematic

  // One Bullet internal step of h seconds: moves the kinematic bodies' target
  // poses by h (Bullet derives their velocity from it), then
  // stepSimulation(h, 1, h), which runs exactly one internal step.
  void step(xpbd::Real h);

  // Poses of all bodies, in SceneSpec order (out is resized).
  void poses(std::vector<BodyPose>& out) const;
  // True if every body's pose and velocities are finite.
  bool finite() const;

  // Smallest dimension of the bodies' convex features (m): sphere, capsule
  // and cylinder radii, half the cylinder height, the smallest box half
  // extent, the smallest half extent of a hull's bounding box; meshes count
  // as Bullet's soft-body triangle slabs (0.06 m); planes do not count (a
  // plane's distance is linear, exact at any voxel size). +infinity without
  // such bodies. Used to choose btSoftBody's sparse-SDF voxel size.
  xpbd::Real thinnest_feature() const { return thinnest_; }

 private:
  struct Body {
    std::unique_ptr<btCollisionShape> shape;
    std::unique_ptr<btTriangleMesh> mesh;  // owned triangle data of a mesh shape
    std::unique_ptr<btDefaultMotionState> motion;
    std::unique_ptr<btRigidBody> body;
    bool kinematic = false;
    bool dynamic = false;
    btVector3 v{0, 0, 0}, w{0, 0, 0};  // kinematic velocities (world)
    btTransform target;                // kinematic pose at the end of the current step
  };
  std::unique_ptr<btCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btBroadphaseInterface> broadphase_;
  std::unique_ptr<btConstraintSolver> solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  btSoftRigidDynamicsWorld* soft_ = nullptr;
  std::vector<Body> bodies_;
  xpbd::Real thinnest_;
};

}  // namespace xpbd_demos

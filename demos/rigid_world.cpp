#include "demos/rigid_world.hpp"

#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <LinearMath/btTransformUtil.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "xpbd/error.hpp"

namespace xpbd_demos {
namespace {

using xpbd::Real;
using xpbd::Vec3;

// Thickness Bullet gives a triangle of a concave shape when a btSoftBody
// collides with it (BT_SOFTBODY_TRIANGLE_EXTRUSION in
// btSoftBodyConcaveCollisionAlgorithm.cpp, not exported): each triangle
// becomes a hull extruded by this much to both sides.
constexpr Real kBulletTriangleSlab = Real(0.06);  // m

std::string num(double v) { return xpbd::format_value(v); }
std::string vec(const Vec3& v) { return xpbd::format_vec(v); }

btVector3 bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }

btQuaternion orientation(const RigidSpec& b) {
  const auto& q = b.orientation;  // (w, x, y, z), non-zero (validated)
  return btQuaternion(q[1], q[2], q[3], q[0]).normalized();
}

}  // namespace

void validate_body(const RigidSpec& b, int index) {
  const std::string at = "bodies[" + std::to_string(index) + "]";
  auto fail = [&](const std::string& field, const std::string& what) {
    throw xpbd::SceneError(at + "." + field + ": " + what);
  };
  auto positive = [&](const std::string& field, Real v) {
    if (!(v > Real(0)) || !std::isfinite(v)) fail(field, "must be finite and > 0, got " + num(v));
  };
  auto finite = [&](const std::string& field, const Vec3& v) {
    if (!v.allFinite()) fail(field, "must be finite, got " + vec(v));
  };
  const ShapeSpec& s = b.shape;
  switch (s.kind) {
    case ShapeKind::sphere: positive("shape.radius", s.radius); break;
    case ShapeKind::box:
      for (int a = 0; a < 3; ++a) positive("shape.half_extents", s.half_extents[a]);
      break;
    case ShapeKind::capsule:
      positive("shape.radius", s.radius);
      if (!(s.height >= Real(0)) || !std::isfinite(s.height))
        fail("shape.height", "must be finite and >= 0, got " + num(s.height));
      break;
    case ShapeKind::cylinder:
      positive("shape.radius", s.radius);
      positive("shape.height", s.height);
      break;
    case ShapeKind::plane:
      finite("shape.normal", s.normal);
      if (!(s.normal.norm() > Real(0))) fail("shape.normal", "must be non-zero");
      if (!std::isfinite(s.offset)) fail("shape.offset", "must be finite, got " + num(s.offset));
      break;
    case ShapeKind::convex_hull:
      if (s.points.size() < 4)
        fail("shape.points", "a convex hull needs at least 4 points, got " + std::to_string(s.points.size()));
      for (std::size_t k = 0; k < s.points.size(); ++k)
        finite("shape.points[" + std::to_string(k) + "]", s.points[k]);
      break;
    case ShapeKind::mesh: {
      positive("shape.scale", s.scale);
      const bool file = !s.mesh_file.empty();
      const bool inline_mesh = !s.vertices.empty() || !s.triangles.empty();
      if (file && inline_mesh)
        fail("shape.mesh_file", "give either mesh_file or vertices/triangles, not both");
      if (!file && !inline_mesh) fail("shape", "a mesh needs mesh_file or vertices and triangles");
      if (inline_mesh) {
        if (s.triangles.empty()) fail("shape.triangles", "a mesh needs at least one triangle");
        for (std::size_t k = 0; k < s.vertices.size(); ++k)
          finite("shape.vertices[" + std::to_string(k) + "]", s.vertices[k]);
        const int nv = static_cast<int>(s.vertices.size());
        for (std::size_t k = 0; k < s.triangles.size(); ++k)
          for (int c = 0; c < 3; ++c) {
            const int v = s.triangles[k][static_cast<std::size_t>(c)];
            if (v < 0 || v >= nv)
              fail("shape.triangles[" + std::to_string(k) + "][" + std::to_string(c) + "]",
                   "vertex index " + std::to_string(v) + " out of range [0, " + std::to_string(nv) + ")");
          }
      }
      break;
    }
  }
  if (!(b.mass >= Real(0)) || !std::isfinite(b.mass))
    fail("mass", "must be finite and >= 0, got " + num(b.mass));
  if (s.kind == ShapeKind::plane && (b.mass != Real(0) || b.kinematic))
    fail(b.kinematic ? "kinematic" : "mass", "a plane must be static (mass 0, not kinematic)");
  if (s.kind == ShapeKind::mesh && b.mass != Real(0))
    fail("mass", "a triangle mesh must be static or kinematic (mass 0), got " + num(b.mass));
  finite("position", b.position);
  const auto& q = b.orientation;
  const Real qn = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!std::isfinite(qn) || !(qn > Real(0)))
    fail("orientation", "must be a finite, non-zero quaternion (w, x, y, z), got (" + num(q[0]) + ", " +
                            num(q[1]) + ", " + num(q[2]) + ", " + num(q[3]) + ")");
  finite("velocity", b.velocity);
  finite("angular_velocity", b.angular_velocity);
  const bool is_static = b.mass == Real(0) && !b.kinematic;
  if (is_static && b.velocity != Vec3::Zero())
    fail("velocity", "a static body (mass 0, not kinematic) cannot move, got " + vec(b.velocity));
  if (is_static && b.angular_velocity != Vec3::Zero())
    fail("angular_velocity", "a static body (mass 0, not kinematic) cannot move, got " +
                                 vec(b.angular_velocity));
  if (!(b.friction >= Real(0)) || !std::isfinite(b.friction))
    fail("friction", "must be finite and >= 0, got " + num(b.friction));
  if (!(b.restitution >= Real(0) && b.restitution <= Real(1)))
    fail("restitution", "must be in [0, 1], got " + num(b.restitution));
  if (!(b.linear_damping >= Real(0) && b.linear_damping <= Real(1)))
    fail("linear_damping", "must be in [0, 1], got " + num(b.linear_damping));
  if (!(b.angular_damping >= Real(0) && b.angular_damping <= Real(1)))
    fail("angular_damping", "must be in [0, 1], got " + num(b.angular_damping));
}

RigidWorld::RigidWorld(const std::vector<RigidSpec>& bodies, const Vec3& gravity, bool soft,
                       const std::filesystem::path& base_dir)
    : thinnest_(std::numeric_limits<Real>::infinity()) {
  for (std::size_t i = 0; i < bodies.size(); ++i) validate_body(bodies[i], static_cast<int>(i));
  if (!gravity.allFinite()) throw xpbd::ConfigError("solver.gravity: must be finite, got " + vec(gravity));

  if (soft)
    config_ = std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>();
  else
    config_ = std::make_unique<btDefaultCollisionConfiguration>();
  dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
  broadphase_ = std::make_unique<btDbvtBroadphase>();
  solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
  if (soft) {
    // softBodySolver = nullptr: the world creates and owns a btDefaultSoftBodySolver.
    auto w = std::make_unique<btSoftRigidDynamicsWorld>(dispatcher_.get(), broadphase_.get(),
                                                        solver_.get(), config_.get(), nullptr);
    soft_ = w.get();
    world_ = std::move(w);
    // btSoftBody reads its own copy of gravity (docs/design.md section 3).
    btSoftBodyWorldInfo& info = soft_->getWorldInfo();
    info.m_gravity = bt(gravity);
    info.air_density = 0;  // no medium (aerodynamics are off anyway)
    info.water_density = 0;
    info.m_sparsesdf.Initialize();
  } else {
    world_ = std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), broadphase_.get(),
                                                       solver_.get(), config_.get());
  }
  world_->setGravity(bt(gravity));

  bodies_.reserve(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const RigidSpec& r = bodies[i];
    const ShapeSpec& s = r.shape;
    Body b;
    Real feature = std::numeric_limits<Real>::infinity();
    switch (s.kind) {
      case ShapeKind::sphere:
        b.shape = std::make_unique<btSphereShape>(s.radius);
        feature = s.radius;
        break;
      case ShapeKind::box:
        b.shape = std::make_unique<btBoxShape>(bt(s.half_extents));
        feature = s.half_extents.minCoeff();
        break;
      case ShapeKind::capsule:
        b.shape = std::make_unique<btCapsuleShape>(s.radius, s.height);
        feature = s.radius;
        break;
      case ShapeKind::cylinder:
        b.shape = std::make_unique<btCylinderShape>(btVector3(s.radius, s.height / 2, s.radius));
        feature = std::min(s.radius, s.height / 2);
        break;
      case ShapeKind::plane: {
        const Vec3 n = s.normal.normalized();
        b.shape = std::make_unique<btStaticPlaneShape>(bt(n), s.offset);
        // No limit: the distance to a plane is linear, which the SDF's
        // trilinear interpolation represents exactly at any voxel size.
        break;
      }
      case ShapeKind::convex_hull: {
        auto hull = std::make_unique<btConvexHullShape>();
        Vec3 lo = s.points[0], hi = s.points[0];
        for (const Vec3& p : s.points) {
          hull->addPoint(bt(p), false);
          lo = lo.cwiseMin(p);
          hi = hi.cwiseMax(p);
        }
        hull->recalcLocalAabb();
        b.shape = std::move(hull);
        feature = std::max((hi - lo).minCoeff() / 2, Real(b.shape->getMargin()));
        break;
      }
      case ShapeKind::mesh: {
        // The shape's vertices (scale applied) and triangles, from its OBJ
        // file or inline (scene_spec.hpp).
        xpbd::TriangleMesh m;
        try {
          m = body_mesh(s, base_dir);
        } catch (const xpbd::SceneError& e) {
          throw xpbd::SceneError("bodies[" + std::to_string(i) + "]." + e.what());
        }
        b.mesh = std::make_unique<btTriangleMesh>(true, false);
        for (const Vec3& v : m.positions) b.mesh->findOrAddVertex(bt(v), false);
        for (const auto& t : m.triangles) b.mesh->addTriangleIndices(t[0], t[1], t[2]);
        b.shape = std::make_unique<btBvhTriangleMeshShape>(b.mesh.get(), true);
        feature = kBulletTriangleSlab;
        break;
      }
    }
    thinnest_ = std::min(thinnest_, feature);

    b.kinematic = r.kinematic;
    b.dynamic = !r.kinematic && r.mass > Real(0);
    const Real mass = b.dynamic ? r.mass : Real(0);
    btVector3 inertia(0, 0, 0);
    if (b.dynamic) b.shape->calculateLocalInertia(mass, inertia);
    const btTransform pose(orientation(r), bt(r.position));
    b.motion = std::make_unique<btDefaultMotionState>(pose);
    btRigidBody::btRigidBodyConstructionInfo info(mass, b.motion.get(), b.shape.get(), inertia);
    info.m_friction = r.friction;
    info.m_restitution = r.restitution;
    info.m_linearDamping = r.linear_damping;
    info.m_angularDamping = r.angular_damping;
    b.body = std::make_unique<btRigidBody>(info);
    if (b.kinematic) {
      b.body->setCollisionFlags(b.body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
      b.v = bt(r.velocity);
      b.w = bt(r.angular_velocity);
      b.target = pose;
    }
    if (b.dynamic) {
      b.body->setLinearVelocity(bt(r.velocity));
      b.body->setAngularVelocity(bt(r.angular_velocity));
    }
    if (b.dynamic || b.kinematic) b.body->setActivationState(DISABLE_DEACTIVATION);
    world_->addRigidBody(b.body.get());
    bodies_.push_back(std::move(b));
  }
}

RigidWorld::~RigidWorld() {
  for (auto& b : bodies_) world_->removeRigidBody(b.body.get());
}

bool RigidWorld::is_dynamic(int i) const { return bodies_[static_cast<std::size_t>(i)].dynamic; }

void RigidWorld::step(Real h) {
  for (Body& b : bodies_) {
    if (!b.kinematic) continue;
    // Bullet's kinematic bodies follow their motion state: saveKinematicState
    // reads the pose at the end of the step from it and sets the velocity to
    // (end - start) / h, so the body moves with (v, w) during the step.
    btTransform next;
    btTransformUtil::integrateTransform(b.target, b.v, b.w, h, next);
    b.target = next;
    b.motion->setWorldTransform(next);
  }
  world_->stepSimulation(h, 1, h);
}

void RigidWorld::poses(std::vector<BodyPose>& out) const {
  out.resize(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const btTransform& t = bodies_[i].body->getCenterOfMassTransform();
    const btQuaternion q = t.getRotation();
    out[i].position = Vec3(t.getOrigin().x(), t.getOrigin().y(), t.getOrigin().z());
    out[i].orientation = {q.w(), q.x(), q.y(), q.z()};
  }
}

bool RigidWorld::finite() const {
  auto ok = [](const btVector3& v) {
    return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
  };
  for (const Body& b : bodies_) {
    const btTransform& t = b.body->getCenterOfMassTransform();
    const btQuaternion q = t.getRotation();
    if (!ok(t.getOrigin()) || !std::isfinite(q.w()) || !ok(btVector3(q.x(), q.y(), q.z())) ||
        !ok(b.body->getLinearVelocity()) || !ok(b.body->getAngularVelocity()))
      return false;
  }
  return true;
}

}  // namespace xpbd_demos

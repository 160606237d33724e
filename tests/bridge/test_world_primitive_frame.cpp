// A particle's contact with a primitive shape (sphere, box, capsule,
// cylinder, plane) that is not swept is found in the shape's own frame, and
// keeps that frame's point and normal (world_contacts.cpp,
// particle_contacts_of; docs/search-costs.md). The reference is the same
// shape as the only child of a compound, at the identity: the narrowphase
// answers a compound through its general path, which takes the point and
// normal to world coordinates and back into the body's frame, as every
// shape took before. Both must give the same contacts (particle, body,
// thickness, friction, restitution, compliance), with points and normals
// equal up to that round trip's round-off.
#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "../integration/support.hpp"

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using namespace xpbd_bullet::test;
using xpbd_bullet::SystemSettings;
using xpbd_bullet::XpbdWorld;

// One world: the shape alone at `pose`, or as a compound's only child at
// the identity; free particles at rest at `points`; no gravity, no refresh
// inside the step (so every contact is the one found before it).
struct World {
  std::unique_ptr<btCollisionShape> child;  // a compound's child (it does not own it); outlives bw
  BulletWorld bw{Vec3::Zero()};
  std::unique_ptr<XpbdWorld> xw;
  xpbd_bullet::SystemId id;

  World(btCollisionShape* shape, const btTransform& pose, bool wrapped, const std::vector<Vec3>& points) {
    if (wrapped) {
      child.reset(shape);
      auto* compound = new btCompoundShape();
      compound->addChildShape(btTransform::getIdentity(), child.get());
      bw.add_body(compound, 0, pose);
    } else {
      bw.add_body(shape, 0, pose);
    }
    xw = std::make_unique<XpbdWorld>(bw.world());
    SystemSettings set;
    set.contacts.refresh = false;
    xpbd::SceneDesc scene;
    for (const Vec3& p : points) {
      scene.positions.push_back(p);
      scene.masses.push_back(Real(0.01));
      scene.velocities.push_back(Vec3::Zero());
      scene.radii.push_back(Real(0.003));
    }
    const System s = make_system(scene);
    id = xw->add_system(s.model, s.state, set);
  }
};

TEST(WorldContacts, PrimitiveInItsOwnFrameMatchesTheGeneralPath) {
  struct Case {
    std::string name;
    std::function<btCollisionShape*()> make;
    btTransform pose;
    Vec3 lo, hi;  // where the particles are scattered (world)
  };
  const btQuaternion turned(btVector3(1, 2, 3).normalized(), Real(0.7));
  const auto box_around = [](const Vec3& c, Real h) {
    return std::pair<Vec3, Vec3>{c - Vec3::Constant(h), c + Vec3::Constant(h)};
  };
  std::vector<Case> cases;
  const auto add = [&](const std::string& name, std::function<btCollisionShape*()> make, const Vec3& at, Real h) {
    const auto [lo, hi] = box_around(at, h);
    cases.push_back({name, std::move(make), btTransform(turned, bt(at)), lo, hi});
  };
  add("box", [] { return new btBoxShape(btVector3(Real(0.2), Real(0.1), Real(0.15))); }, Vec3(Real(0.3), 1, -2),
      Real(0.28));
  add("sphere", [] { return new btSphereShape(Real(0.2)); }, Vec3(-1, Real(0.5), Real(0.2)), Real(0.23));
  add("capsule", [] { return new btCapsuleShapeZ(Real(0.08), Real(0.3)); }, Vec3(2, Real(0.1), 1), Real(0.26));
  add("cylinder", [] { return new btCylinderShapeX(btVector3(Real(0.2), Real(0.1), Real(0.1))); },
      Vec3(0, -1, Real(1.5)), Real(0.24));
  // A static plane (Bullet allows it only static): the slab 3 cm either
  // side of it, above the point of it the particles are around.
  cases.push_back({"plane", [] { return new btStaticPlaneShape(btVector3(0, 1, 1).normalized(), Real(0.4)); },
                   btTransform(turned, btVector3(Real(0.1), Real(0.2), Real(0.3))), Vec3::Zero(), Vec3::Zero()});

  std::mt19937 rng(11);
  for (const Case& c : cases) {
    std::vector<Vec3> points;
    if (c.name == "plane") {
      // Points of the plane (its normal n and constant d in its own frame,
      // taken to world), each moved along n by up to 3 cm.
      const btVector3 n_local = btVector3(0, 1, 1).normalized();
      const Vec3 n = vec(c.pose.getBasis() * n_local);
      const Vec3 on = vec(c.pose * (n_local * Real(0.4)));
      const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
      std::uniform_real_distribution<double> s(-0.5, 0.5), off(-0.03, 0.03);
      for (int k = 0; k < 300; ++k)
        points.push_back(on + Real(s(rng)) * u + Real(s(rng)) * v + Real(off(rng)) * n);
    } else {
      std::uniform_real_distribution<double> x(double(c.lo.x()), double(c.hi.x())),
          y(double(c.lo.y()), double(c.hi.y())), z(double(c.lo.z()), double(c.hi.z()));
      for (int k = 0; k < 600; ++k) points.push_back(Vec3(Real(x(rng)), Real(y(rng)), Real(z(rng))));
    }
    World direct(c.make(), c.pose, false, points), wrapped(c.make(), c.pose, true, points);
    direct.bw.step();
    wrapped.bw.step();
    const std::vector<xpbd::BodyContact>& a = direct.xw->state(direct.id).contacts;
    const std::vector<xpbd::BodyContact>& b = wrapped.xw->state(wrapped.id).contacts;
    // It means something only if many particles are in contact.
    EXPECT_GE(a.size(), 30u) << c.name;
    ASSERT_EQ(a.size(), b.size()) << c.name;
    // Coordinates up to 2.5 m from the origin: the round trip's round-off
    // is a few eps of that.
    const Real tol = Real(64) * kEps;
    for (std::size_t k = 0; k < a.size(); ++k) {
      const xpbd::BodyContact &p = a[k], &q = b[k];
      ASSERT_TRUE(p.particle == q.particle && p.body == q.body && p.thickness == q.thickness &&
                  p.static_friction == q.static_friction && p.dynamic_friction == q.dynamic_friction &&
                  p.restitution == q.restitution && p.compliance == q.compliance)
          << c.name << ", contact " << k << ": particle " << p.particle << " vs " << q.particle;
      EXPECT_LE((p.r - q.r).norm(), tol) << c.name << ", particle " << p.particle;
      EXPECT_LE((p.n - q.n).norm(), tol) << c.name << ", particle " << p.particle;
      EXPECT_NEAR(p.n.norm(), Real(1), tol) << c.name << ", particle " << p.particle;
    }
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

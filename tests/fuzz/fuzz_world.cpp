// Fuzz target: the embedding API driven by a byte stream. Each operation
// takes a byte for its kind and then its arguments: add or remove a system
// (a small rope, perhaps branched, or cloth, perhaps with collision
// triangles), add or remove and delete a rigid body, attach or detach,
// change settings (a pool of two threads among them), write a particle or
// a body state (NaN and huge
// values included), and step Bullet with any dt. The API may refuse an
// argument by throwing (ConfigError, out_of_range: caught here); nothing
// may be thrown out of stepSimulation, and a crash, a sanitizer report, a
// leak or a hang is a finding.
#include <btBulletDynamicsCommon.h>
#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <limits>
#include <memory>
#include <vector>

#include "xpbd/builders.hpp"
#include "xpbd/compile.hpp"
#include "xpbd/state.hpp"
#include "xpbd/workers.hpp"
#include "xpbd_bullet/world.hpp"

namespace {

using xpbd::Real;
using xpbd::Vec3;

// A float from the stream: mostly ordinary values, sometimes the awkward ones.
Real value(FuzzedDataProvider& in, Real lo, Real hi) {
  switch (in.ConsumeIntegralInRange<int>(0, 9)) {
    case 0: return std::numeric_limits<Real>::quiet_NaN();
    case 1: return std::numeric_limits<Real>::infinity();
    case 2: return Real(-1);
    case 3: return Real(1e30);
    case 4: return Real(0);
    default: return lo + (hi - lo) * Real(in.ConsumeProbability<double>());
  }
}
Vec3 vec(FuzzedDataProvider& in, Real lo, Real hi) {
  const Real x = value(in, lo, hi), y = value(in, lo, hi);
  return Vec3(x, y, value(in, lo, hi));
}

struct Body {
  std::unique_ptr<btCollisionShape> shape;
  std::unique_ptr<btRigidBody> body;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // One pool for every input (its helper threads are made once).
  static xpbd::Workers pool(2);
  FuzzedDataProvider in(data, size);
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
  world.setGravity(btVector3(0, -10, 0));
  std::vector<Body> bodies;
  {
    xpbd_bullet::XpbdWorld xw(world);
    std::vector<xpbd_bullet::SystemId> systems;
    std::vector<xpbd_bullet::AttachmentId> attachments;
    for (int op = 0; op < 64 && in.remaining_bytes() > 0; ++op) {
      try {
        switch (in.ConsumeIntegralInRange<int>(0, 9)) {
          case 0: {  // add a small rope or cloth
            xpbd::SceneDesc scene;
            if (in.ConsumeBool()) {
              xpbd::RopeDesc r;
              r.n = in.ConsumeIntegralInRange<int>(2, 8);
              r.start = vec(in, -1, 1);
              r.spacing = Real(0.1);
              r.pin_first = in.ConsumeBool();
              xpbd::add_rope(scene, r);
              // Branches off the rope: a tree (direct_chains' tree solve).
              const int branches = in.ConsumeIntegralInRange<int>(0, 3);
              for (int b = 0; b < branches; ++b) {
                xpbd::Index from = in.ConsumeIntegralInRange<xpbd::Index>(0, xpbd::Index(r.n - 1));
                const int links = in.ConsumeIntegralInRange<int>(1, 3);
                for (int k = 0; k < links; ++k) {
                  const Vec3 at = scene.positions[std::size_t(from)] + vec(in, -0.1f, 0.1f);
                  const xpbd::Index p = scene.add_particle(at, Real(0.05));
                  xpbd::DistanceDesc d{from, p, Real(0.1), {}};
                  d.mat.compliance = value(in, 0, 1e-4f);
                  scene.distances.push_back(d);
                  from = p;
                }
              }
            } else {
              xpbd::ClothGridDesc c;
              c.nx = in.ConsumeIntegralInRange<int>(2, 6);
              c.ny = in.ConsumeIntegralInRange<int>(2, 6);
              c.origin = vec(in, -1, 1);
              c.pins = in.ConsumeBool() ? xpbd::ClothPins::top_corners : xpbd::ClothPins::none;
              c.collision_triangles = in.ConsumeBool();
              xpbd::add_cloth_grid(scene, c);
            }
            auto model = std::make_shared<const xpbd::Model>(xpbd::compile(scene));
            xpbd_bullet::SystemSettings set;
            set.substeps = in.ConsumeIntegralInRange<int>(1, 8);
            set.contacts.enabled = in.ConsumeBool();
            systems.push_back(xw.add_system(model, xpbd::make_state(*model), set));
            break;
          }
          case 1:  // remove a system (perhaps one already removed)
            if (!systems.empty())
              xw.remove_system(systems[in.ConsumeIntegralInRange<std::size_t>(0, systems.size() - 1)]);
            break;
          case 2: {  // add a body
            Body b;
            const int kind = in.ConsumeIntegralInRange<int>(0, 2);
            const Real mass = in.ConsumeBool() ? 0 : value(in, 0, 5);
            if (kind == 0) b.shape = std::make_unique<btSphereShape>(btScalar(value(in, 0.01f, 1)));
            else if (kind == 1) b.shape = std::make_unique<btBoxShape>(btVector3(0.2f, 0.1f, 0.3f));
            else b.shape = std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), 0);
            const bool dynamic = kind != 2 && mass > 0 && std::isfinite(mass) && mass < 1e6;
            btVector3 inertia(0, 0, 0);
            if (dynamic) b.shape->calculateLocalInertia(btScalar(mass), inertia);
            btRigidBody::btRigidBodyConstructionInfo info(dynamic ? btScalar(mass) : 0, nullptr, b.shape.get(),
                                                          inertia);
            const Vec3 p = vec(in, -2, 2);
            info.m_startWorldTransform.setOrigin(btVector3(btScalar(p.x()), btScalar(p.y()), btScalar(p.z())));
            b.body = std::make_unique<btRigidBody>(info);
            world.addRigidBody(b.body.get());
            bodies.push_back(std::move(b));
            break;
          }
          case 3:  // remove and delete a body (attachments may still point at it)
            if (!bodies.empty()) {
              const std::size_t k = in.ConsumeIntegralInRange<std::size_t>(0, bodies.size() - 1);
              world.removeRigidBody(bodies[k].body.get());
              bodies.erase(bodies.begin() + std::ptrdiff_t(k));
            }
            break;
          case 4:  // attach
            if (!systems.empty() && !bodies.empty()) {
              const auto sys = systems[in.ConsumeIntegralInRange<std::size_t>(0, systems.size() - 1)];
              btRigidBody* body = bodies[in.ConsumeIntegralInRange<std::size_t>(0, bodies.size() - 1)].body.get();
              const Vec3 l = vec(in, -0.2f, 0.2f);
              attachments.push_back(xw.attach(sys, in.ConsumeIntegralInRange<int>(-1, 40), body,
                                              btVector3(btScalar(l.x()), btScalar(l.y()), btScalar(l.z())),
                                              in.ConsumeBool() ? 0 : value(in, 0, 1e-3f)));
            }
            break;
          case 5:  // detach (perhaps an attachment that has already ended)
            if (!attachments.empty())
              xw.remove_attachment(attachments[in.ConsumeIntegralInRange<std::size_t>(0, attachments.size() - 1)]);
            break;
          case 6:  // new settings, some of them bad
            if (!systems.empty()) {
              const auto sys = systems[in.ConsumeIntegralInRange<std::size_t>(0, systems.size() - 1)];
              xpbd_bullet::SystemSettings set = xw.settings(sys);
              set.substeps = in.ConsumeIntegralInRange<int>(0, 8);
              set.iterations = in.ConsumeIntegralInRange<int>(0, 4);
              set.contacts.margin = value(in, 0, 0.05f);
              set.contacts.thickness = value(in, 0, 0.02f);
              set.contacts.feature_spacing = value(in, 0, 0.1f);
              set.contact_sweeps = in.ConsumeIntegralInRange<int>(-1, 4);
              set.sleep_speed = value(in, 0, 1);
              set.direct_chains = in.ConsumeBool();
              set.chain_passes = in.ConsumeIntegralInRange<int>(0, 20);
              set.chain_tolerance = value(in, 0, 0.01f);
              set.coloured = in.ConsumeBool();
              // Two threads for the coloured sweep and the contact search.
              set.workers = set.coloured && in.ConsumeBool() ? &pool : nullptr;
              set.alternate_sweeps = in.ConsumeBool();
              set.hierarchy = in.ConsumeBool();
              set.hierarchy_slack = value(in, 0, 0.05f);
              // The accuracy targets, kept cheap (at most 12 substeps).
              set.tolerance.strain = in.ConsumeBool() ? 0 : double(value(in, 0, 0.2f));
              set.tolerance.penetration = in.ConsumeBool() ? 0 : double(value(in, 0, 0.01f));
              set.tolerance.max_substeps = in.ConsumeIntegralInRange<int>(0, 12);
              // 2 is no StrainMeasure: the settings must refuse it.
              set.tolerance.measure = static_cast<xpbd_bullet::StrainMeasure>(in.ConsumeIntegralInRange<int>(0, 2));
              xw.set_settings(sys, set);
            }
            break;
          case 7: {  // write a particle's state
            if (!systems.empty()) {
              const auto sys = systems[in.ConsumeIntegralInRange<std::size_t>(0, systems.size() - 1)];
              xpbd::State& st = xw.state(sys);
              if (!st.x.empty()) {
                const std::size_t i = in.ConsumeIntegralInRange<std::size_t>(0, st.x.size() - 1);
                (in.ConsumeBool() ? st.x : st.v)[i] = vec(in, -3, 3);
              }
            }
            break;
          }
          case 8:  // move a body, perhaps to a non-finite pose
            if (!bodies.empty()) {
              btRigidBody* body = bodies[in.ConsumeIntegralInRange<std::size_t>(0, bodies.size() - 1)].body.get();
              const Vec3 p = vec(in, -3, 3);
              btTransform t = body->getWorldTransform();
              t.setOrigin(btVector3(btScalar(p.x()), btScalar(p.y()), btScalar(p.z())));
              body->setWorldTransform(t);
              const Vec3 v = vec(in, -10, 10);
              body->setLinearVelocity(btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z())));
            }
            break;
          default: {  // step, with any dt
            const btScalar dt = btScalar(value(in, 0.0001f, 0.05f));
            const int max_sub = in.ConsumeIntegralInRange<int>(0, 2);
            try {
              world.stepSimulation(dt, max_sub, std::isfinite(dt) && dt > 0 ? dt : btScalar(1) / 60);
            } catch (...) {
              std::abort();  // nothing may leave stepSimulation
            }
            break;
          }
        }
      } catch (const std::exception&) {
        // The API refused an argument: what it is documented to do.
      }
    }
  }
  for (Body& b : bodies) world.removeRigidBody(b.body.get());
  return 0;
}

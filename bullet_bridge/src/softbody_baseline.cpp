#include "xpbd_bullet/softbody_baseline.hpp"

#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <sstream>
#include <string>
#include <type_traits>

#include "xpbd/compile.hpp"
#include "xpbd/error.hpp"
#include "xpbd/model.hpp"
#include "xpbd_bullet/softbody_builder.hpp"

namespace xpbd_bullet {

static_assert(std::is_same_v<btScalar, xpbd::Real>,
              "the bridge must link the Bullet build whose btScalar is xpbd::Real");

namespace {

using xpbd::Real;
using xpbd::Vec3;

std::string num(double v) { return xpbd::format_value(v); }

btVector3 bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }
Vec3 from_bt(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }

void validate(const SoftBodyBaselineConfig& c) {
  auto fail = [](const char* field, const std::string& what) {
    throw xpbd::ConfigError(std::string("SoftBodyBaselineConfig.") + field + ": " + what);
  };
  if (!(c.dt > Real(0)) || !std::isfinite(c.dt)) fail("dt", "must be finite and > 0, got " + num(c.dt));
  if (c.internal_steps < 1)
    fail("internal_steps", "must be >= 1, got " + std::to_string(c.internal_steps));
  if (c.piterations < 1) fail("piterations", "must be >= 1, got " + std::to_string(c.piterations));
  if (!(c.kLST > Real(0) && c.kLST <= Real(1))) fail("kLST", "must be in (0, 1], got " + num(c.kLST));
  if (!c.gravity.allFinite()) fail("gravity", "must be finite");
  if (!(c.margin >= Real(0)) || !std::isfinite(c.margin))
    fail("margin", "must be finite and >= 0, got " + num(c.margin));
  if (!(c.friction >= Real(0) && c.friction <= Real(1)))
    fail("friction", "must be in [0, 1], got " + num(c.friction));
}

}  // namespace

// Members are declared in construction order; they are destroyed in reverse:
// the soft body (after removal from the world, in ~Impl), then the world
// (which frees its own btDefaultSoftBodySolver), the constraint solver, the
// broadphase, the dispatcher and last the collision configuration that the
// dispatcher uses.
struct SoftBodyBaseline::Impl {
  SoftBodyBaselineConfig cfg;
  std::unique_ptr<btSoftBodyRigidBodyCollisionConfiguration> collision_config;
  std::unique_ptr<btCollisionDispatcher> dispatcher;
  std::unique_ptr<btDbvtBroadphase> broadphase;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver;
  std::unique_ptr<btSoftRigidDynamicsWorld> world;
  std::unique_ptr<btSoftBody> body;
  long long frames = 0;

  ~Impl() {
    if (world && body) world->removeSoftBody(body.get());
  }
};

SoftBodyBaseline::SoftBodyBaseline(const xpbd::SceneDesc& scene, const SoftBodyBaselineConfig& cfg)
    : impl_(std::make_unique<Impl>()) {
  validate(cfg);
  const xpbd::Model model = xpbd::compile(scene);  // validates the scene, gives the rest lengths

  Impl& m = *impl_;
  m.cfg = cfg;
  m.collision_config = std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>();
  m.dispatcher = std::make_unique<btCollisionDispatcher>(m.collision_config.get());
  m.broadphase = std::make_unique<btDbvtBroadphase>();
  m.solver = std::make_unique<btSequentialImpulseConstraintSolver>();
  // softBodySolver = nullptr: the world creates and owns a btDefaultSoftBodySolver.
  m.world = std::make_unique<btSoftRigidDynamicsWorld>(m.dispatcher.get(), m.broadphase.get(),
                                                       m.solver.get(), m.collision_config.get(),
                                                       nullptr);
  // Bullet keeps two gravities: the rigid world's and the soft bodies' own.
  m.world->setGravity(bt(cfg.gravity));
  btSoftBodyWorldInfo& info = m.world->getWorldInfo();
  info.m_gravity = bt(cfg.gravity);
  info.air_density = 0;  // no medium (aerodynamics are off anyway: kLF = kDG = 0)
  info.water_density = 0;

  // The soft body under the fairness rules (softbody_builder.hpp); it rejects
  // the elements a btSoftBody cannot express.
  SoftBodyBuildConfig bc;
  bc.piterations = cfg.piterations;
  bc.kLST = cfg.kLST;
  bc.kDP = 0;
  bc.margin = cfg.margin;
  bc.friction = cfg.friction;
  m.body = build_softbody(info, scene, model, bc);
  m.world->addSoftBody(m.body.get());
}

SoftBodyBaseline::~SoftBodyBaseline() = default;

void SoftBodyBaseline::step_frame() {
  const Impl& m = *impl_;
  const btScalar h = m.cfg.dt / btScalar(m.cfg.internal_steps);
  // stepSimulation(h, 1, h): exactly one internal step of h per call (the
  // accumulator holds h and drops back to 0), no interpolation.
  for (int s = 0; s < m.cfg.internal_steps; ++s) m.world->stepSimulation(h, 1, h);
  ++impl_->frames;
}

int SoftBodyBaseline::num_nodes() const { return impl_->body->m_nodes.size(); }
int SoftBodyBaseline::num_links() const { return impl_->body->m_links.size(); }
Real SoftBodyBaseline::total_mass() const { return impl_->body->getTotalMass(); }
Real SoftBodyBaseline::time() const { return Real(impl_->frames) * impl_->cfg.dt; }

long long SoftBodyBaseline::projections_per_frame() const {
  return static_cast<long long>(impl_->cfg.internal_steps) * impl_->cfg.piterations * num_links();
}

void SoftBodyBaseline::positions(std::vector<Vec3>& out) const {
  const auto& nodes = impl_->body->m_nodes;
  out.resize(static_cast<std::size_t>(nodes.size()));
  for (int i = 0; i < nodes.size(); ++i) out[static_cast<std::size_t>(i)] = from_bt(nodes[i].m_x);
}

void SoftBodyBaseline::velocities(std::vector<Vec3>& out) const {
  const auto& nodes = impl_->body->m_nodes;
  out.resize(static_cast<std::size_t>(nodes.size()));
  for (int i = 0; i < nodes.size(); ++i) out[static_cast<std::size_t>(i)] = from_bt(nodes[i].m_v);
}

const SoftBodyBaselineConfig& SoftBodyBaseline::config() const { return impl_->cfg; }
const btSoftBody& SoftBodyBaseline::body() const { return *impl_->body; }

std::vector<std::vector<Vec3>> run_recording_positions(SoftBodyBaseline& sb, int frames) {
  std::vector<std::vector<Vec3>> out(static_cast<std::size_t>(frames > 0 ? frames + 1 : 1));
  sb.positions(out[0]);
  for (int f = 0; f < frames; ++f) {
    sb.step_frame();
    sb.positions(out[static_cast<std::size_t>(f + 1)]);
  }
  return out;
}

}  // namespace xpbd_bullet

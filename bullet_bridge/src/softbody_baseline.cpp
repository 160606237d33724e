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

namespace xpbd_bullet {

static_assert(std::is_same_v<btScalar, xpbd::Real>,
              "the bridge must link the Bullet build whose btScalar is xpbd::Real");

namespace {

using xpbd::Real;
using xpbd::Vec3;

std::string num(Real v) {
  std::ostringstream o;
  o.precision(9);
  o << v;
  return o.str();
}

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

// Rejects the scene elements a plain btSoftBody cannot represent.
void check_representable(const xpbd::SceneDesc& s) {
  if (!s.collisions.empty())
    throw xpbd::SceneError("collisions[0]: the btSoftBody baseline has no particle-particle "
                           "collisions (scene has " + std::to_string(s.collisions.size()) + ")");
  if (!s.planes.empty())
    throw xpbd::SceneError("planes[0]: the btSoftBody baseline has no planes (scene has " +
                           std::to_string(s.planes.size()) + ")");
  for (std::size_t k = 0; k < s.pins.size(); ++k) {
    const auto& p = s.pins[k];
    const std::string w = "pins[" + std::to_string(k) + "]";
    // compile() has already checked the index.
    const Real m = s.masses[static_cast<std::size_t>(p.particle)];
    if (m != Real(0))
      throw xpbd::SceneError(w + ".particle: the btSoftBody baseline supports only kinematic pins "
                             "(mass 0); particle " + std::to_string(p.particle) + " has mass " +
                             num(m) + " kg");
    if (p.target && *p.target != s.positions[static_cast<std::size_t>(p.particle)])
      throw xpbd::SceneError(w + ".target: the btSoftBody baseline supports only pins at the "
                             "particle's initial position");
  }
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
  check_representable(scene);

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

  // Nodes: positions, then masses node by node (never setTotalMass).
  const int n = scene.num_particles();
  std::vector<btVector3> x(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) x[static_cast<std::size_t>(i)] = bt(scene.positions[static_cast<std::size_t>(i)]);
  m.body = std::make_unique<btSoftBody>(&info, n, n > 0 ? x.data() : nullptr, nullptr);
  btSoftBody& b = *m.body;
  for (int i = 0; i < n; ++i) b.setMass(i, scene.masses[static_cast<std::size_t>(i)]);
  // Initial velocities; pinned (kinematic, pinned in place) nodes stay at rest,
  // as xpbd holds them on their pin target.
  std::vector<char> pinned(static_cast<std::size_t>(n), 0);
  for (const auto& p : scene.pins) pinned[static_cast<std::size_t>(p.particle)] = 1;
  for (int i = 0; i < n; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    b.m_nodes[i].m_v = pinned[ui] ? btVector3(0, 0, 0) : bt(model.v0[ui]);
  }

  // Material 0 (created by the constructor) is shared by every link.
  b.m_materials[0]->m_kLST = cfg.kLST;

  // Links: one per distance constraint, same order, same particles.
  const auto& dist = model.get<xpbd::Distance>();
  for (const auto& d : dist) b.appendLink(d.p[0], d.p[1], nullptr, false);

  // Solver configuration (DESIGN.md section 5).
  btSoftBody::Config& c = b.m_cfg;
  c.piterations = cfg.piterations;
  c.viterations = 0;  // no velocity solver
  c.diterations = 0;  // no drift solver
  c.kDP = 0;          // no damping (xpbd runs with zero damping)
  c.kDG = 0;          // no drag
  c.kLF = 0;          // no lift
  c.kPR = 0;          // no pressure
  c.kVC = 0;          // no volume conservation
  c.kMT = 0;          // no pose matching
  c.kCHR = 1;         // rigid contact hardness
  c.kKHR = 1;         // kinetic contact hardness
  c.kDF = cfg.friction;
  c.timescale = 1;
  b.getCollisionShape()->setMargin(cfg.margin);

  // Runtime constants now, as predictMotion would on the first step (it resets
  // every rest length to the current node distance and computes the link
  // constants from kLST and the inverse masses); then the scene's rest lengths.
  b.updateConstants();
  for (std::size_t k = 0; k < dist.size(); ++k) {
    btSoftBody::Link& l = b.m_links[static_cast<int>(k)];
    l.m_rl = dist[k].rest;
    l.m_c1 = l.m_rl * l.m_rl;
  }
  b.m_bUpdateRtCst = false;

  b.setActivationState(DISABLE_DEACTIVATION);  // sleeping off
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

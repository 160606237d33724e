#include "xpbd_bullet/softbody_builder.hpp"

#include <BulletSoftBody/btSoftBody.h>

#include <cmath>
#include <sstream>
#include <type_traits>

#include "xpbd/error.hpp"

namespace xpbd_bullet {

static_assert(std::is_same_v<btScalar, xpbd::Real>,
              "the bridge must link the Bullet build whose btScalar is xpbd::Real");

namespace {

using xpbd::Real;
using xpbd::Vec3;

std::string num(double v) { return xpbd::format_value(v); }

btVector3 bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }

}  // namespace

std::vector<std::string> softbody_unsupported(const xpbd::SceneDesc& s) {
  std::vector<std::string> out;
  // "<field>: scene has <n> <what>[s]; btSoftBody cannot express it/them<why>"
  auto count = [&](std::size_t n, const char* field, const char* what, const char* why) {
    if (n == 0) return;
    out.push_back(std::string(field) + ": scene has " + std::to_string(n) + " " + what + (n == 1 ? "" : "s") +
                  "; btSoftBody cannot express " + (n == 1 ? "it" : "them") + why);
  };
  count(s.collisions.size(), "collisions", "particle-particle collision pair", "");
  if (s.self_collision.enabled)
    out.push_back("self_collision: particle-particle collision is on; btSoftBody cannot express it "
                  "(its soft-soft collision is vertex-face or cluster based)");
  count(s.planes.size(), "planes", "plane", " (use a static plane rigid body instead)");
  count(s.penetrations.size(), "penetrations", "point-triangle penetration constraint", "");
  count(s.dihedral_bends.size(), "dihedral_bends", "dihedral bending element",
        " (its links are distance constraints only)");
  count(s.isometric_bends.size(), "isometric_bends", "isometric bending element",
        " (its links are distance constraints only)");
  count(s.tets.size(), "tets", "tetrahedral volume constraint", "");
  count(s.tethers.size(), "tethers", "tether", "");
  count(s.global_volumes.size(), "global_volumes", "global volume (pressure) constraint",
        " (its pressure kPR and volume conservation kVC are different physics)");
  for (std::size_t k = 0; k < s.pins.size(); ++k) {
    const auto& p = s.pins[k];
    const std::string w = "pins[" + std::to_string(k) + "]";
    const auto i = static_cast<std::size_t>(p.particle);
    if (i >= s.masses.size() || i >= s.positions.size()) continue;  // compile() reports it
    if (s.masses[i] != Real(0)) {
      out.push_back(w + ".particle: btSoftBody supports only kinematic pins (mass 0); particle " +
                    std::to_string(p.particle) + " has mass " + num(s.masses[i]) + " kg");
      break;
    }
    if (p.target && *p.target != s.positions[i]) {
      out.push_back(w + ".target: btSoftBody supports only pins at the particle's initial position");
      break;
    }
  }
  return out;
}

void validate(const SoftBodyBuildConfig& c) {
  auto fail = [](const char* field, const std::string& what) {
    throw xpbd::ConfigError(std::string("SoftBodyBuildConfig.") + field + ": " + what);
  };
  if (c.piterations < 1) fail("piterations", "must be >= 1, got " + std::to_string(c.piterations));
  if (!(c.kLST > Real(0) && c.kLST <= Real(1))) fail("kLST", "must be in (0, 1], got " + num(c.kLST));
  if (!(c.kDP >= Real(0) && c.kDP < Real(1))) fail("kDP", "must be in [0, 1), got " + num(c.kDP));
  if (!(c.margin >= Real(0)) || !std::isfinite(c.margin))
    fail("margin", "must be finite and >= 0, got " + num(c.margin));
  if (!(c.friction >= Real(0) && c.friction <= Real(1)))
    fail("friction", "must be in [0, 1], got " + num(c.friction));
}

std::unique_ptr<btSoftBody> build_softbody(btSoftBodyWorldInfo& info, const xpbd::SceneDesc& scene,
                                           const xpbd::Model& model, const SoftBodyBuildConfig& cfg) {
  validate(cfg);
  if (const auto why = softbody_unsupported(scene); !why.empty()) throw xpbd::SceneError(why.front());
  const int n = scene.num_particles();
  if (model.num_particles() != n)
    throw xpbd::ConfigError("build_softbody: model has " + std::to_string(model.num_particles()) +
                            " particles, scene has " + std::to_string(n) + " (pass compile(scene))");

  // Nodes: positions, then masses node by node (never setTotalMass).
  std::vector<btVector3> x(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) x[static_cast<std::size_t>(i)] = bt(scene.positions[static_cast<std::size_t>(i)]);
  auto body = std::make_unique<btSoftBody>(&info, n, n > 0 ? x.data() : nullptr, nullptr);
  btSoftBody& b = *body;
  for (int i = 0; i < n; ++i) b.setMass(i, scene.masses[static_cast<std::size_t>(i)]);
  // Initial velocities; pinned nodes stay at rest, as xpbd holds them on
  // their pin target.
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

  // Solver configuration (docs/design.md section 5).
  btSoftBody::Config& c = b.m_cfg;
  c.piterations = cfg.piterations;
  c.viterations = 0;  // no velocity solver
  c.diterations = 0;  // no drift solver
  c.kDP = cfg.kDP;    // damping per internal step
  c.kDG = 0;          // no drag
  c.kLF = 0;          // no lift
  c.kPR = 0;          // no pressure
  c.kVC = 0;          // no volume conservation
  c.kMT = 0;          // no pose matching
  c.kCHR = 1;         // rigid contact hardness
  c.kKHR = 1;         // kinetic contact hardness
  c.kAHR = 1;         // anchor hardness (rigid attachments)
  c.kDF = cfg.friction;
  c.timescale = 1;
  c.collisions = btSoftBody::fCollision::SDF_RS;  // nodes vs rigid bodies, no soft-soft
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
  return body;
}

}  // namespace xpbd_bullet

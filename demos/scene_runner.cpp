#include "demos/scene_runner.hpp"

#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <type_traits>

#include "demos/run_metrics.hpp"
#include "demos/soft_sim.hpp"
#include "demos/state_hash.hpp"
#include "xpbd/compile.hpp"
#include "xpbd/error.hpp"
#include "xpbd/model.hpp"
#include "xpbd/spatial_hash.hpp"
#include "xpbd/state.hpp"
#include "xpbd_bullet/narrowphase.hpp"
#include "xpbd_bullet/softbody_builder.hpp"
#include "xpbd_bullet/world.hpp"

namespace xpbd_demos {
namespace {

using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;
using Clock = std::chrono::steady_clock;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Vec3 vec(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }

// True if some component's magnitude exceeds `limit`.
bool beyond(std::span<const Vec3> a, double limit) {
  for (const Vec3& v : a)
    if (double(v.cwiseAbs().maxCoeff()) > limit) return true;
  return false;
}

// ---------------------------------------------------------------------------
// Input checks

void validate_options(const RunOptions& o, const SceneSpec& spec) {
  auto fail = [](const std::string& field, const std::string& what) {
    throw xpbd::ConfigError("solver." + field + ": " + what);
  };
  if (!(o.dt > Real(0)) || !std::isfinite(o.dt)) fail("dt", "must be finite and > 0, got " + num(o.dt));
  if (o.substeps < 1) fail("substeps", "must be >= 1, got " + std::to_string(o.substeps));
  if (o.iterations < 1) fail("iterations", "must be >= 1, got " + std::to_string(o.iterations));
  if (o.frames < 1) fail("frames", "must be >= 1, got " + std::to_string(o.frames));
  if (o.rigid_steps < 1 || o.substeps % o.rigid_steps != 0)
    fail("rigid_steps", "must be >= 1 and divide substeps (" + std::to_string(o.substeps) + "), got " +
                            std::to_string(o.rigid_steps));
  if (o.solver == Solver::bullet && o.rigid_steps != 1)
    fail("rigid_steps", "applies to xpbd and pbd only (btSoftBody steps the rigid bodies at every internal "
                        "step already), got " + std::to_string(o.rigid_steps));
  if (o.threads < 1) fail("threads", "must be >= 1, got " + std::to_string(o.threads));
  if (o.threads > 1 && (o.solver == Solver::bullet || !spec.solver.coloured))
    fail("threads", "more than one thread needs an xpbd or pbd run with solver.coloured = true (the threads "
                    "share a colour's sweep), got " + std::to_string(o.threads));
  if (!(o.bullet_sdf_voxel >= Real(0)) || !std::isfinite(o.bullet_sdf_voxel))
    fail("bullet_sdf_voxel", "must be finite and >= 0 (0 = automatic), got " + num(o.bullet_sdf_voxel));
  const SolverSpec& s = spec.solver;
  if (!(s.drag >= Real(0)) || !std::isfinite(s.drag))
    fail("drag", "must be finite and >= 0, got " + num(s.drag));
  if (!s.gravity.allFinite()) fail("gravity", "must be finite");
  if (!(s.bullet_kLST > Real(0) && s.bullet_kLST <= Real(1)))
    fail("bullet_kLST", "must be in (0, 1], got " + num(s.bullet_kLST));
  xpbd::validate(o.health, "solver.");
  if (!(o.tolerance >= 0) || !std::isfinite(o.tolerance))
    fail("tolerance", "must be finite and >= 0 (0 = off), got " + num(o.tolerance));
  if (!(o.penetration_tolerance >= 0) || !std::isfinite(o.penetration_tolerance))
    fail("penetration_tolerance", "must be finite and >= 0 (m, 0 = off), got " + num(o.penetration_tolerance));
  if (o.max_substeps < 1) fail("max_substeps", "must be >= 1, got " + std::to_string(o.max_substeps));
  if (o.tolerance_measure == ToleranceMeasure::residual && o.solver == Solver::pbd)
    fail("tolerance_measure", "\"residual\" needs method xpbd (PBD's multipliers are not XPBD's), got method pbd");
}

void validate_contacts(const SoftContactSpec& c) {
  auto fail = [](const std::string& field, const std::string& what) {
    throw xpbd::SceneError("soft.contacts." + field + ": " + what);
  };
  auto nonneg = [&](const char* field, Real v) {
    if (!(v >= Real(0)) || !std::isfinite(v)) fail(field, "must be finite and >= 0, got " + num(v));
  };
  nonneg("thickness", c.thickness);
  nonneg("margin", c.margin);
  nonneg("static_friction", c.static_friction);
  nonneg("dynamic_friction", c.dynamic_friction);
  nonneg("compliance", c.compliance);
  if (c.dynamic_friction > c.static_friction)
    fail("dynamic_friction", "must be <= static_friction (" + num(c.static_friction) + "), got " +
                                 num(c.dynamic_friction));
  if (!(c.restitution >= Real(0) && c.restitution <= Real(1)))
    fail("restitution", "must be in [0, 1], got " + num(c.restitution));
  if (!(c.feature_spacing > Real(0)) || !std::isfinite(c.feature_spacing))
    fail("feature_spacing", "must be finite and > 0, got " + num(c.feature_spacing));
}

void validate_attachments(const SceneSpec& spec, Index particles) {
  const int nb = static_cast<int>(spec.bodies.size());
  for (std::size_t k = 0; k < spec.attachments.size(); ++k) {
    const AttachmentSpec& a = spec.attachments[k];
    const std::string at = "attachments[" + std::to_string(k) + "].";
    if (a.particle < 0 || a.particle >= particles)
      throw xpbd::SceneError(at + "particle: index " + std::to_string(a.particle) + " out of range [0, " +
                             std::to_string(particles) + ")");
    if (a.body < 0 || a.body >= nb)
      throw xpbd::SceneError(at + "body: index " + std::to_string(a.body) + " out of range [0, " +
                             std::to_string(nb) + ")");
    if (a.local && !a.local->allFinite()) throw xpbd::SceneError(at + "local: must be finite");
    if (!(a.compliance >= Real(0)) || !std::isfinite(a.compliance))
      throw xpbd::SceneError(at + "compliance: must be finite and >= 0, got " + num(a.compliance));
  }
}

// All the reasons btSoftBody cannot run the scene.
std::vector<std::string> bullet_limitations(const SceneSpec& spec, const xpbd::SceneDesc& scene) {
  std::vector<std::string> why = xpbd_bullet::softbody_unsupported(scene);
  const SoftContactSpec& c = spec.soft.contacts;
  if (!spec.bodies.empty()) {
    if (c.restitution != Real(0))
      why.push_back("soft.contacts.restitution: btSoftBody contacts have no restitution, got " +
                    num(c.restitution));
    if (c.compliance != Real(0))
      why.push_back("soft.contacts.compliance: btSoftBody contacts have no compliance (only a "
                    "hardness), got " + num(c.compliance) + " m/N");
    if (c.dynamic_friction > Real(1))
      why.push_back("soft.contacts.dynamic_friction: btSoftBody's kDF must be in [0, 1], got " +
                    num(c.dynamic_friction));
    if (!uniform_radius(scene))
      why.push_back("radii: the movable particles have different radii; btSoftBody has one "
                    "collision margin per body");
  }
  for (std::size_t k = 0; k < spec.attachments.size(); ++k) {
    const AttachmentSpec& a = spec.attachments[k];
    const std::string at = "attachments[" + std::to_string(k) + "]";
    if (a.compliance != Real(0)) {
      why.push_back(at + ".compliance: btSoftBody anchors have no compliance, got " +
                    num(a.compliance) + " m/N");
      continue;
    }
    const auto i = static_cast<std::size_t>(a.particle);
    const auto b = static_cast<std::size_t>(a.body);
    if (i < scene.masses.size() && b < spec.bodies.size() && scene.masses[i] == Real(0) &&
        (spec.bodies[b].mass == Real(0) || spec.bodies[b].kinematic))
      why.push_back(at + ": particle " + std::to_string(a.particle) +
                    " (mass 0) on a static or kinematic body; a btSoftBody anchor needs a movable "
                    "node or body");
  }
  return why;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : "; ") + x;
  return s;
}

// ---------------------------------------------------------------------------
// Measurements: one piece of code for every solver, from positions and
// velocities of the particles and the Bullet state of the rigid bodies.

class Measurer {
 public:
  Measurer(const SceneSpec& spec, const xpbd::Model& m, RigidWorld& rw)
      : m_(m), rw_(rw), g_(spec.solver.gravity), thickness_(spec.soft.contacts.thickness) {
    attached_.resize(static_cast<std::size_t>(rw.num_bodies()));
    for (const AttachmentSpec& a : spec.attachments)
      attached_[static_cast<std::size_t>(a.body)].push_back(a.particle);
    for (auto& v : attached_) std::sort(v.begin(), v.end());
    particle_collision_ = m.self_collision.enabled || !m.get<xpbd::Collision>().empty();
  }

  bool particle_collision() const { return particle_collision_; }

  FrameMetrics measure(double time, std::span<const Vec3> x, std::span<const Vec3> v, bool finite) {
    FrameMetrics f;
    f.time = time;
    if (!finite) {
      f.kinetic_energy = f.potential_energy = f.max_strain = f.mean_strain = f.max_penetration = kNaN;
      if (particle_collision_) f.min_particle_distance = kNaN;
      return f;
    }
    energies(x, v, f);
    strain(x, f);
    f.max_penetration = penetration(x);
    if (particle_collision_) f.min_particle_distance = min_pair_distance(x);
    return f;
  }

 private:
  void energies(std::span<const Vec3> x, std::span<const Vec3> v, FrameMetrics& f) const {
    double ke = 0, pe = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      const Real w = m_.inv_mass[i];
      if (!(w > Real(0))) continue;  // kinematic: infinite mass, driven
      const Real mass = Real(1) / w;
      ke += double(Real(0.5) * mass * v[i].squaredNorm());
      pe -= double(mass * g_.dot(x[i]));
    }
    for (int b = 0; b < rw_.num_bodies(); ++b) {
      if (!rw_.is_dynamic(b)) continue;
      const btRigidBody& body = rw_.body(b);
      const Real mass = Real(1) / body.getInvMass();
      const btTransform& t = body.getCenterOfMassTransform();
      const Vec3 vb = vec(body.getLinearVelocity());
      // Rotational energy in the principal frame: w_local = R^T w,
      // E = 1/2 sum_k I_k w_k^2 with I_k = 1 / invI_k (0 where invI_k = 0).
      const Vec3 wl = vec(t.getBasis().transpose() * body.getAngularVelocity());
      const Vec3 inv_i = vec(body.getInvInertiaDiagLocal());
      Real rot = 0;
      for (int k = 0; k < 3; ++k)
        if (inv_i[k] > Real(0)) rot += wl[k] * wl[k] / inv_i[k];
      ke += double(Real(0.5) * (mass * vb.squaredNorm() + rot));
      pe -= double(mass * g_.dot(vec(t.getOrigin())));
    }
    f.kinetic_energy = ke;
    f.potential_energy = pe;
  }

  void strain(std::span<const Vec3> x, FrameMetrics& f) const {
    const auto& dist = m_.get<xpbd::Distance>();
    double sum = 0, mx = 0;
    for (const auto& d : dist) {
      const Real len = (x[static_cast<std::size_t>(d.p[0])] - x[static_cast<std::size_t>(d.p[1])]).norm();
      const double e = std::abs(double(len / d.rest) - 1.0);
      sum += e;
      mx = std::max(mx, e);
    }
    f.max_strain = mx;
    f.mean_strain = dist.empty() ? 0.0 : sum / double(dist.size());
  }

  // Deepest (radius + thickness) - signed distance of a movable particle
  // into a rigid body, 0 if none; pairs joined by an attachment are skipped.
  double penetration(std::span<const Vec3> x) const {
    Real worst = 0;
    for (int b = 0; b < rw_.num_bodies(); ++b) {
      const btRigidBody& obj = rw_.body(b);
      btVector3 lo, hi;
      obj.getCollisionShape()->getAabb(obj.getWorldTransform(), lo, hi);
      const auto& skip = attached_[static_cast<std::size_t>(b)];
      for (std::size_t i = 0; i < x.size(); ++i) {
        if (!(m_.inv_mass[i] > Real(0))) continue;
        const Real reach = m_.radius[i] + thickness_;
        const Vec3& p = x[i];
        if (p.x() < lo.x() - reach || p.y() < lo.y() - reach || p.z() < lo.z() - reach ||
            p.x() > hi.x() + reach || p.y() > hi.y() + reach || p.z() > hi.z() + reach)
          continue;
        if (!skip.empty() && std::binary_search(skip.begin(), skip.end(), static_cast<Index>(i))) continue;
        xpbd_bullet::ParticleContact c;
        if (xpbd_bullet::query_point(obj, p, reach, c) && c.distance < reach)
          worst = std::max(worst, reach - c.distance);
      }
    }
    return double(worst);
  }

  // Smallest centre distance among the pairs that may collide: the explicit
  // Collision pairs, and with self_collision on every pair it does not
  // exclude (both kinematic, or connected). Exact: the grid search radius
  // grows until a pair is found or it covers the whole bounding box.
  std::optional<double> min_pair_distance(std::span<const Vec3> x) {
    Real best = std::numeric_limits<Real>::infinity();
    for (const auto& c : m_.get<xpbd::Collision>())
      best = std::min(best, (x[static_cast<std::size_t>(c.p[0])] - x[static_cast<std::size_t>(c.p[1])]).norm());
    const auto& sc = m_.self_collision;
    if (sc.enabled && x.size() >= 2) {
      Vec3 lo = x[0], hi = x[0];
      for (const Vec3& p : x) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      const Real extent = (hi - lo).norm();
      Real self = std::numeric_limits<Real>::infinity();
      for (Real r = 2 * sc.distance;; r *= 4) {
        xpbd::build_spatial_hash(hash_, x, r);
        xpbd::for_each_close_pair(hash_, x, r, [&](Index i, Index j) {
          if (m_.inv_mass[std::size_t(i)] == Real(0) && m_.inv_mass[std::size_t(j)] == Real(0)) return;
          if (sc.excluded(i, j)) return;
          self = std::min(self, (x[std::size_t(i)] - x[std::size_t(j)]).norm());
        });
        if (std::isfinite(self) || r > extent) break;
      }
      best = std::min(best, self);
    }
    if (!std::isfinite(best)) return std::nullopt;
    return double(best);
  }

  const xpbd::Model& m_;
  RigidWorld& rw_;
  Vec3 g_;
  Real thickness_;
  std::vector<std::vector<Index>> attached_;  // per body: attached particles, sorted
  bool particle_collision_ = false;
  xpbd::SpatialHash hash_;
};


}  // namespace

// The energy moving kinematic bodies can give the rest of the scene, for the
// status's energy budget (J): 2 M v^2, M the mass of everything that moves
// (movable particles and dynamic bodies) and v the fastest speed of a point
// of a kinematic body (|v| + |w| times its bounding sphere's reach from its
// centre of mass). A mass hit by a wall moving at v leaves at most 2v faster;
// 1/2 M (2v)^2 is that for all of it. 0 without kinematic bodies.
static double kinematic_energy_input(const SceneSpec& spec, const xpbd::Model& model, RigidWorld& rw) {
  double v = 0;
  for (std::size_t b = 0; b < spec.bodies.size(); ++b) {
    const RigidSpec& s = spec.bodies[b];
    if (!s.kinematic) continue;
    btVector3 centre;
    btScalar radius = 0;
    rw.body(int(b)).getCollisionShape()->getBoundingSphere(centre, radius);
    v = std::max(v, double(s.velocity.norm()) + double(s.angular_velocity.norm()) * (double(radius) + double(centre.length())));
  }
  if (v == 0) return 0;
  double mass = 0;
  for (const Real w : model.inv_mass)
    if (w > Real(0)) mass += double(Real(1) / w);
  for (int b = 0; b < rw.num_bodies(); ++b)
    if (rw.is_dynamic(b)) mass += 1.0 / double(rw.body(b).getInvMass());
  return 2 * mass * v * v;
}

RunOptions run_options(const SceneSpec& spec) {
  RunOptions o;
  o.solver = spec.solver.method;
  o.dt = spec.solver.dt;
  o.substeps = spec.solver.substeps;
  o.iterations = spec.solver.iterations;
  o.frames = spec.solver.frames;
  o.health.max_strain = spec.solver.max_strain;
  o.tolerance = spec.solver.tolerance;
  o.penetration_tolerance = spec.solver.penetration_tolerance;
  o.tolerance_measure = spec.solver.tolerance_measure;
  o.max_substeps = spec.solver.max_substeps;
  return o;
}

const char* solver_name(Solver s) {
  switch (s) {
    case Solver::xpbd: return "xpbd";
    case Solver::pbd: return "pbd";
    case Solver::bullet: return "bullet";
  }
  return "?";
}

bool bullet_can_express(const SceneSpec& spec, const ExpandedSoft& soft, std::string* why) {
  const auto reasons = bullet_limitations(spec, soft.scene);
  if (why) *why = join(reasons);
  return reasons.empty();
}

bool bullet_can_express(const SceneSpec& spec, std::string* why) {
  return bullet_can_express(spec, expand(spec.soft, spec.base_dir), why);
}

RunResult run_scene(const SceneSpec& spec, const RunOptions& opt, const FrameCallback& on_frame) {
  return run_scene(spec, expand(spec.soft, spec.base_dir), opt, on_frame);
}

RunResult run_scene(const SceneSpec& spec, const ExpandedSoft& soft, const RunOptions& opt,
                    const FrameCallback& on_frame) {
  validate_options(opt, spec);
  validate_contacts(spec.soft.contacts);
  auto model = std::make_shared<const xpbd::Model>(xpbd::compile(soft.scene));
  if (model->num_particles() == 0) throw xpbd::SceneError("soft: the scene has no particles");
  validate_attachments(spec, model->num_particles());
  for (std::size_t i = 0; i < spec.bodies.size(); ++i) validate_body(spec.bodies[i], static_cast<int>(i));
  const bool bullet = opt.solver == Solver::bullet;
  if (bullet) {
    const auto reasons = bullet_limitations(spec, soft.scene);
    if (!reasons.empty()) throw xpbd::SceneError("--solver bullet: " + join(reasons));
  }

  RunResult r;
  r.scene = spec.name;
  r.options = opt;
  r.particles = model->num_particles();
  r.bodies = static_cast<int>(spec.bodies.size());
  r.distance_constraints = static_cast<int>(model->get<xpbd::Distance>().size());
  r.gravity = spec.solver.gravity;

  // Declared before the solver, so the solver (which removes itself from the
  // world) is destroyed first.
  RigidWorld rw(spec.bodies, spec.solver.gravity, bullet, spec.base_dir);
  std::unique_ptr<SoftSim> sim;
  if (bullet) {
    sim = make_softbody_sim(spec, soft.scene, *model, rw, opt, r.solver_settings, r.notes);
  } else {
    sim = make_bridge_sim(spec, model, rw, opt);
    const SoftContactSpec& c = spec.soft.contacts;
    r.solver_settings = {{"world", "btDiscreteDynamicsWorld + XpbdWorld"},
                         {"method", solver_name(opt.solver)},
                         {"substeps", opt.substeps},
                         {"iterations", opt.iterations},
                         {"rigid_steps_per_frame", opt.rigid_steps},
                         {"threads", opt.threads},
                         {"drag", double(spec.solver.drag)},
                         {"alternate_sweeps", spec.solver.alternate_sweeps},
                         {"coloured", spec.solver.coloured},
                         {"direct_chains", spec.solver.direct_chains && opt.solver == Solver::xpbd},
                         {"hierarchy", spec.solver.hierarchy && opt.solver != Solver::bullet},
                         {"contacts",
                          {{"enabled", !spec.bodies.empty()},
                           {"thickness", double(c.thickness)},
                           {"margin", double(c.margin)},
                           {"static_friction", double(c.static_friction)},
                           {"dynamic_friction", double(c.dynamic_friction)},
                           {"restitution", double(c.restitution)},
                           {"compliance", double(c.compliance)},
                           {"feature_spacing", double(c.feature_spacing)},
                           {"wedges", c.wedges},
                           {"edge_contacts", c.edge_contacts},
                           {"surface_edges", c.surface_edges}}},
                         {"attachments", spec.attachments.size()}};
  }
  r.projections_per_frame = sim->projections_per_frame();

  Measurer meas(spec, *model, rw);
  r.particle_collision = meas.particle_collision();
  std::vector<BodyPose> poses;
  detail::Summary summary;
  summary.set_energy_input(kinematic_energy_input(spec, *model, rw));
  auto report = [&](int frame, bool finite, double wall_ms) {
    const double t = double(frame) * double(opt.dt);
    FrameMetrics fm = meas.measure(t, sim->x(), sim->v(), finite);
    if (frame >= 1) {
      fm.substeps = sim->frame_substeps();
      fm.tolerance_met = sim->frame_tolerance_met();
    }
    if (frame >= 1) summary.add(fm);
    else summary.start(fm);
    if (opt.keep_series) r.series.push_back(fm);
    if (!on_frame) return;
    rw.poses(poses);
    FrameView view;
    view.frame = frame;
    view.time = t;
    view.positions = sim->x();
    view.bodies = poses;
    view.finite = finite;
    view.metrics = &fm;
    view.wall_ms = wall_ms;
    on_frame(view);
  };

  if (opt.keep_series) {
    r.series.reserve(static_cast<std::size_t>(opt.frames) + 1);
    r.frame_ms.reserve(static_cast<std::size_t>(opt.frames));
  }
  report(0, all_finite(sim->x()) && all_finite(sim->v()) && rw.finite(), 0);
  for (int f = 1; f <= opt.frames && r.finite; ++f) {
    bool ok = true;
    const auto t0 = Clock::now();
    try {
      ok = sim->step_frame();
    } catch (const std::invalid_argument&) {
      // A query refusing a non-finite input (narrowphase.hpp) means the state
      // went non-finite inside the frame, or blew up so far (beyond 1e30 m or
      // m/s, where products of coordinates overflow) that a derived quantity
      // did; anything else is a real error.
      const bool blown_up = !all_finite(sim->x()) || !all_finite(sim->v()) || !rw.finite() ||
                            beyond(sim->x(), 1e30) || beyond(sim->v(), 1e30);
      if (!blown_up) throw;
      if (all_finite(sim->x()) && all_finite(sim->v()))
        r.notes.push_back("frame " + std::to_string(f) + ": the state exceeded 1e30 (m or m/s) and a collision "
                          "query refused it; the run is reported as non-finite");
      ok = false;
    }
    const auto t1 = Clock::now();
    const double ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    if (opt.keep_series) r.frame_ms.push_back(ms);
    summary.add_ms(ms);
    r.frames_completed = f;
    r.finite = ok;
    report(f, ok, ms);
  }
  summary.apply(r);
  if (r.finite && r.frames_completed > 0) r.forces = sim->forces(spec, r.notes);
  rw.poses(poses);
  r.state_hash = state_hash(sim->x(), sim->v(), poses);
  if (const xpbd_bullet::SystemTimes* t = sim->times(); t && r.frames_completed > 0)
    r.stage_ms_per_frame = detail::stage_breakdown(*t, double(r.frames_completed), r.wall_ms_mean);
  else if (bullet && opt.stage_times)
    r.notes.push_back("stage_times: not available for btSoftBody (it has no per-stage hooks); "
                      "only wall_ms_per_frame is measured");
  return r;
}

}  // namespace xpbd_demos

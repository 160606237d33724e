// XPBD/PBD and btSoftBody runs of a scene's particles (soft_sim.hpp).
#include "demos/soft_sim.hpp"

#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "xpbd/error.hpp"
#include "xpbd/state.hpp"
#include "xpbd/workers.hpp"
#include "xpbd_bullet/softbody_builder.hpp"

namespace xpbd_demos {

using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;

bool all_finite(std::span<const Vec3> a) {
  for (const Vec3& v : a)
    if (!v.allFinite()) return false;
  return true;
}

// Radius shared by all movable particles, or nullopt if they differ.
std::optional<Real> uniform_radius(const xpbd::SceneDesc& s) {
  std::optional<Real> r;
  for (std::size_t i = 0; i < s.positions.size(); ++i) {
    if (s.masses[i] == Real(0)) continue;
    const Real ri = s.radii.empty() ? Real(0) : s.radii[i];
    if (!r) r = ri;
    else if (*r != ri) return std::nullopt;
  }
  return r ? r : Real(0);
}

std::string num(double v) {
  std::ostringstream o;
  o.precision(9);
  o << v;
  return o.str();
}

namespace {

btVector3 bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }
Vec3 vec(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }

// The attachment point in the body's centre-of-mass frame (m).
btVector3 attachment_local(const AttachmentSpec& a, const btRigidBody& body, const Vec3& x0) {
  if (a.local) return bt(*a.local);
  return body.getCenterOfMassTransform().inverse() * bt(x0);
}

long long constraint_elements(const xpbd::Model& m) {
  long long n = 0;
  xpbd::for_each_constraint_type([&]<class T>(std::type_identity<T>) {
    n += static_cast<long long>(m.get<T>().size());
  });
  return n;
}

class XpbdSim : public SoftSim {
 public:
  XpbdSim(const SceneSpec& spec, std::shared_ptr<const xpbd::Model> model, RigidWorld& rw,
          const RunOptions& opt)
      : rw_(rw), dt_(opt.dt / Real(opt.rigid_steps)), rigid_steps_(opt.rigid_steps), world_(rw.world()) {
    xpbd_bullet::SystemSettings s;
    s.substeps = opt.substeps / opt.rigid_steps;  // per Bullet step (validate_options: divides)
    s.iterations = opt.iterations;
    s.method = opt.solver == Solver::pbd ? xpbd::Method::pbd : xpbd::Method::xpbd;
    s.drag = spec.solver.drag;
    s.alternate_sweeps = spec.solver.alternate_sweeps;
    s.coloured = spec.solver.coloured;
    s.direct_chains = spec.solver.direct_chains && opt.solver == Solver::xpbd;
    s.chain_passes = spec.solver.chain_passes;
    s.chain_tolerance = spec.solver.chain_tolerance;
    s.hierarchy = spec.solver.hierarchy;
    s.hierarchy_slack = spec.solver.hierarchy_slack;
    if (opt.threads > 1) {
      workers_ = std::make_unique<xpbd::Workers>(opt.threads);
      s.workers = workers_.get();
    }
    const SoftContactSpec& c = spec.soft.contacts;
    s.contacts.enabled = !spec.bodies.empty();
    s.contacts.margin = c.margin;
    s.contacts.thickness = c.thickness;
    s.contacts.static_friction = c.static_friction;
    s.contacts.dynamic_friction = c.dynamic_friction;
    s.contacts.restitution = c.restitution;
    s.contacts.compliance = c.compliance;
    s.contacts.feature_spacing = c.feature_spacing;
    s.contacts.wedges = c.wedges;
    s.contacts.edge_contacts = c.edge_contacts;
    s.contacts.surface_edge_contacts = c.surface_edges;
    s.tolerance.strain = opt.tolerance;
    s.tolerance.measure = opt.tolerance_measure == ToleranceMeasure::residual ? xpbd_bullet::StrainMeasure::residual
                                                                             : xpbd_bullet::StrainMeasure::total;
    s.tolerance.penetration = opt.penetration_tolerance;
    s.tolerance.max_substeps = opt.max_substeps;
    timing_ = opt.stage_times;
    if (timing_) s.times = &times_;
    projections_ = static_cast<long long>(opt.substeps) * opt.iterations * constraint_elements(*model);
    xpbd::State state = xpbd::make_state(*model);
    id_ = world_.add_system(model, std::move(state), s);
    const xpbd::Model& m = world_.model(id_);
    for (const AttachmentSpec& a : spec.attachments) {
      btRigidBody& body = rw.body(a.body);
      world_.attach(id_, a.particle, &body,
                    attachment_local(a, body, m.x0[static_cast<std::size_t>(a.particle)]), a.compliance);
    }
  }

  bool step_frame() override {
    frame_substeps_ = 0;
    frame_met_ = true;
    for (int k = 0; k < rigid_steps_; ++k) {
      rw_.step(dt_);
      frame_substeps_ += world_.health(id_).substeps;
      frame_met_ = frame_met_ && world_.health(id_).tolerance_met;
    }
    // XpbdWorld throws nothing out of stepSimulation: a failed step is
    // recorded. Report it as the step's exception (run_scene classifies it).
    if (const std::string& e = world_.error(id_); !e.empty()) throw std::invalid_argument(e);
    const xpbd::State& s = world_.state(id_);
    return all_finite(s.x) && all_finite(s.v) && rw_.finite();
  }
  std::span<const Vec3> x() override { return world_.state(id_).x; }
  std::span<const Vec3> v() override { return world_.state(id_).v; }
  long long projections_per_frame() const override { return projections_; }
  const xpbd_bullet::SystemTimes* times() const override { return timing_ ? &times_ : nullptr; }
  std::optional<int> frame_substeps() const override {
    if (!world_.settings(id_).tolerance.on()) return std::nullopt;
    return frame_substeps_;
  }
  bool frame_tolerance_met() const override { return frame_met_; }
  std::optional<RunForces> forces(const SceneSpec& spec, std::vector<std::string>& notes) const override {
    if (world_.settings(id_).method != xpbd::Method::xpbd) return {};
    return read_forces(spec, world_.model(id_), world_.state(id_), spec.solver.gravity, notes);
  }

 private:
  RigidWorld& rw_;
  Real dt_;             // s, one Bullet step: the frame's dt / rigid_steps_
  int rigid_steps_ = 1;  // Bullet steps per frame
  int frame_substeps_ = 0;  // substeps of the last frame (all its Bullet steps)
  bool frame_met_ = true;   // every step of the last frame met the tolerance
  bool timing_ = false;
  xpbd_bullet::SystemTimes times_;  // before world_: outlives the system
  std::unique_ptr<xpbd::Workers> workers_;  // before world_: outlives the system
  xpbd_bullet::XpbdWorld world_;  // removes its action from the world when destroyed
  xpbd_bullet::SystemId id_;
  long long projections_ = 0;
};

class BulletSim : public SoftSim {
 public:
  BulletSim(const SceneSpec& spec, const xpbd::SceneDesc& scene, const xpbd::Model& model, RigidWorld& rw,
            const RunOptions& opt, nlohmann::json& settings, std::vector<std::string>& notes)
      : rw_(rw), h_(opt.dt / Real(opt.substeps)), substeps_(opt.substeps) {
    btSoftRigidDynamicsWorld& w = *rw.soft_world();
    btSoftBodyWorldInfo& info = w.getWorldInfo();
    // Voxel of the sparse SDF btSoftBody's node contacts read (trilinear
    // interpolation of GJK distances sampled on the voxel grid): a quarter of
    // the thinnest rigid feature (docs/design.md section 5 asks for no more than
    // the feature; at the full feature size the interpolation rounds a box's
    // edges by centimetres, see docs/metrics.md), at most Bullet's 0.25 m.
    const Real voxel = opt.bullet_sdf_voxel > Real(0)
                           ? opt.bullet_sdf_voxel
                           : std::min(Real(0.25), rw.thinnest_feature() / Real(4));
    info.m_sparsesdf.setDefaultVoxelsz(voxel);
    info.m_sparsesdf.Reset();

    const SoftContactSpec& c = spec.soft.contacts;
    xpbd_bullet::SoftBodyBuildConfig bc;
    bc.piterations = opt.iterations;
    bc.kLST = spec.solver.bullet_kLST;
    // xpbd's drag scales velocities by exp(-drag h) every substep; Bullet by
    // (1 - kDP) every internal step, and here an internal step is a substep.
    bc.kDP = Real(1) - std::exp(-spec.solver.drag * h_);
    // The distance kept from rigid surfaces: radius + thickness, as xpbd.
    const Real radius = spec.bodies.empty() ? Real(0) : uniform_radius(scene).value_or(Real(0));
    bc.margin = c.thickness + radius;
    bc.friction = c.dynamic_friction;
    body_ = xpbd_bullet::build_softbody(info, scene, model, bc);
    w.addSoftBody(body_.get());
    for (const AttachmentSpec& a : spec.attachments) {
      btRigidBody& rb = rw.body(a.body);
      body_->appendAnchor(a.particle, &rb,
                          attachment_local(a, rb, model.x0[static_cast<std::size_t>(a.particle)]), false, 1);
    }
    projections_ = static_cast<long long>(opt.substeps) * opt.iterations * body_->m_links.size();
    x_.resize(static_cast<std::size_t>(body_->m_nodes.size()));
    v_.resize(x_.size());
    copy();

    settings = {{"world", "btSoftRigidDynamicsWorld"},
                {"internal_steps_per_frame", opt.substeps},
                {"internal_step", double(h_)},
                {"piterations", opt.iterations},
                {"viterations", 0},
                {"diterations", 0},
                {"kLST", double(bc.kLST)},
                {"kDP", double(bc.kDP)},
                {"kDF", double(bc.friction)},
                {"kCHR", 1},
                {"kKHR", 1},
                {"kAHR", 1},
                {"margin", double(bc.margin)},
                {"collisions", "SDF_RS"},
                {"sdf_voxel", double(voxel)},
                {"links", body_->m_links.size()},
                {"anchors", body_->m_anchors.size()},
                {"sleeping", false}};
    notes.push_back("btSoftBody: every Distance element is a link with kLST = " + num(bc.kLST) +
                    "; the scene's distance compliances and stiffnesses are not used");
    if (spec.solver.alternate_sweeps)
      notes.push_back("btSoftBody: alternate_sweeps is not used (btSoftBody sweeps its links in one order)");
    if (spec.solver.coloured)
      notes.push_back("btSoftBody: coloured is not used (btSoftBody sweeps its links in one order)");
    if (spec.solver.direct_chains)
      notes.push_back("btSoftBody: direct_chains is not used (btSoftBody sweeps its links)");
    if (spec.solver.hierarchy)
      notes.push_back("btSoftBody: hierarchy is not used (btSoftBody sweeps its links)");
    if (opt.tolerance > 0)
      notes.push_back("btSoftBody: tolerance is not used (it runs the fixed substeps x iterations)");
    if (opt.penetration_tolerance > 0)
      notes.push_back("btSoftBody: penetration_tolerance is not used (it runs the fixed substeps x iterations)");
    if (!spec.bodies.empty()) {
      if (!model.collision_triangles.empty())
        notes.push_back("btSoftBody: the " + std::to_string(model.collision_triangles.size()) +
                        " collision_triangles are not used; btSoftBody collides its nodes only (SDF_RS)");
      if (c.static_friction != c.dynamic_friction)
        notes.push_back("btSoftBody: one friction coefficient, kDF = dynamic_friction; "
                        "static_friction is not used");
      for (std::size_t b = 0; b < spec.bodies.size(); ++b) {
        const ShapeKind k = spec.bodies[b].shape.kind;
        if (k == ShapeKind::plane || k == ShapeKind::mesh)
          notes.push_back("btSoftBody: bodies[" + std::to_string(b) +
                          "] is concave: btSoftBody collides with each triangle as a hull extruded "
                          "0.06 m to both sides and grown by the hull's 0.04 m margin, so its nodes "
                          "rest about 0.1 m in front of the surface (docs/metrics.md)");
      }
    }
    if (!spec.attachments.empty())
      notes.push_back("btSoftBody: anchored nodes do not collide with rigid bodies");
  }

  ~BulletSim() override { rw_.soft_world()->removeSoftBody(body_.get()); }

  bool step_frame() override {
    for (int s = 0; s < substeps_; ++s) {
      rw_.step(h_);
      if (!nodes_finite()) {
        copy();
        return false;
      }
    }
    // Drops the SDF cells no node has touched for a while (as Bullet's own
    // demos do once per frame); part of btSoftBody's cost.
    rw_.soft_world()->getWorldInfo().m_sparsesdf.GarbageCollect();
    copy();
    return rw_.finite();
  }
  std::span<const Vec3> x() override { return x_; }
  std::span<const Vec3> v() override { return v_; }
  long long projections_per_frame() const override { return projections_; }

 private:
  bool nodes_finite() const {
    auto ok = [](const btVector3& a) { return std::isfinite(a.x()) && std::isfinite(a.y()) && std::isfinite(a.z()); };
    for (int i = 0; i < body_->m_nodes.size(); ++i)
      if (!ok(body_->m_nodes[i].m_x) || !ok(body_->m_nodes[i].m_v)) return false;
    return true;
  }
  void copy() {
    for (int i = 0; i < body_->m_nodes.size(); ++i) {
      x_[static_cast<std::size_t>(i)] = vec(body_->m_nodes[i].m_x);
      v_[static_cast<std::size_t>(i)] = vec(body_->m_nodes[i].m_v);
    }
  }

  RigidWorld& rw_;
  Real h_;
  int substeps_;
  std::unique_ptr<btSoftBody> body_;
  std::vector<Vec3> x_, v_;
  long long projections_ = 0;
};

}  // namespace

std::unique_ptr<SoftSim> make_bridge_sim(const SceneSpec& spec, std::shared_ptr<const xpbd::Model> model,
                                         RigidWorld& rw, const RunOptions& opt) {
  return std::make_unique<XpbdSim>(spec, std::move(model), rw, opt);
}

std::unique_ptr<SoftSim> make_softbody_sim(const SceneSpec& spec, const xpbd::SceneDesc& scene,
                                           const xpbd::Model& model, RigidWorld& rw, const RunOptions& opt,
                                           nlohmann::json& settings, std::vector<std::string>& notes) {
  return std::make_unique<BulletSim>(spec, scene, model, rw, opt, settings, notes);
}

}  // namespace xpbd_demos

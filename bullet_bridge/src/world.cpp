#include "xpbd_bullet/world.hpp"

#include <LinearMath/btTransformUtil.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#include "world_impl.hpp"
#include "world_marker.hpp"
#include "xpbd/error.hpp"

namespace xpbd_bullet {

namespace {

void check_settings(const SystemSettings& s) {
  auto bad = [](const std::string& field, const std::string& what) {
    throw xpbd::ConfigError("SystemSettings." + field + ": " + what);
  };
  if (s.substeps < 1) bad("substeps", "must be >= 1, got " + std::to_string(s.substeps));
  if (s.iterations < 1) bad("iterations", "must be >= 1, got " + std::to_string(s.iterations));
  if (s.contact_sweeps < 0)
    bad("contact_sweeps", "must be >= 0, got " + std::to_string(s.contact_sweeps));
  if (!(s.contact_tolerance >= Real(0)) || !std::isfinite(s.contact_tolerance))
    bad("contact_tolerance", "must be finite and >= 0, got " + xpbd::format_value(double(s.contact_tolerance)));
  const ContactSettings& c = s.contacts;
  auto nonneg = [&](const char* f, Real v) {
    if (!(v >= Real(0)) || !std::isfinite(v))
      bad(std::string("contacts.") + f, "must be finite and >= 0, got " + xpbd::format_value(double(v)));
  };
  nonneg("margin", c.margin);
  nonneg("thickness", c.thickness);
  nonneg("static_friction", c.static_friction);
  nonneg("dynamic_friction", c.dynamic_friction);
  nonneg("restitution", c.restitution);
  nonneg("compliance", c.compliance);
  if (!(c.feature_spacing > Real(0)) || !std::isfinite(c.feature_spacing))
    bad("contacts.feature_spacing", "must be finite and > 0, got " + xpbd::format_value(double(c.feature_spacing)));
  if (c.triangle_bvh_from < 0)
    bad("contacts.triangle_bvh_from", "must be >= 0, got " + std::to_string(c.triangle_bvh_from));
  if (c.restitution > Real(1)) bad("contacts.restitution", "must be <= 1, got " + xpbd::format_value(double(c.restitution)));
  if (!(s.sleep_speed >= Real(0)) || !std::isfinite(s.sleep_speed))
    bad("sleep_speed", "must be finite and >= 0, got " + xpbd::format_value(double(s.sleep_speed)));
  if (!(s.sleep_time > Real(0)) || !std::isfinite(s.sleep_time))
    bad("sleep_time", "must be finite and > 0, got " + xpbd::format_value(double(s.sleep_time)));
  if (s.direct_chains && s.method != xpbd::Method::xpbd)
    bad("direct_chains", "needs method xpbd (the direct solve is XPBD's linearised system)");
  if (s.chain_passes < 1) bad("chain_passes", "must be >= 1, got " + std::to_string(s.chain_passes));
  if (!(s.chain_tolerance >= Real(0)) || !std::isfinite(s.chain_tolerance))
    bad("chain_tolerance", "must be finite and >= 0, got " + xpbd::format_value(double(s.chain_tolerance)));
  if (!(s.hierarchy_slack >= Real(0)) || !std::isfinite(s.hierarchy_slack))
    bad("hierarchy_slack", "must be finite and >= 0, got " + xpbd::format_value(double(s.hierarchy_slack)));
  if (s.workers != nullptr && !s.coloured)
    bad("workers", "the threads split the coloured sweep; set coloured = true");
  xpbd::validate(s.health, "SystemSettings.health.");
  if (!(s.tolerance.strain >= 0) || !std::isfinite(s.tolerance.strain))
    bad("tolerance.strain", "must be finite and >= 0 (0 = off), got " + xpbd::format_value(s.tolerance.strain));
  if (!(s.tolerance.penetration >= 0) || !std::isfinite(s.tolerance.penetration))
    bad("tolerance.penetration",
        "must be finite and >= 0 (m, 0 = off), got " + xpbd::format_value(s.tolerance.penetration));
  if (s.tolerance.max_substeps < 1)
    bad("tolerance.max_substeps", "must be >= 1, got " + std::to_string(s.tolerance.max_substeps));
  if (s.tolerance.measure != StrainMeasure::total && s.tolerance.measure != StrainMeasure::residual)
    bad("tolerance.measure", "must be StrainMeasure::total or residual, got " +
                                 std::to_string(static_cast<int>(s.tolerance.measure)));
  if (s.tolerance.measure == StrainMeasure::residual && s.method != xpbd::Method::xpbd)
    bad("tolerance.measure", "StrainMeasure::residual needs method xpbd (PBD's multipliers are not XPBD's)");
}

// Bullet has no getter for the pre-tick callback; it is a protected member
// of btDynamicsWorld, readable through a derived class's member pointer.
struct TickPeek : btDynamicsWorld {
  static btInternalTickCallback pre_tick(const btDynamicsWorld& w) {
    return w.*(&TickPeek::m_internalPreTickCallback);
  }
};

// Which XpbdWorld serves which Bullet world: the hook is a plain function,
// and the world's user info belongs to the application.
struct Registry {
  std::mutex mutex;
  std::vector<std::pair<const btDynamicsWorld*, XpbdWorld*>> entries;
};
Registry& registry() {
  static Registry r;
  return r;
}
XpbdWorld* find_registered(const btDynamicsWorld* w) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  for (const auto& [world, xw] : r.entries)
    if (world == w) return xw;
  return nullptr;
}

// The residual must not push a body into what Bullet's solver just kept it
// out of. Bullet's own contacts with static and kinematic bodies (the
// ground under a box that a cloth presses down) are solved once per Bullet step, after XPBD; a residual
// applied after that solve would sink or tilt the body into them a little
// every step (measured: a 0.2 kg box under a 0.3 kg cloth, 60 Hz x 10, sank
// 4.9 cm in 2 s, up to 9.5 cm at 20 substeps). The residual (dx, a translation;
// dtheta, a small rotation vector) is projected onto those contacts like an
// XPBD position solve of the body alone: at every point of the body's
// contact manifolds closer than the manifold's processing threshold, a
// displacement into the other body, (dx + dtheta x r) . n < 0, is removed
// with the body's generalized inverse mass (a few Gauss-Seidel passes, so
// that a box on several corners settles on all of them). Only what pushes
// inward beyond the point's gap at the body's current pose is removed; the
// support itself does not move. Returns whether
// anything was removed.
bool clip_to_contacts(btVector3& dx, btVector3& dtheta, const btRigidBody* rb, btCollisionWorld* cw) {
  if (!cw || (dx.isZero() && dtheta.isZero())) return false;
  bool clipped = false;
  btDispatcher* disp = cw->getDispatcher();
  const btVector3 com = rb->getCenterOfMassPosition();
  const btMatrix3x3& inv_i = rb->getInvInertiaTensorWorld();
  const btScalar inv_m = rb->getInvMass();
  for (int pass = 0; pass < 4; ++pass) {
    bool changed = false;
    for (int m = 0; m < disp->getNumManifolds(); ++m) {
      const btPersistentManifold* pm = disp->getManifoldByIndexInternal(m);
      const bool is_a = pm->getBody0() == rb, is_b = pm->getBody1() == rb;
      if (!is_a && !is_b) continue;
      // Only static and kinematic supports: a dynamic one (a box stacked on
      // a coupled tray) moves with the push, and the prediction of Bullet's
      // contact load already carries it (clipping there made the stack test's
      // gaps 0.1 mm larger).
      const btCollisionObject* other = is_a ? pm->getBody1() : pm->getBody0();
      if (!other->isStaticOrKinematicObject()) continue;
      for (int k = 0; k < pm->getNumContacts(); ++k) {
        const btManifoldPoint& pt = pm->getContactPoint(k);
        if (pt.getDistance() > pm->getContactProcessingThreshold()) continue;
        // normalWorldOnB points from body 1 towards body 0: out of the
        // support for body 0.
        const btVector3 n = is_a ? pt.m_normalWorldOnB : -pt.m_normalWorldOnB;
        const btVector3 r = (is_a ? pt.getPositionWorldOnA() : pt.getPositionWorldOnB()) - com;
        // The gap at the body's pose now (after Bullet's integration) may
        // be closed: only a displacement beyond it is into the support.
        const btVector3 self = rb->getWorldTransform() * (is_a ? pt.m_localPointA : pt.m_localPointB);
        const btVector3 support = other->getWorldTransform() * (is_a ? pt.m_localPointB : pt.m_localPointA);
        const btScalar gap = btMax((self - support).dot(n), btScalar(0));
        const btScalar into = (dx + dtheta.cross(r)).dot(n) + gap;
        if (into >= 0) continue;
        const btVector3 rn = r.cross(n);
        const btVector3 i_rn = rb->getAngularFactor() * (inv_i * rn);
        const btScalar w = inv_m * (rb->getLinearFactor() * n).dot(n) + rn.dot(i_rn);
        if (!(w > 0)) continue;
        const btScalar lambda = -into / w;
        dx += lambda * inv_m * (rb->getLinearFactor() * n);
        dtheta += lambda * i_rn;
        changed = clipped = true;
      }
    }
    if (!changed) break;
  }
  return clipped;
}

// Removes from (dv, dw) the velocity change that Bullet's solver gave rb
// through its contacts with static bodies in this step (the normal and both
// friction impulses of every manifold point). Kinematic bodies are not
// static: XPBD does not solve those contacts.
void remove_static_contact_impulses(const btRigidBody* rb, btCollisionWorld* cw, btVector3& dv, btVector3& dw) {
  if (!cw) return;
  btDispatcher* disp = cw->getDispatcher();
  const btVector3 com = rb->getCenterOfMassPosition();
  for (int m = 0; m < disp->getNumManifolds(); ++m) {
    const btPersistentManifold* pm = disp->getManifoldByIndexInternal(m);
    const bool is_a = pm->getBody0() == rb, is_b = pm->getBody1() == rb;
    if (!is_a && !is_b) continue;
    const btCollisionObject* other = is_a ? pm->getBody1() : pm->getBody0();
    if (!other->isStaticObject() || other->isKinematicObject()) continue;
    for (int k = 0; k < pm->getNumContacts(); ++k) {
      const btManifoldPoint& pt = pm->getContactPoint(k);
      // Bullet's solver pushes body 0 along +normalWorldOnB and the
      // friction directions, body 1 the other way.
      btVector3 j = pt.m_normalWorldOnB * pt.m_appliedImpulse +
                    pt.m_lateralFrictionDir1 * pt.m_appliedImpulseLateral1 +
                    pt.m_lateralFrictionDir2 * pt.m_appliedImpulseLateral2;
      if (!is_a) j = -j;
      const btVector3 r = (is_a ? pt.getPositionWorldOnA() : pt.getPositionWorldOnB()) - com;
      dv -= rb->getLinearFactor() * j * rb->getInvMass();
      dw -= rb->getAngularFactor() * (rb->getInvInertiaTensorWorld() * r.cross(j));
    }
  }
}

// The rotation dq with its rotation vector scaled axis by axis (Bullet's
// angular factor, world axes).
btQuaternion scaled_rotation(const btQuaternion& dq, const btVector3& factor) {
  if (factor == btVector3(1, 1, 1)) return dq;
  btQuaternion q = dq;
  if (q.w() < 0) q = -q;  // the short way round
  const btScalar s = q.getAxis().length2() > 0 ? q.getAngle() : btScalar(0);
  const btVector3 rv = s > 0 ? q.getAxis() * s * factor : btVector3(0, 0, 0);
  const btScalar angle = rv.length();
  return angle > 0 ? btQuaternion(rv / angle, angle) : btQuaternion::getIdentity();
}

}  // namespace

XpbdWorld::XpbdWorld(btDiscreteDynamicsWorld& world) : world_(world) {
  {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    // An entry whose world has been destroyed (its XpbdWorld not yet) may
    // name a new world at the same address: it is stale.
    std::erase_if(r.entries, [&](const auto& e) { return e.first == &world && e.second->world_gone(); });
    for (const auto& e : r.entries)
      if (e.first == &world)
        throw xpbd::ConfigError("XpbdWorld: this Bullet world already has an XpbdWorld (one per world; "
                                "add several systems to it instead)");
    r.entries.emplace_back(&world, this);
  }
  marker_ = new detail::WorldMarker(this);
  world_.addCollisionObject(marker_, 0, 0);
  install_hook();
  world_.addAction(this);
}

XpbdWorld::~XpbdWorld() {
  if (world_gone()) {
    // The Bullet world was destroyed first: nothing of it may be touched
    // (its dispatcher released the spacers' manifolds with it or not; they
    // are its to free).
    spacers_.clear();
  } else {
    release_spacers();
    world_.removeAction(this);
    // Give the slot back to the callback we chained, unless someone
    // installed theirs after ours (then it is theirs to keep).
    if (hook_installed()) world_.setInternalTickCallback(chained_, world_.getWorldUserInfo(), true);
    if (marker_ != nullptr && marker_->in_world()) world_.removeCollisionObject(marker_);
  }
  if (marker_ != nullptr) {
    marker_->owner = nullptr;
    delete marker_;
  }
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  std::erase_if(r.entries, [&](const auto& e) { return e.second == this; });
}

bool XpbdWorld::hook_installed() const { return TickPeek::pre_tick(world_) == &XpbdWorld::pre_tick; }

void XpbdWorld::install_hook() {
  if (hook_installed()) return;
  chained_ = TickPeek::pre_tick(world_);
  // setInternalTickCallback also sets the world's user info: pass it through.
  world_.setInternalTickCallback(&XpbdWorld::pre_tick, world_.getWorldUserInfo(), true);
}

void XpbdWorld::pre_tick(btDynamicsWorld* world, btScalar dt) {
  XpbdWorld* xw = find_registered(world);
  if (xw == nullptr) return;
  if (xw->chained_) xw->chained_(world, dt);  // the application's own pre-tick first
  xw->pre_solve(dt);
}

SystemId XpbdWorld::add_system(std::shared_ptr<const xpbd::Model> model, xpbd::State state,
                          const SystemSettings& settings) {
  if (!model) throw xpbd::ConfigError("add_system: model is null");
  check_settings(settings);
  const auto n = static_cast<std::size_t>(model->num_particles());
  if (state.x.size() != n || state.v.size() != n || state.x_prev.size() != n)
    throw xpbd::ConfigError("add_system: state has " + std::to_string(state.x.size()) +
                            " particles, model has " + std::to_string(n) + " (use xpbd::make_state)");
  auto s = std::make_unique<System>();
  s->id = next_id_++;
  s->model = std::move(model);
  s->state = std::move(state);
  s->settings = settings;
  systems_.push_back(std::move(s));
  return SystemId(systems_.back()->id);
}

void XpbdWorld::remove_system(SystemId id) {
  auto it = std::find_if(systems_.begin(), systems_.end(), [&](auto& s) { return s->id == id.value; });
  if (it == systems_.end()) throw std::out_of_range("remove_system: no system with id " + std::to_string(id.value));
  systems_.erase(it);
  std::erase_if(attachments_, [&](const Attachment& a) { return a.system == id.value; });
}

bool XpbdWorld::has_system(SystemId id) const {
  return std::any_of(systems_.begin(), systems_.end(), [&](auto& s) { return s->id == id.value; });
}

XpbdWorld::System& XpbdWorld::system(SystemId id) {
  for (auto& s : systems_)
    if (s->id == id.value) return *s;
  throw std::out_of_range("XpbdWorld: no system with id " + std::to_string(id.value));
}
const XpbdWorld::System& XpbdWorld::system(SystemId id) const {
  return const_cast<XpbdWorld*>(this)->system(id);
}

xpbd::State& XpbdWorld::state(SystemId id) { return system(id).state; }
const xpbd::State& XpbdWorld::state(SystemId id) const { return system(id).state; }
const xpbd::Model& XpbdWorld::model(SystemId id) const { return *system(id).model; }
const SystemSettings& XpbdWorld::settings(SystemId id) const { return system(id).settings; }
xpbd::Model& XpbdWorld::own_model(SystemId id) {
  System& s = system(id);
  if (!s.own_model) {
    s.own_model = std::make_shared<xpbd::Model>(*s.model);
    s.model = s.own_model;
  }
  // A material is about to change: the system must step again.
  s.asleep = false;
  s.quiet = 0;
  return *s.own_model;
}
void XpbdWorld::set_settings(SystemId id, const SystemSettings& settings) {
  System& s = system(id);
  check_settings(settings);
  s.settings = settings;
  s.tol_substeps = 0;
  s.tol_calm = 0;
  s.tol_window_max = 0;
  s.tol_futile_error = 0;
  s.tol_futile_steps = 0;
  s.asleep = false;
  s.quiet = 0;
}

AttachmentId XpbdWorld::attach(SystemId id, Index particle, btRigidBody* body, const btVector3& local,
                      Real compliance) {
  System& s = system(id);
  if (particle < 0 || particle >= s.model->num_particles())
    throw xpbd::ConfigError("attach: particle index " + std::to_string(particle) +
                            " out of range [0, " + std::to_string(s.model->num_particles()) + ")");
  if (!body) throw xpbd::ConfigError("attach: body is null");
  if (!in_world(world_, body)) throw xpbd::ConfigError("attach: body is not in the world");
  if (!(compliance >= Real(0)) || !std::isfinite(compliance))
    throw xpbd::ConfigError("attach: compliance must be finite and >= 0, got " + std::to_string(compliance));
  if (!to_vec(local).allFinite())
    throw xpbd::ConfigError("attach: local point " + xpbd::format_vec(to_vec(local)) + " must be finite");
  attachments_.push_back(
      Attachment{next_attachment_, id.value, particle, body, local, compliance, BodyIdentity::of(body)});
  return AttachmentId(next_attachment_++);
}

void XpbdWorld::remove_attachment(AttachmentId attachment_id) {
  const auto n = std::erase_if(attachments_, [&](const Attachment& a) { return a.id == attachment_id.value; });
  if (n == 0)
    throw std::out_of_range("remove_attachment: no attachment with id " + std::to_string(attachment_id.value));
}

bool XpbdWorld::has_attachment(AttachmentId attachment_id) const {
  return std::any_of(attachments_.begin(), attachments_.end(),
                     [&](const Attachment& a) { return a.id == attachment_id.value; });
}

void XpbdWorld::drop_departed_bodies() {
  if (attachments_.empty() && predicted_.empty()) return;
  const auto& arr = world_.getCollisionObjectArray();
  live_.resize(std::size_t(arr.size()));
  for (int i = 0; i < arr.size(); ++i) live_[std::size_t(i)] = arr[i];
  std::sort(live_.begin(), live_.end());
  stats_.dropped_attachments +=
      int(std::erase_if(attachments_, [&](const Attachment& a) { return !a.identity.alive(live_); }));
  std::erase_if(predicted_, [&](const Predicted& p) { return !p.identity.alive(live_); });
}

const std::string& XpbdWorld::error(SystemId id) const { return system(id).error; }

const SystemHealth& XpbdWorld::health(SystemId id) const { return system(id).health; }

const std::vector<BodyContactReport>& XpbdWorld::contact_report(SystemId id) const { return system(id).report; }

void XpbdWorld::set_step_callback(SystemId id, StepCallback callback) { system(id).callback = std::move(callback); }

void XpbdWorld::run_callbacks(btScalar dt) {
  // By id, from a copy: a callback may add or remove systems.
  callback_ids_.clear();
  for (const auto& s : systems_)
    if (s->callback && s->error.empty() && s->stepped) callback_ids_.push_back(SystemId(s->id));
  for (const SystemId id : callback_ids_) {
    if (!has_system(id)) continue;
    System& s = system(id);
    if (!s.callback || !s.error.empty()) continue;
    const StepCallback cb = s.callback;  // the callback may replace itself
    try {
      cb(id, dt);
    } catch (const std::exception& e) {
      if (has_system(id)) system(id).error = std::string("step callback: ") + e.what();
    } catch (...) {
      if (has_system(id)) system(id).error = "step callback: an exception that is not a std::exception";
    }
  }
}

// ---------------------------------------------------------------------------

void XpbdWorld::pre_solve(btScalar dt) {
  run_systems(dt);
  hand_over(dt, false);
  release_spacers();  // none are left, unless a step was cut short
  for (auto& s : systems_)
    if (s->stepped && s->error.empty() && s->settings.contacts.enabled && s->settings.contacts.spacers)
      add_spacers(*s);
}

void XpbdWorld::run_systems(btScalar dt) {
  pre_solved_ = true;
  stats_ = {};
  shadows_.clear();
  residuals_.clear();
  drop_departed_bodies();
  // A step length the solver cannot use (stepSimulation(dt, 0) passes any
  // dt on): no system steps, and the next good step goes on from here.
  if (!(dt > 0) || !std::isfinite(dt)) {
    stats_.bad_dt = 1;
    for (auto& s : systems_) s->stepped = false;
    return;
  }
  // The broadphase boxes are from the last collision detection, before the
  // bodies were integrated: bring them to the bodies' current poses.
  const bool collides = std::any_of(systems_.begin(), systems_.end(), [](const auto& s) {
    return s->error.empty() && s->settings.contacts.enabled && s->model->num_particles() > 0;
  });
  if (collides) world_.updateAabbs();
  // Dynamic bodies attached to a system that steps now, with no prediction
  // of Bullet's contacts on them from the last step: their first coupled
  // step (or the first after a pause), probed (world_probe.cpp).
  std::vector<detail::ProbeLoad> probes;  // allocates only when there is one
  for (const Attachment& a : attachments_) {
    btRigidBody* rb = a.body;
    if (rb->isStaticOrKinematicObject() ||
        std::any_of(predicted_.begin(), predicted_.end(), [&](const Predicted& p) { return p.body == rb; }) ||
        !in_world(world_, rb) || !finite_body(rb))
      continue;
    const auto s = std::find_if(systems_.begin(), systems_.end(), [&](auto& t) { return t->id == a.system; });
    if (s == systems_.end() || !(*s)->error.empty() || ((*s)->asleep && !must_wake(**s, dt))) continue;
    const bool skip_static = (*s)->settings.coupled_static_contacts && rb->hasContactResponse();
    auto p = std::find_if(probes.begin(), probes.end(), [&](const detail::ProbeLoad& q) { return q.body == rb; });
    if (p == probes.end())
      probes.push_back(detail::ProbeLoad{rb, skip_static});
    else
      p->skip_static = p->skip_static || skip_static;
  }
  if (!probes.empty()) detail::probe_loads(world_, probes, dt);
  for (const detail::ProbeLoad& p : probes)
    predicted_.push_back(Predicted{p.body, BodyIdentity::of(p.body), to_vec(p.accel), to_vec(p.ang_accel)});
  for (auto& s : systems_) {
    s->stepped = false;
    if (!s->error.empty()) continue;
    if (s->asleep) {
      if (!must_wake(*s, dt)) {
        ++stats_.sleeping;
        continue;
      }
      s->asleep = false;
      s->quiet = 0;
    }
    try {
      step_system(*s, dt);
      s->stepped = true;
      update_sleep(*s, dt);
    } catch (const std::exception& e) {
      // Nothing may leave stepSimulation: the system stops here, with its reason.
      s->error = std::string("step at t = ") + xpbd::format_value(double(s->state.time)) + " s: " + e.what();
      s->report.clear();
      ++stats_.failed;
      if (s->settings.check_health && !all_finite(s->state)) {
        s->health.status = xpbd::Health::nonfinite;
        ++stats_.nonfinite;
      }
    }
  }
}

void XpbdWorld::hand_over(btScalar dt, bool late) {
  // Timed only if a system asks for it (SystemTimes, "coupling").
  const bool timing = !shadows_.empty() && std::any_of(systems_.begin(), systems_.end(), [](const auto& s) {
                        return s->settings.times != nullptr;
                      });
  const auto t0 = timing ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
  for (const Shadow& sh : shadows_) {
    btRigidBody* rb = sh.dynamic;
    if (!rb || !sh.coupled) continue;
    ++stats_.coupled;
    rb->activate(true);
    // The shadow's end state: the contact-free motion plus every system's change.
    const btVector3 x_end = to_bt(Vec3(sh.free.x + sh.dx));
    const btQuaternion q_end = to_bt(Quat(sh.dq * sh.free.q)).normalized();
    const btVector3 v_end = to_bt(Vec3(sh.free.v + sh.dv));
    const btVector3 w_end = to_bt(Vec3(sh.free.w + sh.dw));
    if (late) {
      // After Bullet's integration (StepStats::late): the old lagged coupling.
      rb->setCenterOfMassTransform(btTransform(q_end, x_end));
      rb->setLinearVelocity(v_end);
      rb->setAngularVelocity(w_end);
      continue;
    }
    // Bullet's step will keep `keep` of the velocity (damping), then add
    // `kick` (its forces over dt) and its own contact and joint impulses,
    // predicted to be contact_accel dt. Set u such that
    // keep u + kick + contact_accel dt = the end velocity; the axes Bullet's
    // linear and angular factors lock are left alone. A damping of 1 keeps
    // nothing: there the velocity cannot be handed over, only the pose.
    const btScalar keep_v = btPow(btScalar(1) - rb->getLinearDamping(), dt);
    const btScalar keep_w = btPow(btScalar(1) - rb->getAngularDamping(), dt);
    const btVector3 kick_v = rb->getTotalForce() * rb->getInvMass() * dt;
    const btVector3 kick_w = rb->getTotalTorque() * rb->getInvInertiaTensorWorld() * dt;
    const btVector3 v0 = rb->getLinearVelocity(), w0 = rb->getAngularVelocity();
    const btVector3 v_pre = v_end - to_bt(sh.contact_accel) * dt;
    const btVector3 w_pre = w_end - to_bt(sh.contact_ang_accel) * dt;
    btVector3 u = keep_v > 0 ? (v_pre - kick_v) / keep_v : v0;
    btVector3 uw = keep_w > 0 ? (w_pre - kick_w) / keep_w : w0;
    u = v0 + rb->getLinearFactor() * (u - v0);
    uw = w0 + rb->getAngularFactor() * (uw - w0);
    rb->setLinearVelocity(u);
    rb->setAngularVelocity(uw);
    // The XPBD path's excess over Bullet's integration of the end velocity
    // (btTransformUtil::integrateTransform, as predictIntegratedTransform).
    btTransform reach;
    btTransformUtil::integrateTransform(sh.start, v_end, w_end, dt, reach);
    Residual r;
    r.body = rb;
    r.dx = x_end - reach.getOrigin();
    r.dq = q_end * reach.getRotation().inverse();
    r.v_end = v_end;
    r.w_end = w_end;
    r.v_pre = keep_v * u + kick_v;
    r.w_pre = keep_w * uw + kick_w;
    r.spread = dt * btScalar(sh.substeps - 1) / btScalar(2 * sh.substeps);
    r.world_contacts = sh.world_contacts;
    // XPBD's substeps integrated the body's gyroscopic term
    // (xpbd::rigid::predict_bodies); Bullet's own (on by default since 2.83)
    // would add it a second time, and its change, taken for a contact's,
    // would come back a step late as part of contact_ang_accel: a bar landing
    // on a cloth at 270 substeps rose at 2.16 m/s with it and 0.53 m/s
    // without it (docs/squeeze-surface-edges.md). Off for this step;
    // updateAction puts the flags back.
    r.flags = rb->getFlags();
    rb->setFlags(r.flags & ~(BT_ENABLE_GYROSCOPIC_FORCE_EXPLICIT | BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_WORLD |
                             BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY));
    residuals_.push_back(r);
  }
  if (timing) {
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count();
    for (auto& s : systems_)
      if (s->settings.times && !s->shadow_of_body.empty()) s->settings.times->ns[SystemTimes::coupling] += ns;
  }
}

void XpbdWorld::updateAction(btCollisionWorld* cw, btScalar dt) {
  if (!pre_solved_) {
    // The pre-tick hook did not run in this step: the application installed
    // its own callback after ours. Chain it and put ours back; this one step
    // runs here, after Bullet's integration, with the old one-step lag.
    install_hook();
    run_systems(dt);
    hand_over(dt, true);
    stats_.late = 1;
  }
  // After Bullet's integration: the residual of every coupled body (see
  // XpbdWorld::Residual), and what Bullet's contacts did, for the next step.
  predicted_.clear();
  for (const Residual& r : residuals_) {
    btRigidBody* rb = r.body;
    rb->setFlags(r.flags);
    const btVector3 dv_b = rb->getLinearVelocity() - r.v_end;
    const btVector3 dw_b = rb->getAngularVelocity() - r.w_end;
    btVector3 dx = rb->getLinearFactor() * (r.dx - r.spread * dv_b);
    btQuaternion dq = scaled_rotation(r.dq, rb->getAngularFactor());
    const btVector3 turn = -r.spread * dw_b;  // rotation vector, rad
    if (!turn.isZero()) dq = btQuaternion(turn.normalized(), turn.length()) * dq;
    // As a rotation vector for the contact projection (clip_to_contacts);
    // dq is rebuilt only where the projection changed something.
    const btQuaternion dq_pos = dq.getW() < 0 ? -dq : dq;
    const btScalar angle = dq_pos.getAngle();
    btVector3 dtheta = angle > btScalar(1e-12) ? dq_pos.getAxis() * angle : btVector3(0, 0, 0);
    if (clip_to_contacts(dx, dtheta, rb, cw))
      dq = dtheta.isZero() ? btQuaternion::getIdentity() : btQuaternion(dtheta.normalized(), dtheta.length());
    if (!dx.isZero() || dq != btQuaternion::getIdentity()) {
      btTransform t = rb->getCenterOfMassTransform();
      t.setOrigin(t.getOrigin() + dx);
      t.setRotation((dq * t.getRotation()).normalized());
      rb->setCenterOfMassTransform(t);
    }
    btVector3 dv = rb->getLinearVelocity() - r.v_pre;
    btVector3 dw = rb->getAngularVelocity() - r.w_pre;
    if (r.world_contacts) remove_static_contact_impulses(rb, cw, dv, dw);
    predicted_.push_back(Predicted{rb, BodyIdentity::of(rb), to_vec(dv / dt), to_vec(dw / dt)});
  }
  residuals_.clear();
  release_spacers();
  for (auto& s : systems_)
    if (s->stepped && s->error.empty() && s->settings.contacts.enabled && s->settings.contacts.settle) settle(*s);
  for (auto& s : systems_)
    if (s->stepped && s->error.empty() && s->settings.check_health) health_after_step(*s);
  pre_solved_ = false;
  run_callbacks(dt);
}

}  // namespace xpbd_bullet

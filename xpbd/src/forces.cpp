// Forces from the XPBD multipliers (forces.hpp).
#include "xpbd/forces.hpp"

#include <cmath>
#include <string>
#include <type_traits>

#include "xpbd/constraint_types.hpp"
#include "xpbd/error.hpp"
#include "xpbd/profile.hpp"

namespace xpbd {

namespace {

// 1/h^2 of the last substep; checks that the state was stepped and matches.
Real inv_h2_of(const Model& m, const State& s, const char* fn) {
  const std::string f = std::string(fn) + ": ";
  if (!(s.last_substep > Real(0)) || !std::isfinite(s.last_substep))
    throw ConfigError(f + "state.last_substep is " + format_value(double(s.last_substep)) +
                      "; the state has not been stepped (no multipliers yet)");
  if (s.x.size() != m.inv_mass.size())
    throw ConfigError(f + "state has " + std::to_string(s.x.size()) + " particles, the model " +
                      std::to_string(m.inv_mass.size()));
  for_each_constraint_type([&]<class T>(std::type_identity<T>) {
    if (s.lambdas<T>().size() != m.get<T>().size())
      throw ConfigError(f + "state.lambda of " + stage_name(stage::of<T>) + " has " +
                        std::to_string(s.lambdas<T>().size()) + " entries, the model " +
                        std::to_string(m.get<T>().size()) + " elements");
  });
  if (s.pin_target_now.size() != m.get<Pin>().size())
    throw ConfigError(f + "state.pin_target_now does not match the model's pins");
  if (s.attachment_impulse.size() != s.attachments.size())
    throw ConfigError(f + "state.attachment_impulse has " + std::to_string(s.attachment_impulse.size()) +
                      " entries, state.attachments " + std::to_string(s.attachments.size()) +
                      " (attachments changed since the last step?)");
  for (std::size_t k = 0; k < s.attachments.size(); ++k)
    if (s.attachments[k].particle < 0 || static_cast<std::size_t>(s.attachments[k].particle) >= s.x.size())
      throw ConfigError(f + "state.attachments[" + std::to_string(k) + "].particle " +
                        std::to_string(s.attachments[k].particle) + " is not a particle");
  return Real(1) / (s.last_substep * s.last_substep);
}

EvalContext eval_context(const Model& m, const State& s) {
  EvalContext c;
  c.x = s.x.data();
  c.pin_target = s.pin_target_now.data();
  c.planes = m.planes.data();
  c.penetration_side = s.penetration_side.data();
  return c;
}

// The mass times gravity plus the external force on a movable particle (N).
Vec3 applied_force(const Model& m, const State& s, Index i, const Vec3& gravity) {
  const Vec3 f = s.f_ext.empty() ? Vec3::Zero() : s.f_ext[static_cast<std::size_t>(i)];
  return gravity / m.inv_mass[static_cast<std::size_t>(i)] + f;
}

}  // namespace

std::vector<Vec3> constraint_forces_on_particles(const Model& m, const State& s) {
  const Real inv_h2 = inv_h2_of(m, s, "constraint_forces_on_particles");
  std::vector<Vec3> f(m.inv_mass.size(), Vec3::Zero());
  const EvalContext ctx = eval_context(m, s);
  for_each_constraint_type([&]<class T>(std::type_identity<T>) {
    if constexpr (is_generic_constraint_v<T> && !std::is_same_v<T, Pin>) {
      if constexpr (std::is_same_v<T, Penetration>)
        if (s.penetration_side.size() != m.get<T>().size()) return;  // never stepped with them
      const auto& cs = m.get<T>();
      const auto& lam = s.lambdas<T>();
      for (std::size_t k = 0; k < cs.size(); ++k) {
        if (lam[k] == Real(0)) continue;
        Real C;
        Vec3 g[T::kArity];
        if (!T::eval(cs[k], static_cast<Index>(k), ctx, C, g)) continue;
        const Real l = lam[k] * inv_h2;  // F_i = (lambda/h^2) grad_i C
        for (int i = 0; i < T::kArity; ++i) f[static_cast<std::size_t>(cs[k].p[i])] += l * g[i];
      }
    }
  });
  return f;
}

std::vector<AttachmentForce> attachment_forces(const Model& m, const State& s) {
  const Real inv_h2 = inv_h2_of(m, s, "attachment_forces");
  std::vector<AttachmentForce> out;
  out.reserve(s.attachments.size());
  for (std::size_t k = 0; k < s.attachments.size(); ++k) {
    AttachmentForce r;
    r.attachment = static_cast<Index>(k);
    r.particle = s.attachments[k].particle;
    r.body = s.attachments[k].body;
    r.on_body = -inv_h2 * s.attachment_impulse[k];  // the particle got +impulse
    out.push_back(r);
  }
  return out;
}

std::vector<PinReaction> pin_reactions(const Model& m, const State& s, const Vec3& gravity) {
  const Real inv_h2 = inv_h2_of(m, s, "pin_reactions");
  const std::size_t n = m.inv_mass.size();
  const std::vector<Vec3> net = constraint_forces_on_particles(m, s);
  // Attachments add to the forces on their particles.
  std::vector<Vec3> att(n, Vec3::Zero());
  for (std::size_t k = 0; k < s.attachments.size(); ++k)
    att[static_cast<std::size_t>(s.attachments[k].particle)] += inv_h2 * s.attachment_impulse[k];
  const auto& pins = m.get<Pin>();
  std::vector<Index> pin_of(n, -1);
  for (std::size_t k = 0; k < pins.size(); ++k) pin_of[static_cast<std::size_t>(pins[k].p[0])] = static_cast<Index>(k);
  const EvalContext ctx = eval_context(m, s);
  std::vector<PinReaction> out;
  for (std::size_t i = 0; i < n; ++i) {
    const Index k = pin_of[i];
    const bool kinematic = !(m.inv_mass[i] > Real(0));
    if (k < 0 && !kinematic) continue;
    PinReaction r;
    r.particle = static_cast<Index>(i);
    r.pin = k;
    if (kinematic) {
      // What the support passes on: minus what the elements do to it.
      r.force = -(net[i] + att[i]);
    } else {
      const Pin& p = pins[static_cast<std::size_t>(k)];
      if (p.mat.compliance > Real(0)) {
        Real C;
        Vec3 g[1];
        if (Pin::eval(p, k, ctx, C, g)) r.force = (s.lambdas<Pin>()[static_cast<std::size_t>(k)] * inv_h2) * g[0];
      } else {
        r.force = -applied_force(m, s, r.particle, gravity) - net[i] - att[i];
        r.from_balance = true;
      }
    }
    out.push_back(r);
  }
  return out;
}

std::vector<MaxConstraintForce> max_constraint_forces(const Model& m, const State& s) {
  const Real inv_h2 = inv_h2_of(m, s, "max_constraint_forces");
  std::vector<MaxConstraintForce> out;
  for_each_constraint_type([&]<class T>(std::type_identity<T>) {
    MaxConstraintForce r;
    r.type = stage_name(stage::of<T>);
    // J per unit of C: C in m -> N; rad -> N*m/rad; dimensionless -> J; m^3 -> Pa.
    if constexpr (std::is_same_v<T, DihedralBending>)
      r.unit = "N*m/rad";
    else if constexpr (std::is_same_v<T, IsometricBending>)
      r.unit = "J";
    else if constexpr (std::is_same_v<T, TetVolume> || std::is_same_v<T, GlobalVolume>)
      r.unit = "Pa";
    else
      r.unit = "N";
    const auto& lam = s.lambdas<T>();
    r.count = static_cast<Index>(lam.size());
    for (std::size_t k = 0; k < lam.size(); ++k) {
      const Real f = std::abs(lam[k]) * inv_h2;
      if (r.element < 0 || f > r.force) {
        r.force = f;
        r.element = static_cast<Index>(k);
      }
    }
    out.push_back(r);
  });
  return out;
}

}  // namespace xpbd

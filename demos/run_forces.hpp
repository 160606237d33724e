#pragma once
// The forces of a run's final frame, for metrics.json's "forces" object
// (docs/metrics.md): pin reactions, attachment forces and the largest
// constraint force per type, read from the XPBD multipliers of the last
// substep (xpbd/forces.hpp). XPBD runs only (--solver xpbd): PBD's
// multipliers are not forces and btSoftBody has none.
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "xpbd/forces.hpp"
#include "xpbd/model.hpp"
#include "xpbd/state.hpp"

namespace xpbd_demos {

struct SceneSpec;

// One scene attachment (SceneSpec::attachments) and its force.
struct RunAttachmentForce {
  int attachment = 0;          // index into SceneSpec::attachments
  xpbd::Index particle = 0;
  int body = 0;                // index into SceneSpec::bodies
  std::string body_name;       // RigidSpec::name (may be empty)
  xpbd::Vec3 on_body = xpbd::Vec3::Zero();  // N, world; the particle gets -on_body
};

struct RunForces {
  double substep = 0;  // s, h of the last substep (lambda/h^2)
  std::vector<xpbd::PinReaction> pins;
  std::vector<RunAttachmentForce> attachments;
  std::vector<xpbd::MaxConstraintForce> max_by_type;
};

// Reads the forces of an XPBD state. `state.attachments` must be the scene's
// attachments in order (the runner's XpbdWorld keeps them so while every
// body is in the world); otherwise the attachments are left out and a note
// says why. Throws xpbd::ConfigError for a state that was never stepped.
RunForces read_forces(const SceneSpec& spec, const xpbd::Model& model, const xpbd::State& state,
                      const xpbd::Vec3& gravity, std::vector<std::string>& notes);

// More than this many pins (or attachments): metrics.json lists the total and
// the kForcesListed largest, not every one.
inline constexpr std::size_t kForcesListedMax = 1000;
inline constexpr std::size_t kForcesListed = 10;

// metrics.json's "forces" object.
nlohmann::json forces_json(const RunForces& f);

}  // namespace xpbd_demos

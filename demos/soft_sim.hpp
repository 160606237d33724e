#pragma once
// The particle system of a scene run (run_scene, scene_runner.hpp) by one of
// the solvers: XPBD or PBD through the bridge (xpbd_bullet::XpbdWorld), or
// btSoftBody. Internal to the demo library.
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "demos/rigid_world.hpp"
#include "demos/run_forces.hpp"
#include "demos/scene_runner.hpp"
#include "xpbd/model.hpp"
#include "xpbd/scene.hpp"
#include "xpbd_bullet/world.hpp"

namespace xpbd_demos {

// One solver's run of the scene's particles, frame by frame.
class SoftSim {
 public:
  virtual ~SoftSim() = default;
  // Advances one frame; returns false if a state turned non-finite (the
  // frame may then have stopped early).
  virtual bool step_frame() = 0;
  virtual std::span<const xpbd::Vec3> x() = 0;
  virtual std::span<const xpbd::Vec3> v() = 0;
  virtual long long projections_per_frame() const = 0;
  // The stage breakdown so far (RunOptions::stage_times), or nullptr.
  virtual const xpbd_bullet::SystemTimes* times() const { return nullptr; }
  // The forces of the current state (XPBD only), or nothing.
  virtual std::optional<RunForces> forces(const SceneSpec&, std::vector<std::string>&) const { return {}; }
  // With a tolerance: the substeps the last frame took, and whether it met it.
  virtual std::optional<int> frame_substeps() const { return std::nullopt; }
  virtual bool frame_tolerance_met() const { return true; }
};

// The scene's particles run by XPBD or PBD (opt.solver) in the bridge.
std::unique_ptr<SoftSim> make_bridge_sim(const SceneSpec& spec, std::shared_ptr<const xpbd::Model> model,
                                         RigidWorld& rw, const RunOptions& opt);
// The scene's particles as one btSoftBody in rw's soft world; writes the
// solver's settings to `settings` and what it does not use to `notes`.
std::unique_ptr<SoftSim> make_softbody_sim(const SceneSpec& spec, const xpbd::SceneDesc& scene,
                                           const xpbd::Model& model, RigidWorld& rw, const RunOptions& opt,
                                           nlohmann::json& settings, std::vector<std::string>& notes);

// Shared with scene_runner.cpp:
// v with 9 significant digits, for messages;
std::string num(double v);
// every component of every vector finite;
bool all_finite(std::span<const xpbd::Vec3> a);
// the radius shared by all movable particles, or nullopt if they differ.
std::optional<xpbd::Real> uniform_radius(const xpbd::SceneDesc& s);

}  // namespace xpbd_demos

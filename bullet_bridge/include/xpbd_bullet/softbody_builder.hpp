#pragma once
// Builds one xpbd::SceneDesc as a Bullet btSoftBody under the fairness rules
// of docs/design.md section 5. Shared by the btSoftBody baseline
// (softbody_baseline.hpp, a soft body alone in its own world) and the demo
// scene runner (demos/scene_runner.hpp, a soft body among rigid bodies).
//
// What the builder sets (and why):
//   - nodes: one per particle, at its position, with setMass per node (mass
//     0 = kinematic node); setTotalMass is never called, so pins are never
//     rescaled. Initial velocities are the scene's (0 for pinned nodes, which
//     xpbd holds on their pin target);
//   - links: one appendLink per Distance element, in the scene's order, all
//     with material 0 (kLST); Bullet generates no bending links;
//   - rest lengths: the scene's (explicit, or the initial distance). Bullet
//     resets every link's rest length to the current node distance on the
//     first step after any setMass/appendLink (predictMotion calls
//     updateConstants while m_bUpdateRtCst is set). The builder runs that
//     update itself and then writes the scene's rest lengths and clears the
//     flag. Do not call setMass/appendLink on the result afterwards;
//     appendAnchor does not set the flag and is safe;
//   - solver: piterations as given, viterations = diterations = 0, kDP as
//     given (0 in the fair comparison), kDG = kLF = kPR = kVC = kMT = 0,
//     kCHR = kKHR = 1, kAHR = 1 (rigid anchors), kDF = friction;
//   - collisions: fCollision::SDF_RS (node against rigid body through the
//     world's btSparseSdf, node-level like xpbd's particle contacts; see
//     docs/metrics.md for why not CL_RS), collision margin set explicitly
//     (Bullet's default is 0.25 m);
//   - sleeping off (DISABLE_DEACTIVATION).
//
// Scene elements a btSoftBody cannot express (softbody_unsupported lists
// them; build_softbody rejects them with xpbd::SceneError):
//   - particle-particle collisions (explicit Collision pairs, self_collision);
//   - planes, penetration constraints, dihedral and isometric bending, tet
//     volumes, tethers, global volumes (btSoftBody's pressure kPR and volume
//     conservation kVC are different physics, not a mapping of them);
//   - pins on particles of non-zero mass (btSoftBody has no compliant pin
//     without a rigid anchor) and pins whose target is not the particle's
//     initial position.
// Distance compliances and PBD stiffnesses are not used: every link gets the
// one kLST, which is calibrated by measured strain (docs/design.md section 5).
// collision_triangles and particle radii are not part of the soft body
// (btSoftBody collides its nodes, with one margin per body).
#include "xpbd_bullet/precision_check.hpp"  // first: the float/double guard

#include <memory>
#include <string>
#include <vector>

#include "xpbd/model.hpp"
#include "xpbd/scene.hpp"
#include "xpbd/types.hpp"

class btSoftBody;
struct btSoftBodyWorldInfo;

namespace xpbd_bullet {

struct SoftBodyBuildConfig {
  int piterations = 10;    // btSoftBody position iterations per internal step (>= 1)
  // Link stiffness kLST in (0, 1], dimensionless; its effect depends on
  // piterations and the step, like PBD's k.
  xpbd::Real kLST = 1;
  // Velocity damping kDP in [0, 1), dimensionless: Bullet scales node
  // velocities by (1 - kDP) once per internal step. 0 in the fair comparison.
  xpbd::Real kDP = 0;
  xpbd::Real margin = xpbd::Real(0.01);  // m, >= 0: collision margin (distance kept from rigid surfaces)
  xpbd::Real friction = 0;               // kDF in [0, 1], dimensionless; multiplied by the body's friction
};

// The elements of `scene` a btSoftBody cannot express, one message per kind,
// naming the SceneDesc field and the count, e.g. "dihedral_bends: scene has
// 12 dihedral bending elements; btSoftBody cannot express them". Empty = the
// scene can be built. Assumes indices are valid (run xpbd::compile first for
// a clear error about those).
std::vector<std::string> softbody_unsupported(const xpbd::SceneDesc& scene);

// Checks cfg; throws xpbd::ConfigError("SoftBodyBuildConfig.<field>: ...").
void validate(const SoftBodyBuildConfig& cfg);

// Builds the soft body (not added to any world). `model` must be
// xpbd::compile(scene) (it gives the rest lengths and initial velocities);
// `info` must outlive the body. Throws xpbd::SceneError with the first
// message of softbody_unsupported, or xpbd::ConfigError for a bad cfg.
std::unique_ptr<btSoftBody> build_softbody(btSoftBodyWorldInfo& info, const xpbd::SceneDesc& scene,
                                           const xpbd::Model& model, const SoftBodyBuildConfig& cfg);

}  // namespace xpbd_bullet

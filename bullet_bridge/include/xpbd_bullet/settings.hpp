#pragma once
// The settings of one particle system in an XpbdWorld (world.hpp):
// ContactSettings, the accuracy target (Tolerance), the opt-in stage
// timing (SystemTimes) and SystemSettings, which holds them. Checked where
// they are set (XpbdWorld::add_system, set_settings); docs/embedding.md
// lists every field with its default.
#include "xpbd_bullet/precision_check.hpp"  // first: the float/double guard

#include <BulletCollision/BroadphaseCollision/btBroadphaseProxy.h>

#include <array>
#include <cstddef>
#include <cstdint>

#include "xpbd/health.hpp"
#include "xpbd/profile.hpp"
#include "xpbd/step.hpp"
#include "xpbd/types.hpp"
#include "xpbd/workers.hpp"

namespace xpbd_bullet {


// Contact settings of one particle system.
struct ContactSettings {
  bool enabled = true;
  xpbd::Real margin = xpbd::Real(0.01);  // m, speculative contact margin (>= 0)
  // Thickness added to every particle's radius (m, >= 0): the distance kept
  // from rigid surfaces.
  xpbd::Real thickness = xpbd::Real(0.005);
  // Friction coefficients of the soft material; combined with the rigid
  // body's getFriction() by product, as Bullet combines two rigid bodies.
  xpbd::Real static_friction = xpbd::Real(0.5);
  xpbd::Real dynamic_friction = xpbd::Real(0.5);
  // Restitution of the soft material, combined with the body's by product.
  xpbd::Real restitution = 0;
  xpbd::Real compliance = 0;  // m/N
  // Rigid features against the model's collision_triangles: box corners
  // (and points along box edges at most this far apart, m, > 0, with
  // edge_contacts off or on a body that moves farther than the thickness
  // in a step), hull vertices, and on static triangle meshes (and
  // heightfields) the corners of their sharp edges (faces more than about a
  // degree from flat) and points along those edges, this far apart, among
  // the triangles near the system. Choose it below the soft mesh's edge
  // length. With edge_contacts on, a box edge gets up to 4 edge contacts
  // per spacing of its length (at least 64).
  xpbd::Real feature_spacing = xpbd::Real(0.01);
  // Continuous collision of fast rigid features against the
  // collision_triangles: a feature that can move farther than the
  // thickness (at least 1 mm) in a step is swept along its path over the
  // step (FCL's vertex-face test) and gets a contact with every triangle
  // whose contact band it would enter, not only the one it starts over;
  // and one found over a triangle less than the thickness from it, on the
  // side away from its shape's centre, is pushed back to the centre's side
  // (docs/feature-contacts.md, "Fast features").
  bool sweep_features = true;
  // The edges of the collision_triangles against the edges of box shapes
  // (xpbd::BodyEdgeContact): a cloth folded tight over a box's edge has no
  // face over points along the edge, and its edge along the fold went
  // through the box (docs/edge-contacts.md). They
  // hold a cloth along a box's whole edge (a triangle's plane is linear
  // along the edge, so one held the thickness away where the box edge
  // crosses its edges and at the box's corners is held between them), so
  // with them on a box's feature points are its corners alone (but for a
  // fast body, see feature_spacing): a 64 x 64
  // cloth on 50 boxes has 291 feature-triangle contacts per step instead of
  // 3,717, and its contact search takes about half the time
  // (bench_triangles).
  // With Coulomb friction (static_friction, dynamic_friction times the
  // body's getFriction(), as the particle contacts).
  bool edge_contacts = true;
  // A system without collision_triangles: its surface_triangles' edges
  // against the edges of box shapes, as edge_contacts does for collision
  // triangles (needs edge_contacts). Particle contacts keep particle centres
  // out of a body, not the edges between them: a cloth pressed over a box's
  // corner cut it with the edge between a particle on each face. The soft
  // edges tested are those whose box over the step meets the box's (the
  // same with and without `cull`); those at a particle attached to that box
  // or next to one are kept out of it with no thickness (the attachment
  // holds such a particle on the box's face: the cloth there lies along the
  // face, and a thickness would lift the box off it). After each edge
  // contact's push, its two particles' own contacts' friction is solved
  // again. It helps: in the bar squeeze of docs/squeeze.md (32 runs,
  // 2026-11-29) the frames with a cloth edge stretched over 20 % fell from
  // 12,312 to 6,174 in double, and such edges through a body from 50,622 to
  // 4,545; a 1000 kg box landing on its edge on a cloth on the ground
  // stretched it by 0.04 and 0.06 (tilted 0.3 and 0.6 rad) with it, 0.07
  // and 0.15 without. On by default since 2026-11-29 (it was off while one
  // run of the 32 left a particle 8.9 mm (double) or 12.3 mm (float) inside
  // a body, docs/squeeze.md, "Not on by default yet"): since the gyroscopic
  // change of that day the campaign with it leaves no particle deeper than
  // the thickness in either build, and a third (double) or a half (float)
  // of the frames with an edge over 20 %, at 1.41-1.48 times the wall time
  // of that 49-body pile (docs/squeeze-surface-edges.md, "Surface edges
  // after the gyroscopic change"). It costs nothing where no box is near a
  // system without collision triangles; a cloth lying over 50 boxes and 50
  // spheres (bench_contacts) takes 1.45-1.54 times the bridge step it
  // takes without it (docs/bench-bridge.md). The scene format keeps its own
  // default off (docs/scene-format.md, soft.contacts.surface_edges).
  bool surface_edge_contacts = true;
  // From this many collision_triangles on (>= 0), the rigid features are
  // matched with the triangles through a bounding volume hierarchy of the
  // triangles' swept boxes (built by FCL once, refitted every step) and a
  // grid per body instead of against every triangle's box. The same
  // contacts in the same order either way: 0 (the default) = always, a
  // number above the model's = never. The hierarchy was faster at every
  // size measured, from 18 triangles (1.2x) to 32,258 (140-158x)
  // (docs/feature-contacts.md).
  int triangle_bvh_from = 0;
  // Bullet collision filter of the particle system.
  int filter_group = btBroadphaseProxy::DefaultFilter;
  int filter_mask = btBroadphaseProxy::AllFilter;
  // Skip the narrowphase for (particle, body) pairs whose boxes are apart.
  // Conservative: the same contacts in the same order as false, which
  // queries every (particle, candidate) pair (the brute-force reference for
  // tests and benchmarks).
  bool cull = true;
  // Keep the contacts complete inside the step (xpbd::StepConfig::
  // contact_margin): the contacts are found once per Bullet step for each
  // particle's straight path, margin wide; a particle that the solve
  // carries off that path (a cloth whipped by its edges into a body it
  // was not near) is queried again, against the bodies around its rest
  // of the step, in the substep it leaves it. Costs a pass over the
  // particles per substep, and the queries of the particles that left.
  bool refresh = true;
  // After Bullet's solve and integration, put back outside each dynamic
  // body the particles its final pose closed over (Bullet's own contacts
  // and joints move a coupled body after XPBD has run: a box struck by
  // another box, a body pushed down by what lands on it). Particles
  // attached rigidly (compliance 0) to a dynamic body are put at their
  // attachment point; each particle with a contact in the step that is
  // closer to the body than the contact's thickness (radius plus
  // `thickness`) is moved along the surface normal to it, then likewise
  // for static and kinematic bodies. A position projection of the
  // particles alone: velocities and bodies are unchanged, but for `wedges`.
  bool settle = true;
  // With settle: a particle that the settle pass cannot put outside every
  // body (squeezed between two that Bullet pushed together, or between a
  // heavy body and the ground at a budget that did not converge the
  // mass ratio) moves the dynamic body out instead, by translation along
  // the surface normal at the particle, at most two contact thicknesses
  // per step: the cloth between them is the rigid spacer that XPBD
  // solved. A position correction only, as Bullet's split impulse makes
  // (velocities are unchanged). false: such a particle stays inside the
  // body (docs/bullet-bridge.md).
  bool wedges = true;
  // Make the cloth between two bodies visible to Bullet's solver: for each
  // particle with contacts with two bodies on opposite sides of it in the
  // step (one of them dynamic), a contact point between the two bodies is
  // added to Bullet for that step, at the gap minus both contact
  // thicknesses, so that Bullet's own contacts and joints cannot push the
  // bodies together through the cloth (docs/bullet-bridge.md section 3).
  bool spacers = true;
};

// Opt-in wall-clock breakdown of one system's steps (SystemSettings::times,
// docs/stages.md): the stages inside xpbd::step() and the bridge's own, in
// ns (std::chrono::steady_clock) and runs, summed over internal steps. As in
// xpbd::StageTimes, a stage without work is neither timed nor counted.
struct SystemTimes {
  xpbd::StageTimes step;  // inside xpbd::step() (xpbd/profile.hpp)
  // The bridge's stages:
  //   contacts  broadphase, culling, narrowphase, triangle contacts, and the
  //             shadow bodies of the bodies touched (when contacts are enabled);
  //   shadows   the attachments' shadow bodies and the bodies' contact-free
  //             reference motion (when the system has bodies);
  //   coupling  shadow changes -> the dynamic bodies' velocities before
  //             Bullet's solver and the residual poses after its integration
  //             (when there are bodies; the per-body hand-over is shared by
  //             all systems, and its time is added to every timed system
  //             with bodies).
  enum Stage : std::size_t { contacts, shadows, coupling, count };
  std::array<std::int64_t, count> ns{};     // ns
  std::array<std::int64_t, count> calls{};  // runs with work
  static const char* name(std::size_t k) {
    constexpr std::array<const char*, count> names = {"bridge_contacts", "bridge_shadows",
                                                      "bridge_coupling"};
    return k < count ? names[k] : "?";
  }
};

// An accuracy target instead of a budget (SystemSettings::tolerance): the
// system picks its substeps step by step so that its largest Distance strain
// |len/rest - 1| after the step stays within `strain`, and its deepest
// contact violation within `penetration`, at the least count it finds,
// within [1, max_substeps] with the strain target and within [substeps,
// max(substeps, max_substeps)] with the contact target alone (depth says
// nothing about the rest of the solve, so it only raises the count).
// Either or both may be set. The contact target is on by default, at 5 mm
// (the default contact thickness): a step that leaves a particle deeper
// than that inside its contact band (a light cloth under a heavy body) is
// solved again with more substeps, and a step that does not costs one copy
// of the state and one pass over its contacts (docs/tolerance.md,
// "The default contact target"). Set penetration = 0 for a fixed budget.
// Rule
// (docs/tolerance.md), with e the larger of strain / tolerance.strain and
// penetration / tolerance.penetration (the targets that are set):
//   - after the step's solve (before Bullet's), e is measured: the strain
//     with one pass over the Distance elements, the penetration with one
//     pass over the step's contacts (how far a particle, or a rigid feature
//     into a cloth triangle, is inside the contact band of its thickness:
//     xpbd::rigid::deepest_contact_violation; a particle pressed between
//     two bodies is where it stays inside). Above 1 with substeps to spare,
//     the step is solved again from its start (the state copied before the
//     solve) with n' = max(n + 1, ceil(n sqrt(e / 0.7))): one sweep per
//     substep leaves an error that falls about as 1/n^2 (the h^2 term),
//     aimed at 70 % of the tolerance. n' is capped at max_substeps and at 3
//     times the last step's count (a sudden rise turns the constraint error
//     the step starts with into velocity at the shorter substep);
//   - at the cap above the tolerance, the step is kept and reported
//     (SystemHealth::tolerance_met = false, StepStats::tolerance_missed);
//     so is a step whose rise did not pay (its error at n' still above 1 and
//     not below e_n (n / n')^0.05): solved at n again, and for the next 15 steps an
//     error up to 1.5 times that one is not solved again (what does not
//     fall with substeps is not an error they remove; docs/tolerance.md);
//   - downwards, only after 15 steps in a row (0.25 s at 60 Hz) at one count
//     whose largest e says fewer would reach 70 % of the tolerance (taking
//     e as 1/n, a cautious guess): then by at most a fifth (at least one),
//     never below that guess. So the count rises at once and falls slowly,
//     without going back and forth.
// The strain from the compliance itself (a link at compliance alpha carrying
// a force F stretches by alpha F) does not fall with substeps, nor does a
// contact's overlap at its compliance: with StrainMeasure::total, a strain
// tolerance below it is reported as missed at max_substeps. With
// StrainMeasure::residual the strain target measures only the stretch that
// the compliance and damping do not explain (the solve's error), so a soft
// material may stretch as far as its compliance says.
// A caution, measured on a chaotic scene (a cloth hanging from a bar in a
// pile of 49 falling bodies, 32 runs; docs/squeeze-budget.md): from the
// default 10 substeps the strain target blew one run up at 20 % and one at
// 50 %, where the fixed budget blew none; started from 30 substeps
// (`substeps` = 30) the 20 % target blew none up and left the fewest
// stretched frames of any setting measured. Watch SystemHealth::status.
enum class StrainMeasure {
  total,     // the largest |len/rest - 1| (xpbd::max_distance_strain)
  residual,  // the largest |C + at lambda + damping| / rest of the last substep
             // (xpbd::max_distance_residual; Method::xpbd only). At compliance 0
             // the same as total.
};

struct Tolerance {
  double strain = 0;       // 1, > 0 turns the strain target on; 0 = off
  StrainMeasure measure = StrainMeasure::total;  // what the strain target measures
  double penetration = 0.005;  // m, > 0 turns the contact target on (the default); 0 = off
  int max_substeps = 200;  // >= 1: the most substeps the system may take in one step
  // With neither target on (strain = penetration = 0),
  // SystemSettings::substeps is fixed.
  bool on() const { return strain > 0 || penetration > 0; }
};

struct SystemSettings {
  // XPBD substeps per Bullet internal step (>= 1); with a tolerance, the
  // count the first step starts from.
  int substeps = 10;
  int iterations = 1;   // Gauss-Seidel sweeps per substep (>= 1)
  xpbd::Method method = xpbd::Method::xpbd;
  xpbd::Real drag = 0;  // 1/s
  bool alternate_sweeps = false;  // xpbd::StepConfig::alternate_sweeps
  bool coloured = false;          // xpbd::StepConfig::coloured
  // Direct solve along chains, attached bodies included (XPBD only):
  // xpbd::StepConfig::direct_chains.
  bool direct_chains = false;
  int chain_passes = 16;                     // xpbd::StepConfig::chain_passes
  xpbd::Real chain_tolerance = xpbd::Real(1e-3);  // xpbd::StepConfig::chain_tolerance
  // Hierarchical PBD's coarse levels before every substep's sweeps
  // (xpbd::StepConfig::hierarchy, hierarchy_slack >= 0).
  bool hierarchy = false;
  xpbd::Real hierarchy_slack = xpbd::Real(0.01);
  // Threads for the coloured sweep (xpbd::StepConfig::workers; needs
  // coloured) and for the contact search, one broadphase candidate body at
  // a time (the contacts are joined in candidate order: the same, bit for
  // bit, on any number of threads): a pool the application owns and keeps
  // alive while the system steps; one pool can serve every system (they
  // step in turn).
  xpbd::Workers* workers = nullptr;
  // Extra sweeps where contacts need them (xpbd::StepConfig::contact_sweeps,
  // >= 0; 0 = off): e.g. 8 for a heavy body landing on cloth that supports
  // it through its own edges (docs/design.md, "Heavy on light").
  int contact_sweeps = 0;
  xpbd::Real contact_tolerance = xpbd::Real(0.1);  // xpbd::StepConfig::contact_tolerance (>= 0)
  // The coupled dynamic bodies' contacts with static bodies (the ground),
  // taken from Bullet's contact manifolds of the last collision detection,
  // are solved inside the XPBD substeps too (xpbd::BodyWorldContact), so a
  // cloth pressing a box onto the ground does not push it into it.
  bool coupled_static_contacts = true;
  // Sleeping (off by default: sleep_speed = 0). A system falls asleep once
  // every particle has moved slower than sleep_speed (m/s, >= 0) for
  // sleep_time (s, > 0) without a break, while no dynamic body it touches
  // is awake in Bullet and no awake non-static body is near it. Asleep, it
  // is not stepped (its velocities are zero and its state does not change)
  // and it does not keep the bodies it touches awake. It wakes when an awake
  // non-static body's box, grown by what it can travel in one step, reaches
  // the system's box (its particles' box grown by the contact margin and
  // thickness), when one of its pins is moved (State::pin_target), when its
  // settings or materials are changed, and on XpbdWorld::wake. Moving its
  // particles yourself does not wake it: call wake.
  xpbd::Real sleep_speed = 0;
  xpbd::Real sleep_time = 1;
  ContactSettings contacts;
  // Divergence checks after every step (XpbdWorld::health, StepStats): the
  // system's status by xpbd::classify with these thresholds (validated like
  // the rest; max_strain defaults to 1, an edge twice its rest length). One
  // pass over the particles at the start and at the end of the step, and one
  // over the Distance elements at the end. false: no checks (health(id)
  // stays as it was).
  bool check_health = true;
  xpbd::HealthThresholds health;
  Tolerance tolerance;
  // Opt-in timing: when set, every step of the system adds its stage times
  // to *times (which must outlive the system or be reset to nullptr).
  // nullptr = no timing.
  SystemTimes* times = nullptr;
};

}  // namespace xpbd_bullet

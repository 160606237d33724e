#pragma once
// SceneSpec: a complete headless demo scene -- one XPBD particle system, the
// rigid bodies around it, the attachments between them and the solver
// settings -- as plain data. Built-in scenes (builtin_scenes.hpp) are
// SceneSpecs written in C++; scene files (scene_file.hpp, the JSON format of
// docs/scene-format.md) are parsed into one; the runner (scene_runner.hpp)
// builds a Bullet world from one and runs it with XPBD, PBD or btSoftBody.
//
// A scene models only what it declares: a scene without rigid bodies gets no
// Bullet contacts, one without `particle_collision` no spatial hash, one
// without collision triangles no triangle collision.
//
// Particle numbering: the explicit particles of `soft.particles` come first
// (0 .. n-1), then every generator in `soft.generators` appends its particles
// in order (a cloth of 10 x 10 after 5 explicit particles starts at index 5).
// Explicit constraints, pins and attachments use these global indices.
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "xpbd/builders.hpp"
#include "xpbd/scene.hpp"
#include "xpbd/step.hpp"
#include "xpbd/types.hpp"

namespace xpbd_demos {

// ---------------------------------------------------------------------------
// Solver settings (command-line options override them).
enum class Solver { xpbd, pbd, bullet };
// What solver.tolerance measures (SolverSpec::tolerance_measure).
enum class ToleranceMeasure { strain, residual };

struct SolverSpec {
  Solver method = Solver::xpbd;
  xpbd::Real dt = xpbd::Real(1) / xpbd::Real(60);  // s, frame = one Bullet internal step (> 0)
  int substeps = 10;    // XPBD/PBD substeps per frame (>= 1)
  int iterations = 1;   // Gauss-Seidel sweeps per substep (>= 1)
  int frames = 180;     // frames to run (>= 1)
  xpbd::Real drag = 0;  // 1/s, velocity damping rate (>= 0)
  // Symmetric Gauss-Seidel (xpbd::StepConfig::alternate_sweeps).
  bool alternate_sweeps = false;
  // Coloured sweep of the Distance elements (xpbd::StepConfig::coloured).
  bool coloured = false;
  // Direct solve along chains (xpbd::StepConfig::direct_chains; XPBD only).
  bool direct_chains = false;
  int chain_passes = 16;                       // xpbd::StepConfig::chain_passes (>= 1)
  xpbd::Real chain_tolerance = xpbd::Real(1e-3);  // xpbd::StepConfig::chain_tolerance (>= 0)
  // Hierarchical PBD (xpbd::StepConfig::hierarchy; XPBD and PBD).
  bool hierarchy = false;
  xpbd::Real hierarchy_slack = xpbd::Real(0.01);  // xpbd::StepConfig::hierarchy_slack (>= 0)
  xpbd::Vec3 gravity{xpbd::Real(0), xpbd::Real(-9.81), xpbd::Real(0)};  // m/s^2, world gravity
  // btSoftBody (--solver bullet) at the matched budget: `substeps` internal
  // steps of dt/substeps per frame, each with `iterations` position
  // iterations (piterations), so both count substeps x iterations x elements
  // projections per frame (docs/design.md section 5). kLST is btSoftBody's link
  // stiffness in (0, 1] (dimensionless).
  xpbd::Real bullet_kLST = 1;
  // The run's status (xpbd/health.hpp, metrics.json "status"): over_stretched
  // once some Distance element's strain |len/rest - 1| exceeds this (> 0;
  // 1 = an edge twice its rest length).
  double max_strain = 1;
  // An accuracy target instead of a budget (xpbd_bullet::Tolerance; XPBD and
  // PBD runs): > 0, the run picks its substeps frame by frame so that the
  // largest Distance strain stays within it, starting from `substeps`, at
  // most max_substeps. 0 = off (`substeps` fixed).
  double tolerance = 0;
  // What `tolerance` measures (xpbd_bullet::StrainMeasure): the strain, or
  // (XPBD only) the residual of the Distance elements' XPBD equation over
  // the rest length, the stretch their compliance and damping do not explain
  // (docs/tolerance.md).
  ToleranceMeasure tolerance_measure = ToleranceMeasure::strain;
  // m, the same for the deepest contact violation (how far a particle is
  // inside the contact band of its thickness; xpbd_bullet::Tolerance::
  // penetration). 0 = off; with both set, the run meets both.
  double penetration_tolerance = 0;
  int max_substeps = 200;  // >= 1
};

// ---------------------------------------------------------------------------
// The particle system.

// Contacts of the particles with rigid bodies (xpbd_bullet::ContactSettings).
struct SoftContactSpec {
  xpbd::Real thickness = xpbd::Real(0.005);      // m, >= 0: kept from rigid surfaces
  xpbd::Real margin = xpbd::Real(0.01);          // m, >= 0: speculative contact margin
  xpbd::Real static_friction = xpbd::Real(0.5);  // >= 0, combined by product with the body's
  xpbd::Real dynamic_friction = xpbd::Real(0.5); // >= 0, <= static_friction
  xpbd::Real restitution = 0;                    // in [0, 1], combined by product
  xpbd::Real compliance = 0;                     // m/N, >= 0
  xpbd::Real feature_spacing = xpbd::Real(0.01); // m, > 0: box-edge sample spacing vs triangles
  bool wedges = true;  // xpbd_bullet::ContactSettings::wedges (XPBD and PBD)
  bool edge_contacts = true;  // xpbd_bullet::ContactSettings::edge_contacts (XPBD and PBD)
  // xpbd_bullet::ContactSettings::surface_edge_contacts (XPBD and PBD). Off
  // here, on in the library (since 2026-11-29): the built-in scenes,
  // docs/results.md and the state hashes were measured without it.
  bool surface_edges = false;
};

// An OBJ file (path relative to the scene file's directory) turned into a
// cloth or a closed pressurised surface (xpbd::add_triangle_mesh). mesh.name
// and mesh.index_base are set from the file (xpbd::io::add_obj_mesh).
struct ObjGenerator {
  std::string path;
  xpbd::TriangleMeshDesc mesh;
  bool triangulate = false;  // split polygons into triangles; false: a polygon is an error
};

// One generator: a builder call with its parameters.
using Generator = std::variant<xpbd::ClothGridDesc, xpbd::RopeDesc, xpbd::TetBoxDesc, ObjGenerator>;

struct SoftSpec {
  // Explicit particles and constraints, in xpbd's own SceneDesc (positions,
  // masses, velocities, radii, distances, pins, planes, bends, tets, tethers,
  // global volumes, self_collision, collision_triangles). Generators append to
  // it (see the numbering above).
  xpbd::SceneDesc particles;
  std::vector<Generator> generators;
  SoftContactSpec contacts;
};

// ---------------------------------------------------------------------------
// Rigid bodies.
enum class ShapeKind { sphere, box, capsule, cylinder, plane, convex_hull, mesh };

struct ShapeSpec {
  ShapeKind kind = ShapeKind::sphere;
  xpbd::Real radius = xpbd::Real(0.5);            // m: sphere, capsule, cylinder
  xpbd::Real height = 1;                          // m: capsule (between cap centres), cylinder (total); along the local y axis
  xpbd::Vec3 half_extents = xpbd::Vec3::Constant(xpbd::Real(0.5));  // m: box
  xpbd::Vec3 normal = xpbd::Vec3::UnitY();        // plane: { x : n.x/|n| = offset } in the body frame
  xpbd::Real offset = 0;                          // m: plane
  std::vector<xpbd::Vec3> points;                 // m: convex hull vertices (body frame)
  // Static triangle mesh: either a file (OBJ, relative to the scene file) or
  // explicit vertices and triangles; scale multiplies the vertices.
  std::string mesh_file;
  std::vector<xpbd::Vec3> vertices;               // m
  std::vector<std::array<int, 3>> triangles;      // 0-based vertex indices
  xpbd::Real scale = 1;                           // > 0
};

struct RigidSpec {
  std::string name;                               // optional, for messages and output
  ShapeSpec shape;
  xpbd::Real mass = 0;                            // kg, >= 0; 0 = static. plane and mesh: must be 0
  xpbd::Vec3 position = xpbd::Vec3::Zero();       // m, centre of mass
  // Orientation as a unit quaternion (w, x, y, z). Scene files: |q| must be
  // within 1e-3 of 1 (catches typos, accepts 4-digit hand rounding); it is
  // normalised on load.
  std::array<xpbd::Real, 4> orientation{1, 0, 0, 0};
  xpbd::Vec3 velocity = xpbd::Vec3::Zero();       // m/s
  xpbd::Vec3 angular_velocity = xpbd::Vec3::Zero();  // rad/s
  xpbd::Real friction = xpbd::Real(0.5);          // >= 0, Bullet's btCollisionObject friction
  xpbd::Real restitution = 0;                     // in [0, 1]
  // Bullet's btRigidBody::setDamping, each in [0, 1]: the velocity is
  // multiplied by (1 - damping)^t per t seconds.
  xpbd::Real linear_damping = 0;
  xpbd::Real angular_damping = 0;
  bool kinematic = false;                         // moved by its velocity, not by forces (mass ignored)
};

// A particle held at a point of a rigid body (XpbdWorld::attach).
struct AttachmentSpec {
  xpbd::Index particle = 0;  // global particle index
  int body = 0;              // index into SceneSpec::bodies
  // Point in the body's frame (m); empty = where the particle starts.
  std::optional<xpbd::Vec3> local;
  xpbd::Real compliance = 0;  // m/N, >= 0
};

// ---------------------------------------------------------------------------
struct SceneSpec {
  std::string name;         // short identifier, [a-z0-9_-]
  std::string description;  // one line
  SolverSpec solver;
  SoftSpec soft;
  std::vector<RigidSpec> bodies;
  std::vector<AttachmentSpec> attachments;
  // Not part of the scene file: the directory relative file paths (OBJ
  // generators, mesh shapes) are resolved against -- the scene file's
  // directory (parse_scene sets it); empty = the current directory.
  std::filesystem::path base_dir;
};

// The particle system a SoftSpec describes, ready for xpbd::compile.
struct ExpandedSoft {
  xpbd::SceneDesc scene;
  // For pictures and exports: the surface triangles (cloth and mesh
  // triangles, the tet boxes' boundary faces) and line segments (rope links)
  // in global particle indices.
  // The explicit part contributes its collision_triangles and
  // global_volumes triangles (once each) and its distances as lines.
  std::vector<std::array<xpbd::Index, 3>> triangles;
  std::vector<std::array<xpbd::Index, 2>> lines;
  // Where each part ended up, for error messages: the sizes of the SceneDesc
  // arrays, keyed by SceneDesc field name ("positions", "distances", "pins",
  // ...), after the explicit part (part_sizes[0]) and after generator g
  // (part_sizes[g + 1]).
  std::vector<std::map<std::string, std::size_t>> part_sizes;
};

// Explicit particles first, then each generator in order. OBJ paths are
// resolved against base_dir. Checks every generator field (and calls the
// builders, which check the rest); throws xpbd::SceneError naming the
// generator and field ("generators[2].cloth.nx: must be >= 2, got 1") for
// invalid input. The explicit part is left to xpbd::compile.
ExpandedSoft expand(const SoftSpec& soft, const std::filesystem::path& base_dir);

// Vertices (m, body frame, already multiplied by shape.scale) and triangles
// of a mesh shape: its OBJ file (resolved against base_dir) or its explicit
// vertices and triangles. Throws xpbd::SceneError for a shape that is not a
// usable mesh (xpbd::io::ObjError for a bad file).
xpbd::TriangleMesh body_mesh(const ShapeSpec& shape, const std::filesystem::path& base_dir);

}  // namespace xpbd_demos

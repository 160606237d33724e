// Scene files (demos/scene_file.hpp, docs/scene-format.md): the malformed
// corpus in tests/demos/malformed/ (every file fails with its JSON path), the
// documented example, exact round trips SceneSpec -> JSON text -> SceneSpec
// (compared field by field and as compiled xpbd::Models, bit for bit), the
// particle numbering of expand(), and --set.
//
// Expected values are written by hand from the format's definition
// (particle counts, indices, positions of a generator's particles), never
// taken from the code under test.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "demos/scene_file.hpp"
#include "support/scene_compare.hpp"
#include "demos/scene_spec.hpp"
#include "xpbd/compile.hpp"
#include "xpbd/step.hpp"

#ifndef XPBD_SOURCE_DIR
#error "XPBD_SOURCE_DIR must be defined (tests/CMakeLists.txt)"
#endif

namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

namespace fs = std::filesystem;
using nlohmann::json;
using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;
using namespace xpbd_demos;
using xpbd_demos::test::round_trip;

const fs::path kSource = XPBD_SOURCE_DIR;

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A scratch directory per test, removed at the end.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("xpbd_scene_file_" + std::to_string(::getpid()) + "_" + info->name());
    fs::create_directories(dir_);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  const fs::path& path() const { return dir_; }

 private:
  fs::path dir_;
};

// ---------------------------------------------------------------------------
// The malformed corpus.

TEST(SceneFile, MalformedCorpusNamesFileAndPath) {
  const fs::path dir = kSource / "tests/demos/malformed";
  std::map<std::string, std::string> expected;
  std::istringstream table(read_text(dir / "EXPECTED.txt"));
  for (std::string line; std::getline(table, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream f(line);
    std::string file, want;
    f >> file >> want;
    ASSERT_FALSE(want.empty()) << "EXPECTED.txt line without expectation: " << line;
    EXPECT_TRUE(expected.emplace(file, want).second) << "listed twice: " << file;
  }
  // Every file is listed and every listed file exists: a new case cannot
  // be forgotten, an expectation cannot refer to nothing.
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".json") files.insert(e.path().filename().string());
  for (const auto& f : files) EXPECT_TRUE(expected.count(f)) << f << " is not in EXPECTED.txt";
  for (const auto& [f, want] : expected) EXPECT_TRUE(files.count(f)) << f << " is listed but missing";
  EXPECT_GE(files.size(), 20u);

  for (const auto& [f, want] : expected) {
    const fs::path path = dir / f;
    const std::string label = path.string();
    try {
      (void)load_scene_file(path);
      ADD_FAILURE() << f << ": loaded without error";
    } catch (const SceneFileError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(label + ": ", 0), 0u) << f << ": message does not start with the file: " << what;
      EXPECT_EQ(e.file(), label);
      if (want[0] == '/') {
        EXPECT_EQ(e.json_path(), want) << f << ": " << what;
        EXPECT_NE(what.find(label + ": " + want + ": "), std::string::npos) << what;
      } else {
        EXPECT_TRUE(e.json_path().empty()) << f << ": " << what;
        EXPECT_NE(e.reason().find(want), std::string::npos) << f << ": " << what;
      }
      EXPECT_FALSE(e.reason().empty());
    } catch (const std::exception& e) {
      ADD_FAILURE() << f << ": not a SceneFileError: " << e.what();
    }
  }
}

TEST(SceneFile, MissingFileAndDirectory) {
  try {
    (void)load_scene_file("does-not-exist-4711.json");
    ADD_FAILURE() << "no error";
  } catch (const SceneFileError& e) {
    EXPECT_STREQ(e.what(), "does-not-exist-4711.json: cannot open: No such file or directory");
  }
  ScratchDir tmp;
  EXPECT_THROW((void)load_scene_file(tmp.path()), SceneFileError);
}

TEST(SceneFile, SyntaxErrorGivesLineAndColumn) {
  ScratchDir tmp;
  const fs::path p = tmp.write("bad.json", "{\n  \"solver\": {\"dt\": 0.01,}\n}\n");
  try {
    (void)load_scene_file(p);
    ADD_FAILURE() << "no error";
  } catch (const SceneFileError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("line 2, column"), std::string::npos) << what;
  }
}

// ---------------------------------------------------------------------------
// The documented example.

TEST(SceneFile, DocumentedExampleLoadsAndMatchesTheDocs) {
  const fs::path file = kSource / "docs/scene-example.json";
  const SceneSpec s = load_scene_file(file);
  EXPECT_EQ(s.name, "example");
  ASSERT_EQ(s.bodies.size(), 3u);
  ASSERT_EQ(s.attachments.size(), 1u);
  EXPECT_EQ(s.attachments[0].body, 2);  // given by name, "crate"

  // Particles: 2 explicit, a 12 x 12 cloth (144), a rope of 10: 156; the
  // rope's last particle (155) hangs 9 * 0.05 m below its start (0.8, 2, 0).
  const ExpandedSoft ex = expand(s.soft, s.base_dir);
  ASSERT_EQ(ex.scene.num_particles(), 156);
  EXPECT_EQ(ex.scene.positions[2], Vec3(Real(-0.5), Real(1.2), Real(-0.5)));  // cloth (0, 0)
  const Vec3 last = ex.scene.positions[155];
  // start + (9 * 0.05) * dir in Real arithmetic: three roundings of values
  // below 2, each at most eps (absolute, since the values are < 2).
  const Real tol = 4 * xpbd::kEpsilon;
  EXPECT_NEAR(last.x(), 0.8, tol);
  EXPECT_NEAR(last.y(), 2.0 - 9 * 0.05, tol);
  EXPECT_NEAR(last.z(), 0.0, tol);
  // Pictures: 2 * 11 * 11 cloth triangles, 1 explicit + 9 rope lines.
  EXPECT_EQ(ex.triangles.size(), 242u);
  EXPECT_EQ(ex.lines.size(), 10u);

  // The JSON block of docs/scene-format.md is this file.
  const std::string md = read_text(kSource / "docs/scene-format.md");
  const std::string open = "<!-- example: docs/scene-example.json -->\n```json\n";
  const auto begin = md.find(open);
  ASSERT_NE(begin, std::string::npos) << "docs/scene-format.md has no marked example block";
  const auto body = begin + open.size();
  const auto end = md.find("```", body);
  ASSERT_NE(end, std::string::npos);
  EXPECT_EQ(json::parse(md.substr(body, end - body)), json::parse(read_text(file)));
}

// ---------------------------------------------------------------------------
// Round trips.

xpbd::Material mat(Real c, Real d = 0, Real k = 1) { return xpbd::Material{c, d, k}; }

TEST(SceneFile, RoundTripExplicitParticlesAndEveryElementType) {
  SceneSpec s;
  s.name = "explicit";
  s.description = "every explicit element type, awkward numbers";
  s.solver.method = Solver::pbd;
  s.solver.dt = Real(1) / Real(240);
  s.solver.substeps = 3;
  s.solver.iterations = 7;
  s.solver.frames = 11;
  s.solver.drag = Real(0.1);
  s.solver.alternate_sweeps = true;
  s.solver.coloured = true;
  s.solver.direct_chains = true;
  s.solver.chain_passes = 5;
  s.solver.chain_tolerance = Real(2.5e-4);
  s.solver.hierarchy = true;
  s.solver.hierarchy_slack = Real(0.03);
  s.solver.gravity = Vec3(Real(0.1), Real(-9.80665), Real(1) / Real(3));
  s.solver.bullet_kLST = Real(0.7);
  s.solver.tolerance = 0.04;
  s.solver.tolerance_measure = ToleranceMeasure::residual;  // not the default
  xpbd::SceneDesc& d = s.soft.particles;
  // A tetrahedron (closed surface, volume, bends) plus a fifth particle.
  d.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1),
                 Vec3(Real(0.3), Real(0.3), Real(2))};
  d.masses = {Real(0.1), Real(1) / Real(3), Real(2), 0, Real(1e-3)};
  d.velocities = {Vec3::Zero(), Vec3(Real(0.5), 0, 0), Vec3::Zero(), Vec3::Zero(), Vec3(0, 0, Real(-1e-7))};
  d.radii = {Real(0.01), Real(0.01), Real(0.02), Real(0.01), Real(0.05)};
  d.distances = {{0, 1, std::nullopt, mat(Real(1e-6), Real(0.25), Real(0.9))}, {1, 2, Real(1.5), mat(0)}};
  d.collisions = {{0, 4, mat(Real(1e-5))}};
  d.pins = {{3, std::nullopt, mat(0)}, {4, Vec3(Real(0.3), Real(0.3), Real(2.5)), mat(Real(1e-4))}};
  d.planes = {{Vec3(0, 2, 0), Real(-0.5), mat(0, 0, Real(0.5))}};
  d.penetrations = {{{4, 0, 1, 2}, Real(0.02), mat(0)}, {{4, 0, 2, 3}, std::nullopt, mat(0)}};
  d.dihedral_bends = {{{0, 1, 2, 3}, Real(0.3), mat(Real(0.01))},
                      {{1, 2, 0, 3}, std::nullopt, mat(Real(0.02))}};
  d.isometric_bends = {{{0, 1, 2, 3}, mat(Real(0.5))}};
  d.tets = {{{0, 1, 2, 3}, std::nullopt, mat(Real(1e-3))}, {{0, 1, 2, 4}, Real(0.05), mat(0)}};
  d.tethers = {{4, 0, Real(3), mat(0)}, {2, 3, std::nullopt, mat(Real(1e-8))}};
  // Outward (counter-clockwise seen from outside) faces of the tetrahedron.
  d.global_volumes = {{{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}, Real(1.25), mat(Real(1e-9))}};
  d.self_collision = {true, Real(0.05), false, mat(Real(1e-6), Real(0.1))};
  d.collision_triangles = {{0, 1, 2}, {1, 2, 3}};
  s.soft.contacts.thickness = Real(0.002);
  s.soft.contacts.static_friction = Real(0.8);
  s.soft.contacts.dynamic_friction = Real(0.6);
  s.soft.contacts.restitution = Real(0.3);
  s.soft.contacts.compliance = Real(1e-7);
  s.soft.contacts.feature_spacing = Real(0.02);
  // Not the defaults, so the round trip can fail.
  s.soft.contacts.wedges = false;
  s.soft.contacts.edge_contacts = false;
  s.soft.contacts.surface_edges = true;
  const SceneSpec back = round_trip(s);

  // The explicit arrays themselves (the model above holds them compiled).
  const xpbd::SceneDesc& b = back.soft.particles;
  EXPECT_TRUE(b.velocities == d.velocities);
  EXPECT_EQ(b.radii, d.radii);
  ASSERT_EQ(b.distances.size(), 2u);
  EXPECT_FALSE(b.distances[0].rest.has_value());
  EXPECT_EQ(b.distances[1].rest, Real(1.5));
  EXPECT_EQ(b.pins[1].target, d.pins[1].target);
  EXPECT_FALSE(b.pins[0].target.has_value());
  EXPECT_EQ(b.penetrations[0].thickness, Real(0.02));
  EXPECT_EQ(b.dihedral_bends[0].rest_angle, Real(0.3));
  EXPECT_EQ(b.tets[1].rest_volume, Real(0.05));
  EXPECT_EQ(b.tethers[0].length, Real(3));
  EXPECT_EQ(b.global_volumes[0].pressure, Real(1.25));

  // ExpandedSoft of the explicit part: the collision triangles, the volume's
  // faces (each once), the distances as lines.
  const ExpandedSoft ex = expand(back.soft, {});
  // {0,2,1} and {1,2,3} of the volume repeat the two collision triangles.
  EXPECT_EQ(ex.triangles.size(), 4u);
  EXPECT_EQ(ex.lines.size(), 2u);
}

// A 4-vertex OBJ: a square of two triangles (z = 0), 1 m side.
constexpr const char* kSquareObj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";

TEST(SceneFile, RoundTripGeneratorsAndBodies) {
  ScratchDir tmp;
  tmp.write("square.obj", kSquareObj);
  tmp.write("ramp.obj", "v 0 0 0\nv 4 0 0\nv 4 1 4\nv 0 1 4\nf 1 2 3 4\n");  // a quad: split
  SceneSpec s;
  s.name = "generators";
  s.base_dir = tmp.path();
  s.soft.particles.positions = {Vec3(0, 3, 0)};
  s.soft.particles.masses = {1};

  xpbd::ClothGridDesc cloth;
  cloth.nx = 5;
  cloth.ny = 4;
  cloth.size_u = Real(0.7);
  cloth.size_v = Real(0.3);
  cloth.origin = Vec3(Real(-0.35), 2, Real(0.1));
  cloth.u = Vec3(1, 0, 0);
  cloth.v = Vec3(0, 0, 1);
  cloth.mass = Real(0.123);
  cloth.radius = Real(0.004);
  cloth.stretch = mat(Real(1e-7), Real(0.01));
  cloth.shear_both_diagonals = false;
  cloth.shear_mat = mat(Real(2e-6));
  cloth.bend_distance = false;
  cloth.hinge_bending = xpbd::HingeBending::isometric;
  cloth.hinge_mat = mat(Real(3));
  cloth.pins = xpbd::ClothPins::top_corners;
  cloth.pinned = {{2, 0}, {2, 0}};
  cloth.tethers = xpbd::TetherAnchors::nearest_pinned;
  cloth.tether_metric = xpbd::TetherMetric::euclidean;
  cloth.collision_triangles = true;
  xpbd::RopeDesc rope;
  rope.n = 7;
  rope.start = Vec3(1, 2, 0);
  rope.dir = Vec3(Real(0.6), Real(-0.8), 0);
  rope.spacing = Real(0.03);
  rope.mass = Real(0.002);
  rope.pin_first = false;
  rope.mat = mat(Real(1e-8), 0, Real(0.5));
  xpbd::TetBoxDesc box;
  box.nx = 2;
  box.ny = 1;
  box.nz = 3;
  box.origin = Vec3(2, 0, 0);
  box.size = Vec3(Real(0.2), Real(0.1), Real(0.3));
  box.split = xpbd::TetSplit::five;
  box.mass = 3;
  box.bulk_modulus = Real(1e5);
  box.edge_mat = mat(Real(1e-6));
  box.pinned = {{0, 0, 0}, {2, 1, 3}};
  ObjGenerator obj;
  obj.path = "square.obj";
  obj.mesh.scale = Real(0.5);
  obj.mesh.offset = Vec3(0, 1, 0);
  obj.mesh.mass = Real(0.4);
  obj.mesh.bending = xpbd::HingeBending::dihedral;
  obj.mesh.bend_mat = mat(Real(0.1));
  s.soft.generators = {cloth, rope, box, obj};

  RigidSpec b;
  b.name = "ball";
  b.shape.kind = ShapeKind::sphere;
  b.shape.radius = Real(0.25);
  b.mass = Real(1.5);
  b.position = Vec3(0, Real(0.7), 0);
  b.velocity = Vec3(0, -1, 0);
  b.angular_velocity = Vec3(0, 0, Real(0.1));
  b.friction = Real(0.3);
  b.restitution = Real(0.2);
  b.linear_damping = Real(0.05);
  b.angular_damping = Real(0.3);
  s.bodies.push_back(b);
  RigidSpec crate;
  crate.shape.kind = ShapeKind::box;
  crate.shape.half_extents = Vec3(Real(0.1), Real(0.2), Real(0.3));
  crate.mass = 2;
  // A rotation of 90 degrees about z, normalised in Real arithmetic.
  const Real h = std::sqrt(Real(0.5));
  crate.orientation = {h, 0, 0, h};
  s.bodies.push_back(crate);
  RigidSpec cap;
  cap.shape.kind = ShapeKind::capsule;
  cap.shape.radius = Real(0.05);
  cap.shape.height = Real(0.4);
  cap.kinematic = true;
  cap.velocity = Vec3(Real(0.1), 0, 0);
  s.bodies.push_back(cap);
  RigidSpec cyl;
  cyl.shape.kind = ShapeKind::cylinder;
  cyl.shape.radius = Real(0.3);
  cyl.shape.height = Real(0.1);
  cyl.mass = Real(0.7);
  s.bodies.push_back(cyl);
  RigidSpec ground;
  ground.name = "ground";
  ground.shape.kind = ShapeKind::plane;
  ground.shape.normal = Vec3(0, 1, 0);
  ground.shape.offset = Real(-0.01);
  s.bodies.push_back(ground);
  RigidSpec hull;
  hull.shape.kind = ShapeKind::convex_hull;
  hull.shape.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1),
                       Vec3(Real(0.2), Real(0.2), Real(0.2))};
  hull.mass = 1;
  s.bodies.push_back(hull);
  RigidSpec ramp;
  ramp.shape.kind = ShapeKind::mesh;
  ramp.shape.mesh_file = "ramp.obj";
  ramp.shape.scale = 2;
  s.bodies.push_back(ramp);
  RigidSpec step;
  step.shape.kind = ShapeKind::mesh;
  step.shape.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 1)};
  step.shape.triangles = {{0, 1, 2}};
  s.bodies.push_back(step);

  // Particles: 1 explicit, cloth 5 x 4 = 20 (1..20), rope 7 (21..27), tet
  // box 3 x 2 x 4 = 24 (28..51), square 4 (52..55).
  s.attachments = {{27, 0, std::nullopt, 0}, {55, 1, Vec3(0, Real(0.2), 0), Real(1e-5)}};
  const SceneSpec back = round_trip(s);
  const ExpandedSoft ex = expand(back.soft, back.base_dir);
  ASSERT_EQ(ex.scene.num_particles(), 56);
  EXPECT_EQ(ex.part_sizes.size(), 5u);
  EXPECT_EQ(ex.part_sizes[1].at("positions"), 21u);
  EXPECT_EQ(ex.part_sizes[2].at("positions"), 28u);
  EXPECT_EQ(ex.part_sizes[3].at("positions"), 52u);
  // Cloth particle (i, j) = 1 + j*5 + i sits at origin + i*du*u + j*dv*v.
  EXPECT_EQ(ex.scene.positions[1], cloth.origin);
  EXPECT_EQ(ex.scene.masses[1], 0);  // (0, 0) is a top corner: pinned
  // Rope particle k = 21 + k at start + k*spacing*dir; the last one: k = 6.
  EXPECT_NEAR(ex.scene.positions[27].x(), 1 + 6 * 0.03 * 0.6, 16 * xpbd::kEpsilon);
  // Square vertex 3 (0, 1, 0) -> offset + 0.5 * (0, 1, 0) = (0, 1.5, 0).
  EXPECT_EQ(ex.scene.positions[55], Vec3(0, Real(1.5), 0));
  // Pictures: cloth 2*4*3 = 24 triangles, tet box surface 2*(2*1 + 1*3 + 2*3)*2 = 44,
  // square 2; rope 6 lines.
  EXPECT_EQ(ex.triangles.size(), 24u + 44u + 2u);
  EXPECT_EQ(ex.lines.size(), 6u);
  // The ramp's quad is split into 2 triangles, its vertices scaled by 2.
  const xpbd::TriangleMesh ramp_mesh = body_mesh(back.bodies[6].shape, back.base_dir);
  EXPECT_EQ(ramp_mesh.triangles.size(), 2u);
  EXPECT_EQ(ramp_mesh.positions[2], Vec3(8, 2, 8));
}

// Numbers at the edges of what a decimal text must carry: every one comes
// back bit for bit (double build: shortest round-trip decimal; float build:
// the float's shortest decimal, read back through a double).
TEST(SceneFile, NumbersRoundTripBitExactly) {
  const Real values[] = {Real(0.1),
                         Real(1) / Real(3),
                         std::nextafter(Real(1), Real(2)),
                         std::nextafter(Real(1), Real(0)),
                         std::numeric_limits<Real>::denorm_min(),
                         std::numeric_limits<Real>::min(),
                         std::numeric_limits<Real>::max(),
                         -std::numeric_limits<Real>::max(),
                         Real(-0.0),
                         Real(1e-30),
                         Real(6.02214076e23),
                         Real(16777217),
                         Real(-9.80665)};
  SceneSpec s;
  s.soft.particles.add_particle(Vec3::Zero(), 1);  // a scene needs one
  for (Real v : values) {
    RigidSpec b;
    b.shape.kind = ShapeKind::sphere;
    b.position = Vec3(v, -v, v * Real(0.5));
    s.bodies.push_back(b);
  }
  // The float build writes a float's shortest decimal, not the digits of
  // its double value (0.100000001490116...).
  EXPECT_EQ(to_json(s)["bodies"][0]["position"][0].dump(), "0.1");
  const SceneSpec back = parse_scene(parse_json_text(scene_text(to_json(s)), "n"), "n", {});
  ASSERT_EQ(back.bodies.size(), s.bodies.size());
  for (std::size_t i = 0; i < s.bodies.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const Real a = s.bodies[i].position[c], b = back.bodies[i].position[c];
      EXPECT_EQ(std::memcmp(&a, &b, sizeof(Real)), 0)
          << "value " << i << " component " << c << ": " << a << " vs " << b;
    }
}

TEST(SceneFile, MissingKeysTakeTheCppDefaults) {
  const SceneSpec s = parse_scene(json::parse(R"({"bodies": [{"shape": {"box": {}}}],
      "soft": {"generators": [{"cloth": {}}, {"rope": {}}, {"tet_box": {}}]}})"),
                                  "d", {});
  const SceneSpec def;
  EXPECT_EQ(s.solver.dt, def.solver.dt);
  EXPECT_EQ(s.solver.substeps, def.solver.substeps);
  EXPECT_EQ(s.solver.gravity, def.solver.gravity);
  EXPECT_EQ(s.bodies[0].shape.half_extents, ShapeSpec{}.half_extents);
  EXPECT_EQ(s.bodies[0].orientation, (std::array<Real, 4>{1, 0, 0, 0}));
  EXPECT_EQ(std::get<xpbd::ClothGridDesc>(s.soft.generators[0]).nx, xpbd::ClothGridDesc{}.nx);
  EXPECT_EQ(std::get<xpbd::RopeDesc>(s.soft.generators[1]).spacing, xpbd::RopeDesc{}.spacing);
  EXPECT_EQ(std::get<xpbd::TetBoxDesc>(s.soft.generators[2]).split, xpbd::TetBoxDesc{}.split);
}

TEST(SceneFile, HandRoundedQuaternionIsNormalised) {
  const SceneSpec s = parse_scene(json::parse(R"({"bodies": [{"shape": {"sphere": {}}, "mass": 1,
      "orientation": [0.7071, 0, 0.7071, 0]}], "soft": {"particles": {"positions": [[0, 0, 0]], "masses": [1]}}})"),
                                  "q", {});
  const auto& q = s.bodies[0].orientation;
  const double n =
      std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
  EXPECT_NEAR(n, 1.0, 4 * xpbd::kEpsilon);
  EXPECT_EQ(q[0], q[2]);
}

// ---------------------------------------------------------------------------
// Errors of generated elements are traced back to their generator, errors
// of explicit ones to the element.

// The limit on tether lengths counts what the builder computes: a cloth
// pinned along its 1000-particle top edge asks for 1000 x 32000 straight
// lines with euclidean tethers (refused, naming the field), but for one
// search from all pins with geodesic ones (accepted: one tether per movable
// particle).
TEST(SceneFile, TetherLengthLimitCountsOneSearchForGeodesicNearest) {
  json j = json::parse(R"({"soft": {"generators": [{"cloth": {"nx": 1000, "ny": 32, "pins": "top_edge",
      "tethers": "nearest_pinned", "tether_metric": "euclidean"}}]}})");
  try {
    (void)parse_scene(j, "banner.json", ".");
    ADD_FAILURE() << "no error";
  } catch (const SceneFileError& e) {
    EXPECT_EQ(e.json_path(), "/soft/generators/0/cloth/tethers") << e.what();
    EXPECT_NE(e.reason().find("32000000 tether lengths"), std::string::npos) << e.what();
  }
  j["soft"]["generators"][0]["cloth"]["tether_metric"] = "geodesic";
  const SceneSpec spec = parse_scene(j, "banner.json", ".");
  const ExpandedSoft soft = expand(spec.soft, spec.base_dir);
  EXPECT_EQ(soft.scene.tethers.size(), std::size_t(1000 * 32 - 1000));
}

TEST(SceneFile, CompileErrorOfAGeneratedElementNamesTheGenerator) {
  ScratchDir tmp;
  // Vertices 1 and 4 coincide, and face 2 uses both: a zero-length edge,
  // i.e. a distance constraint with rest length 0, found by compile().
  tmp.write("pinch.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 0\nf 1 2 3\nf 1 4 2\n");
  const json j = json::parse(R"({"soft": {
      "particles": {"positions": [[5, 0, 0], [6, 0, 0]], "masses": [1, 1]},
      "distances": [{"a": 0, "b": 1}],
      "generators": [{"rope": {"n": 3}}, {"obj": {"path": "pinch.obj"}}]}})");
  try {
    (void)parse_scene(j, "pinch.json", tmp.path());
    ADD_FAILURE() << "no error";
  } catch (const SceneFileError& e) {
    EXPECT_EQ(e.json_path(), "/soft/generators/1/obj") << e.what();
    EXPECT_EQ(e.reason().rfind("generated distances[", 0), 0u) << e.what();
  }
}

// ---------------------------------------------------------------------------
// --set

TEST(SceneFile, SetOverridesExistingFieldsOnly) {
  SceneSpec s;
  xpbd::ClothGridDesc cloth;
  cloth.nx = cloth.ny = 4;
  s.soft.generators = {cloth};
  RigidSpec b;
  b.shape.kind = ShapeKind::sphere;
  s.bodies = {b};
  const SceneSpec t = apply_sets(s,
                                 {"solver.substeps=20", "bodies.0.mass=2", "soft.generators.0.cloth.nx=16",
                                  "solver.method=pbd", "solver.gravity=[0,0,-1.5]", "name=renamed"},
                                 "s.json");
  EXPECT_EQ(t.solver.substeps, 20);
  EXPECT_EQ(t.bodies[0].mass, 2);
  EXPECT_EQ(std::get<xpbd::ClothGridDesc>(t.soft.generators[0]).nx, 16);
  EXPECT_EQ(t.solver.method, Solver::pbd);
  EXPECT_EQ(t.solver.gravity, Vec3(0, 0, Real(-1.5)));
  EXPECT_EQ(t.name, "renamed");

  auto path_of = [&](const std::string& a) {
    json j = to_json(s);
    try {
      apply_set(j, a);
    } catch (const SceneFileError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--set: ", 0), 0u) << e.what();
      return e.json_path();
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(path_of("solver.substepz=3"), "/solver/substepz");
  EXPECT_EQ(path_of("bodies.1.mass=3"), "/bodies/1");
  EXPECT_EQ(path_of("bodies.x.mass=3"), "/bodies/x");
  EXPECT_EQ(path_of("solver.dt.x=3"), "/solver/dt");
  EXPECT_EQ(path_of("solver.substeps"), "");
  // A value of the wrong type or range is caught when the scene is parsed.
  try {
    (void)apply_sets(s, {"solver.substeps=0"}, "s.json");
    ADD_FAILURE() << "no error";
  } catch (const SceneFileError& e) {
    EXPECT_STREQ(e.what(), "s.json: /solver/substeps: must be >= 1, got 0");
  }
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace

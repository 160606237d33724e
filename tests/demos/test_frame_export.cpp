// Frame export (demos/frame_export.hpp): the triangulated rigid bodies
// against the closed-form geometry of their shapes, and OBJ / legacy VTK
// files read back (OBJ with tinyobjloader, VTK with a small reader here) and
// compared with the data written.
#include <gtest/gtest.h>

#include <tiny_obj_loader.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "demos/frame_export.hpp"
#include "support/xpbd_test.hpp"
#include "xpbd/error.hpp"

namespace xpbd_demos {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

namespace fs = std::filesystem;
using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;
using Tri = std::array<Index, 3>;
using Line = std::array<Index, 2>;
using xpbd::test::throws_naming;

constexpr Real kEps = std::numeric_limits<Real>::epsilon();
constexpr Real kPi = std::numbers::pi_v<Real>;

// Volume enclosed by a closed, outward-wound triangle mesh (divergence
// theorem: the sum of the signed tetrahedra origin-a-b-c).
Real volume(const RigidMesh& m) {
  Real v = 0;
  for (const Tri& t : m.triangles)
    v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6;
  return v;
}

// Every directed edge once, and its reverse once: a closed surface whose
// triangles are wound consistently.
::testing::AssertionResult closed_and_consistent(const RigidMesh& m) {
  std::map<std::pair<Index, Index>, int> edges;
  for (const Tri& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, count] : edges) {
    if (count != 1)
      return ::testing::AssertionFailure() << "edge " << e.first << "-" << e.second << " used " << count << " times";
    if (!edges.count({e.second, e.first}))
      return ::testing::AssertionFailure() << "edge " << e.first << "-" << e.second << " has no reverse (open)";
  }
  return ::testing::AssertionSuccess();
}

// Smallest distance from `inside` to the plane of a triangle: a convex
// polyhedron contains the ball of that radius around `inside`.
Real min_face_distance(const RigidMesh& m, const Vec3& inside) {
  Real d = std::numeric_limits<Real>::max();
  for (const Tri& t : m.triangles) {
    const Vec3 n = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).normalized();
    d = std::min(d, n.dot(m.vertices[t[0]] - inside));
  }
  return d;
}

// Quaternion (w, x, y, z) of a rotation by `angle` about the unit `axis`.
std::array<Real, 4> quat(Real angle, const Vec3& axis) {
  const Real s = std::sin(angle / 2);
  return {std::cos(angle / 2), s * axis.x(), s * axis.y(), s * axis.z()};
}

// --------------------------------------------------------------------------
// Shapes.

TEST(RigidMesh, SphereVerticesLieOnTheSphereAndEncloseAnInscribedPolyhedron) {
  ShapeSpec s;
  s.kind = ShapeKind::sphere;
  s.radius = Real(0.3);
  const Vec3 p(1, 2, -3);
  const RigidMesh m = rigid_mesh(s, p, quat(Real(0.7), Vec3(1, 2, 2).normalized()), ".");
  // 12 x 8 grid: two poles and 7 rings of 12; 12 triangles at each pole and
  // 2 x 12 between consecutive rings.
  EXPECT_EQ(m.vertices.size(), 2u + 12u * 7u);
  EXPECT_EQ(m.triangles.size(), 2u * 12u + 2u * 12u * 6u);
  EXPECT_FALSE(m.unbounded);
  // Rotation and translation round off a few ulps of |p| + r.
  const Real tol = 16 * kEps * (p.norm() + s.radius);
  for (const Vec3& v : m.vertices) EXPECT_NEAR((v - p).norm(), s.radius, tol);
  EXPECT_TRUE(closed_and_consistent(m));
  // Inscribed in the sphere, so smaller than it; convex, so it contains the
  // ball that touches its nearest face plane. (Volume relative to p: shift
  // the mesh so that the divergence sum has no cancellation of large terms.)
  RigidMesh local = m;
  for (Vec3& v : local.vertices) v -= p;
  const Real v = volume(local);
  const Real r_in = min_face_distance(local, Vec3::Zero());
  EXPECT_GT(r_in, Real(0.8) * s.radius);  // outward winding: positive distances
  EXPECT_LT(v, 4 * kPi / 3 * std::pow(s.radius, Real(3)));
  EXPECT_GT(v, 4 * kPi / 3 * std::pow(r_in, Real(3)));
}

TEST(RigidMesh, CylinderIsARegularPrismAlongLocalY) {
  ShapeSpec s;
  s.kind = ShapeKind::cylinder;
  s.radius = Real(0.25);
  s.height = Real(1.5);
  const RigidMesh m = shape_mesh(s, ".");
  for (const Vec3& v : m.vertices) {
    EXPECT_EQ(std::abs(v.y()), s.height / 2);
    const Real rho = std::hypot(v.x(), v.z());
    // Either a rim vertex at the radius or a cap centre on the axis.
    EXPECT_TRUE(std::abs(rho - s.radius) < 4 * kEps * s.radius || rho == 0) << rho;
  }
  EXPECT_TRUE(closed_and_consistent(m));
  // Volume of a prism over the regular 12-gon of circumradius r:
  // (n / 2) r^2 sin(2 pi / n) h. About 50 triangle terms of size ~V.
  const Real expected = Real(6) * s.radius * s.radius * std::sin(2 * kPi / 12) * s.height;
  EXPECT_NEAR(volume(m), expected, 64 * kEps * expected);
}

TEST(RigidMesh, CapsuleSurfaceIsAtTheRadiusFromItsAxisSegment) {
  ShapeSpec s;
  s.kind = ShapeKind::capsule;
  s.radius = Real(0.2);
  s.height = Real(0.6);
  const RigidMesh m = shape_mesh(s, ".");
  Real y_max = 0;
  for (const Vec3& v : m.vertices) {
    // Distance to the segment between the cap centres (0, +-h/2, 0).
    const Real y = std::clamp(v.y(), -s.height / 2, s.height / 2);
    EXPECT_NEAR((v - Vec3(0, y, 0)).norm(), s.radius, 8 * kEps);
    y_max = std::max(y_max, v.y());
  }
  EXPECT_EQ(y_max, s.height / 2 + s.radius);
  EXPECT_TRUE(closed_and_consistent(m));
  // Convex and inscribed in the capsule: less than its volume; contains the
  // 12-gon prism between the two equators (vertices of the mesh).
  const Real v = volume(m);
  const Real r = s.radius, h = s.height;
  EXPECT_LT(v, kPi * r * r * h + 4 * kPi / 3 * r * r * r);
  EXPECT_GT(v, Real(6) * r * r * std::sin(2 * kPi / 12) * h);

  // Height 0 is a sphere: no duplicated equator.
  s.height = 0;
  EXPECT_TRUE(closed_and_consistent(shape_mesh(s, ".")));
}

TEST(RigidMesh, BoxCornersFollowThePose) {
  ShapeSpec s;
  s.kind = ShapeKind::box;
  s.half_extents = Vec3(Real(0.5), Real(0.25), Real(2));
  // 90 degrees about z: (x, y, z) -> (-y, x, z).
  const Vec3 p(0, 1, 0);
  const RigidMesh m = rigid_mesh(s, p, quat(kPi / 2, Vec3::UnitZ()), ".");
  ASSERT_EQ(m.vertices.size(), 8u);
  ASSERT_EQ(m.triangles.size(), 12u);
  for (const Vec3& v : m.vertices) {
    EXPECT_NEAR(std::abs(v.x() - p.x()), s.half_extents.y(), 4 * kEps);
    EXPECT_NEAR(std::abs(v.y() - p.y()), s.half_extents.x(), 4 * kEps);
    EXPECT_NEAR(std::abs(v.z() - p.z()), s.half_extents.z(), 4 * kEps);
  }
  EXPECT_TRUE(closed_and_consistent(m));
  const Real expected = 8 * s.half_extents.prod();
  EXPECT_NEAR(volume(m), expected, 64 * kEps * expected);
}

TEST(RigidMesh, PlaneSquareIsCentredNearestTheOrigin) {
  ShapeSpec s;
  s.kind = ShapeKind::plane;
  s.normal = Vec3(0, 2, 0);  // not unit: normalised; the plane is y = offset = 1
  s.offset = 1;
  TessellationOptions opt;
  opt.plane_half_size = 3;
  const auto check_square = [&](const RigidMesh& m, const Vec3& n, const Vec3& centre) {
    ASSERT_EQ(m.vertices.size(), 4u);
    ASSERT_EQ(m.triangles.size(), 2u);
    EXPECT_TRUE(m.unbounded);
    Vec3 c = Vec3::Zero();
    for (const Vec3& v : m.vertices) {
      EXPECT_NEAR(n.dot(v - centre), 0, 16 * kEps * (1 + centre.norm()));
      c += v / 4;
    }
    EXPECT_LT((c - centre).norm(), 16 * kEps * (1 + centre.norm()));
    // Side 2 * half and a right angle.
    const Vec3 a = m.vertices[1] - m.vertices[0], b = m.vertices[3] - m.vertices[0];
    EXPECT_NEAR(a.norm(), 2 * opt.plane_half_size, 16 * kEps);
    EXPECT_NEAR(b.norm(), 2 * opt.plane_half_size, 16 * kEps);
    EXPECT_NEAR(a.dot(b), 0, 16 * kEps);
    // Counter-clockwise seen from the side the normal points to.
    for (const Tri& t : m.triangles)
      EXPECT_GT((m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).dot(n), 0);
  };
  // Body frame: centred at the point nearest the body origin.
  check_square(shape_mesh(s, ".", opt), Vec3::UnitY(), Vec3(0, 1, 0));
  // Rotated 90 degrees about x (y -> z) and moved: the world plane is
  // z = 1 + position.z = -3, nearest the origin at (0, 0, -3).
  check_square(rigid_mesh(s, Vec3(3, Real(0.5), -4), quat(kPi / 2, Vec3::UnitX()), ".", opt), Vec3::UnitZ(),
               Vec3(0, 0, -3));
}

TEST(RigidMesh, ConvexHullOfACubeWithInteriorPoints) {
  ShapeSpec s;
  s.kind = ShapeKind::convex_hull;
  for (int k = 0; k < 8; ++k)
    s.points.emplace_back((k & 1) ? Real(0.5) : Real(-0.5), (k & 2) ? Real(0.5) : Real(-0.5),
                          (k & 4) ? Real(0.5) : Real(-0.5));
  s.points.emplace_back(0, 0, 0);
  s.points.emplace_back(Real(0.1), Real(0.2), Real(-0.3));
  const RigidMesh m = shape_mesh(s, ".");
  // Only the corners are hull vertices; each square face is split in two.
  ASSERT_EQ(m.vertices.size(), 8u);
  EXPECT_EQ(m.triangles.size(), 12u);
  for (const Vec3& v : m.vertices) EXPECT_EQ(v.cwiseAbs(), Vec3::Constant(Real(0.5)));
  EXPECT_TRUE(closed_and_consistent(m));
  EXPECT_NEAR(volume(m), 1, 64 * kEps);
}

TEST(RigidMesh, ExplicitAndFileMeshesAreScaledAndPosed) {
  ShapeSpec s;
  s.kind = ShapeKind::mesh;
  s.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  s.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  s.scale = 2;
  const Vec3 p(Real(0.5), 0, 0);
  const RigidMesh m = rigid_mesh(s, p, quat(kPi / 2, Vec3::UnitZ()), ".");
  ASSERT_EQ(m.vertices.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    // (x, y, z) -> (-y, x, z), times 2, plus p.
    const Vec3 v = s.vertices[i] * 2;
    EXPECT_LT((m.vertices[i] - (Vec3(-v.y(), v.x(), v.z()) + p)).norm(), 8 * kEps);
  }
  ASSERT_EQ(m.triangles.size(), 4u);
  for (std::size_t t = 0; t < 4; ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.triangles[t][k], s.triangles[t][k]);
  // Tetrahedron of legs 2: volume 8 / 6.
  EXPECT_NEAR(volume(m), Real(8) / 6, 64 * kEps);

  // The same from an OBJ file, relative to base_dir, with a quad face
  // (split into two triangles).
  const fs::path dir = fs::temp_directory_path() / ("xpbd_rigid_mesh_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "quad.obj") << "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 2 3 4\n";
  ShapeSpec f;
  f.kind = ShapeKind::mesh;
  f.mesh_file = "quad.obj";
  f.scale = 3;
  const RigidMesh q = shape_mesh(f, dir);
  fs::remove_all(dir);
  ASSERT_EQ(q.vertices.size(), 4u);
  EXPECT_EQ(q.vertices[2], Vec3(3, 0, 3));
  EXPECT_EQ(q.triangles.size(), 2u);
}

TEST(RigidMesh, BadShapesAndPosesAreNamed) {
  ShapeSpec s;
  s.kind = ShapeKind::sphere;
  s.radius = -1;
  EXPECT_TRUE(throws_naming<xpbd::SceneError>([&] { (void)shape_mesh(s, "."); }, {"shape.radius", "> 0", "-1"}));
  s.kind = ShapeKind::box;
  s.half_extents = Vec3(1, 0, 1);
  EXPECT_TRUE(throws_naming<xpbd::SceneError>([&] { (void)shape_mesh(s, "."); }, {"shape.half_extents[1]", "0"}));
  s.kind = ShapeKind::plane;
  s.normal = Vec3::Zero();
  EXPECT_TRUE(throws_naming<xpbd::SceneError>([&] { (void)shape_mesh(s, "."); }, {"shape.normal"}));
  s.kind = ShapeKind::convex_hull;
  EXPECT_TRUE(throws_naming<xpbd::SceneError>([&] { (void)shape_mesh(s, "."); }, {"shape.points"}));
  s.kind = ShapeKind::mesh;
  s.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  s.triangles = {{0, 1, 3}};
  EXPECT_TRUE(throws_naming<xpbd::SceneError>([&] { (void)shape_mesh(s, "."); }, {"triangles[0][2]", "index 3"}));
  s.vertices.clear();
  s.triangles.clear();
  s.mesh_file = "does_not_exist.obj";
  EXPECT_TRUE(throws_naming<xpbd::SceneError>([&] { (void)shape_mesh(s, "/nonexistent_dir"); },
                                              {"does_not_exist.obj"}));
  ShapeSpec ok;
  EXPECT_TRUE(throws_naming<xpbd::SceneError>(
      [&] { (void)rigid_mesh(ok, Vec3::Zero(), {0, 0, 0, 0}, "."); }, {"orientation", "non-zero"}));
  // A non-unit quaternion is normalised: (2, 0, 0, 2) is 90 degrees about z.
  const RigidMesh m = rigid_mesh(ok, Vec3::Zero(), {2, 0, 0, 2}, ".");
  const RigidMesh n = rigid_mesh(ok, Vec3::Zero(), quat(kPi / 2, Vec3::UnitZ()), ".");
  for (std::size_t i = 0; i < m.vertices.size(); ++i)
    EXPECT_LT((m.vertices[i] - n.vertices[i]).norm(), 8 * kEps);
}

// --------------------------------------------------------------------------
// Files.

// A fresh directory per test, removed afterwards.
class FrameFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("xpbd_frames_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A frame with a 3 x 3 cloth (particles 0-8, 8 triangles), a rope of 3
  // particles (9-11, 2 segments), a loose particle (12), a sphere named
  // "ball" and an unnamed box. Coordinates with many significant digits.
  void make_frame() {
    for (int i = 0; i < 13; ++i)
      x_.emplace_back(Real(i) / 3 + Real(0.1), std::sqrt(Real(2 + i)) - 1, -Real(1) / Real(7 + i));
    for (Index j = 0; j < 2; ++j)
      for (Index i = 0; i < 2; ++i) {
        const Index a = 3 * j + i;
        tris_.push_back({a, a + 1, a + 4});
        tris_.push_back({a, a + 4, a + 3});
      }
    lines_ = {{9, 10}, {10, 11}};
    ShapeSpec sphere;
    sphere.radius = Real(0.3);
    bodies_.push_back(rigid_mesh(sphere, Vec3(Real(0.2), Real(-0.7), Real(1) / 3), quat(1, Vec3::UnitX()), "."));
    bodies_.back().name = "ball";
    ShapeSpec box;
    box.kind = ShapeKind::box;
    bodies_.push_back(rigid_mesh(box, Vec3(0, -2, 0), {1, 0, 0, 0}, "."));
  }

  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(dir_))
      if (e.is_regular_file()) names.push_back(fs::relative(e.path(), dir_).string());
    return names;
  }

  fs::path dir_;
  std::vector<Vec3> x_;
  std::vector<Tri> tris_;
  std::vector<Line> lines_;
  std::vector<RigidMesh> bodies_;
};

TEST(FramePaths, NumberedWithFiveDigitsUnderFrames) {
  EXPECT_EQ(frame_file_path("out", 12, ExportFormat::obj), fs::path("out/frames/frame_00012.obj"));
  EXPECT_EQ(frame_file_path("out", 123456, ExportFormat::vtk), fs::path("out/frames/frame_123456.vtk"));
  EXPECT_THROW((void)frame_file_path("out", -1, ExportFormat::vtk), std::invalid_argument);
}

TEST_F(FrameFiles, ObjReadsBackWithTinyobjloader) {
  make_frame();
  const fs::path file = frame_file_path(dir_, 7, ExportFormat::obj);
  write_frame_obj(file, x_, tris_, lines_, bodies_);
  // Atomic write: the directories were created and no temporary file is left.
  EXPECT_EQ(listing(), std::vector<std::string>{"frames/frame_00007.obj"});

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  ASSERT_TRUE(tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, file.c_str(), nullptr, false))
      << err;
  // Positions: the particles, then each body's vertices.
  std::vector<Vec3> expected = x_;
  for (const RigidMesh& m : bodies_) expected.insert(expected.end(), m.vertices.begin(), m.vertices.end());
  ASSERT_EQ(attrib.vertices.size(), 3 * expected.size());
  // tinyobjloader 2.0.0rc10's own number parser is not correctly rounded: on
  // 30000 random doubles written in shortest round-trip form it was off by up
  // to 4 ulp (none after rounding to float). Hence 8 ulp here; the exact
  // check follows with strtod.
  const Real ulps = sizeof(Real) == sizeof(double) ? 8 : 0;
  for (std::size_t i = 0; i < expected.size(); ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(static_cast<Real>(attrib.vertices[3 * i + k]), expected[i][k],
                  ulps * kEps * std::abs(expected[i][k]))
          << "vertex " << i << " axis " << k;
  // The file holds the shortest decimal that reads back to the same Real, so
  // a correctly rounding parser (glibc's strtod/strtof) gives every value
  // exactly.
  {
    std::ifstream in(file);
    std::string line;
    std::size_t i = 0;
    while (std::getline(in, line)) {
      if (line.rfind("v ", 0) != 0) continue;
      std::istringstream words(line.substr(2));
      std::string c[3];
      words >> c[0] >> c[1] >> c[2];
      ASSERT_LT(i, expected.size());
      for (int k = 0; k < 3; ++k) {
        const Real r = sizeof(Real) == sizeof(double) ? Real(std::strtod(c[k].c_str(), nullptr))
                                                      : Real(std::strtof(c[k].c_str(), nullptr));
        EXPECT_EQ(r, expected[i][k]) << "vertex " << i << " axis " << k << ": '" << c[k] << "'";
      }
      ++i;
    }
    EXPECT_EQ(i, expected.size());
  }

  // Objects: soft, ball, body_1, with their faces (body faces offset by the
  // vertices before them), the rope lines and the loose particle.
  ASSERT_EQ(shapes.size(), 3u);
  EXPECT_EQ(shapes[0].name, "soft");
  EXPECT_EQ(shapes[1].name, "ball");
  EXPECT_EQ(shapes[2].name, "body_1");
  const auto faces_of = [](const tinyobj::shape_t& s) {
    std::vector<Tri> f;
    for (std::size_t k = 0; k < s.mesh.num_face_vertices.size(); ++k) {
      EXPECT_EQ(s.mesh.num_face_vertices[k], 3);
      f.push_back({s.mesh.indices[3 * k].vertex_index, s.mesh.indices[3 * k + 1].vertex_index,
                   s.mesh.indices[3 * k + 2].vertex_index});
    }
    return f;
  };
  EXPECT_EQ(faces_of(shapes[0]), tris_);
  std::vector<Line> lines;
  for (std::size_t k = 0; k < shapes[0].lines.num_line_vertices.size(); ++k) {
    EXPECT_EQ(shapes[0].lines.num_line_vertices[k], 2);
    const auto& ids = shapes[0].lines.indices;
    lines.push_back({ids[2 * k].vertex_index, ids[2 * k + 1].vertex_index});
  }
  EXPECT_EQ(lines, lines_);
  ASSERT_EQ(shapes[0].points.indices.size(), 1u);
  EXPECT_EQ(shapes[0].points.indices[0].vertex_index, 12);
  Index base = Index(x_.size());
  for (std::size_t b = 0; b < 2; ++b) {
    std::vector<Tri> want = bodies_[b].triangles;
    for (Tri& t : want)
      for (Index& i : t) i += base;
    EXPECT_EQ(faces_of(shapes[b + 1]), want) << "body " << b;
    base += Index(bodies_[b].vertices.size());
  }

  // Overwriting an existing frame works the same way.
  x_[0].x() = 42;
  write_frame(ExportFormat::obj, file, x_, tris_, lines_, bodies_);
  ASSERT_TRUE(tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, file.c_str(), nullptr, false));
  EXPECT_EQ(attrib.vertices[0], 42.0);
  EXPECT_EQ(listing().size(), 1u);
}

// The parts of a legacy VTK POLYDATA file this test needs.
struct VtkFile {
  std::string version, title, format, dataset, scalar_type;
  std::vector<Vec3> points;
  std::map<std::string, std::vector<std::vector<long>>> cells;  // VERTICES, LINES, POLYGONS
  std::vector<long> body;                                        // CELL_DATA scalars "body"
};

// Reads the file token by token; each section header gives its counts, and
// the counts must match what follows.
VtkFile read_vtk(const fs::path& file) {
  std::ifstream in(file);
  VtkFile v;
  std::getline(in, v.version);
  std::getline(in, v.title);
  std::getline(in, v.format);
  std::getline(in, v.dataset);
  std::string word;
  while (in >> word) {
    if (word == "POINTS") {
      std::size_t n;
      in >> n >> v.scalar_type;
      for (std::size_t i = 0; i < n; ++i) {
        std::string c[3];
        in >> c[0] >> c[1] >> c[2];
        Vec3 p;
        // glibc's strtod/strtof round correctly.
        for (int k = 0; k < 3; ++k)
          p[k] = sizeof(Real) == sizeof(double) ? Real(std::strtod(c[k].c_str(), nullptr))
                                                : Real(std::strtof(c[k].c_str(), nullptr));
        v.points.push_back(p);
      }
    } else if (word == "VERTICES" || word == "LINES" || word == "POLYGONS") {
      std::size_t n, size, total = 0;
      in >> n >> size;
      auto& cells = v.cells[word];
      for (std::size_t c = 0; c < n; ++c) {
        std::size_t k;
        in >> k;
        std::vector<long> ids(k);
        for (long& id : ids) in >> id;
        cells.push_back(ids);
        total += k + 1;
      }
      EXPECT_EQ(total, size) << word << ": the header's size is the number of integers";
    } else if (word == "CELL_DATA") {
      std::size_t n;
      std::string scalars, name, type, lookup, table;
      in >> n >> scalars >> name >> type;
      std::string ncomp;
      in >> ncomp >> lookup >> table;
      EXPECT_EQ(scalars + " " + name + " " + type + " " + ncomp, "SCALARS body int 1");
      EXPECT_EQ(lookup + " " + table, "LOOKUP_TABLE default");
      v.body.resize(n);
      for (long& b : v.body) in >> b;
    } else {
      ADD_FAILURE() << "unexpected word '" << word << "'";
      break;
    }
  }
  return v;
}

TEST_F(FrameFiles, VtkHeaderCountsAndValues) {
  make_frame();
  const fs::path file = frame_file_path(dir_, 0, ExportFormat::vtk);
  write_frame_vtk(file, x_, tris_, lines_, bodies_);
  EXPECT_EQ(listing(), std::vector<std::string>{"frames/frame_00000.vtk"});
  const VtkFile v = read_vtk(file);
  EXPECT_EQ(v.version, "# vtk DataFile Version 3.0");
  EXPECT_EQ(v.format, "ASCII");
  EXPECT_EQ(v.dataset, "DATASET POLYDATA");
  EXPECT_EQ(v.scalar_type, sizeof(Real) == sizeof(double) ? "double" : "float");

  std::vector<Vec3> expected = x_;
  for (const RigidMesh& m : bodies_) expected.insert(expected.end(), m.vertices.begin(), m.vertices.end());
  ASSERT_EQ(v.points.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(v.points[i], expected[i]) << "point " << i;

  // The loose particle 12 as a vertex cell, the rope, then the triangles of
  // the cloth and of each body (offset by the points before it).
  ASSERT_EQ(v.cells.at("VERTICES"), (std::vector<std::vector<long>>{{12}}));
  ASSERT_EQ(v.cells.at("LINES"), (std::vector<std::vector<long>>{{9, 10}, {10, 11}}));
  std::vector<std::vector<long>> polys;
  std::vector<long> body(1 + lines_.size(), 0);  // cell order: vertices, lines, polygons
  for (const Tri& t : tris_) {
    polys.push_back({t[0], t[1], t[2]});
    body.push_back(0);
  }
  long base = long(x_.size());
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    for (const Tri& t : bodies_[b].triangles) {
      polys.push_back({base + t[0], base + t[1], base + t[2]});
      body.push_back(long(b) + 1);
    }
    base += long(bodies_[b].vertices.size());
  }
  EXPECT_EQ(v.cells.at("POLYGONS"), polys);
  EXPECT_EQ(v.body, body);
}

TEST_F(FrameFiles, BadInputIsNamedAndWritesNothing) {
  make_frame();
  const fs::path file = dir_ / "bad.obj";
  tris_[1][2] = 13;
  EXPECT_TRUE(throws_naming<std::invalid_argument>([&] { write_frame_obj(file, x_, tris_, lines_, bodies_); },
                                                   {"triangles[1]", "index 13", "13 particles"}));
  tris_[1][2] = 4;
  lines_[1][0] = -1;
  EXPECT_TRUE(throws_naming<std::invalid_argument>([&] { write_frame_vtk(file, x_, tris_, lines_, bodies_); },
                                                   {"lines[1]", "index -1"}));
  lines_[1][0] = 10;
  bodies_[1].triangles[3][0] = 8;
  EXPECT_TRUE(throws_naming<std::invalid_argument>([&] { write_frame_obj(file, x_, tris_, lines_, bodies_); },
                                                   {"bodies[1].triangles[3]", "index 8", "8 vertices"}));
  bodies_[1].triangles[3][0] = 0;
  x_[5].y() = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_TRUE(throws_naming<std::invalid_argument>([&] { write_frame_vtk(file, x_, tris_, lines_, bodies_); },
                                                   {"particle 5", "non-finite"}));
  EXPECT_FALSE(fs::exists(dir_));
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd_demos

// OBJ mesh input (xpbd::io, xpbd/io/obj.hpp): round trip of small OBJ files
// written by the test, and the error messages for bad files. Expected
// values are the numbers the test writes into the files.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include <unistd.h>

#include "support/xpbd_test.hpp"
#include "xpbd/io/obj.hpp"

namespace xpbd {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

using test::kEps;
using test::throws_naming;

// A fresh directory per test, removed afterwards.
class ObjFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("xpbd_obj_" + std::to_string(::getpid()) + "_" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }

  std::filesystem::path dir_;
};

// Regular tetrahedron (edge sqrt(8)), faces counter-clockwise seen from
// outside, with the extras a real file has: comments, an object name,
// normals and texture coordinates, v/vt/vn face syntax.
const char* kTetObj = R"(# regular tetrahedron
o tet
v 1 1 1
v 1 -1 -1
v -1 1 -1
v -1 -1 1
vt 0 0
vn 0 0 1
f 1/1/1 2/1/1 3/1/1
f 1//1 3//1 4//1
f 1 4 2
f 2 4 3
)";

TEST_F(ObjFiles, TetrahedronRoundTrip) {
  const std::string path = write("tet.obj", kTetObj);
  const TriangleMesh m = io::load_obj(path);
  ASSERT_EQ(m.positions.size(), 4u);
  // Integers: exact in any parser.
  EXPECT_EQ(m.positions[0], Vec3(1, 1, 1));
  EXPECT_EQ(m.positions[1], Vec3(1, -1, -1));
  EXPECT_EQ(m.positions[2], Vec3(-1, 1, -1));
  EXPECT_EQ(m.positions[3], Vec3(-1, -1, 1));
  const std::vector<Triangle> expect = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
  EXPECT_EQ(m.triangles, expect);

  // As a closed, pressurised surface: 6 edges, 6 hinges, one GlobalVolume
  // whose rest volume is that of the regular tetrahedron, a^3/(6 sqrt 2)
  // = 8/3 m^3 for a = sqrt(8), times scale^3.
  SceneDesc s;
  TriangleMeshDesc d;
  d.kind = MeshKind::closed_surface;
  d.bending = HingeBending::dihedral;
  d.pressure = Real(1.2);
  d.scale = Real(0.5);
  const MeshResult r = io::add_obj_mesh(s, path, d);
  EXPECT_EQ(s.num_particles(), 4);
  EXPECT_EQ(r.edges.size(), 6u);
  EXPECT_EQ(s.dihedral_bends.size(), 6u);
  const Model model = compile(s);
  ASSERT_EQ(model.get<GlobalVolume>().size(), 1u);
  EXPECT_NEAR(model.get<GlobalVolume>()[0].rest_volume, Real(8) / 3 * Real(0.125), 16 * kEps);
  EXPECT_NEAR(model.get<GlobalVolume>()[0].target, Real(1.2) * Real(8) / 3 * Real(0.125), 16 * kEps);
}

TEST_F(ObjFiles, DecimalCoordinatesReadToRoundOff) {
  const std::string path = write("tri.obj", "v 0.1 -2.5e-1 3.75\nv 1.3 0 0\nv 0 0.7 0\nf 1 2 3\n");
  const TriangleMesh m = io::load_obj(path);
  ASSERT_EQ(m.positions.size(), 3u);
  // tinyobjloader parses decimals itself (not strtod), so allow a few ulps.
  EXPECT_NEAR(m.positions[0].x(), Real(0.1), 4 * kEps * Real(0.1));
  EXPECT_NEAR(m.positions[0].y(), Real(-0.25), 4 * kEps * Real(0.25));
  EXPECT_NEAR(m.positions[0].z(), Real(3.75), 4 * kEps * Real(3.75));
  EXPECT_NEAR(m.positions[1].x(), Real(1.3), 4 * kEps * Real(1.3));
}

const char* kQuadObj = R"(v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
f 1 2 3
f 1 3 4
)";

TEST_F(ObjFiles, OpenQuadAsClothAndAsClosedSurface) {
  const std::string path = write("quad.obj", kQuadObj);
  SceneDesc s;
  TriangleMeshDesc d;
  d.bending = HingeBending::dihedral;
  const MeshResult r = io::add_obj_mesh(s, path, d);
  EXPECT_EQ(r.edges.size(), 5u);
  EXPECT_EQ(r.hinges, 1u);
  EXPECT_EQ(s.dihedral_bends.size(), 1u);
  EXPECT_TRUE(s.global_volumes.empty());
  const Model m = compile(s);
  EXPECT_NEAR(m.get<DihedralBending>()[0].rest_angle, 0, 4 * kEps);  // flat

  // Closed surface requested: the first open edge in vertex order is
  // (1, 2) in the file's numbering.
  SceneDesc s2;
  d.kind = MeshKind::closed_surface;
  EXPECT_TRUE(throws_naming<io::ObjError>([&] { io::add_obj_mesh(s2, path, d); },
                              {path, "not closed", "edge (1, 2)"}));
  EXPECT_EQ(s2.num_particles(), 0);
}

TEST_F(ObjFiles, PolygonFaceIsAnErrorUnlessTriangulated) {
  const std::string path =
      write("poly.obj", "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4 2\n");
  // Error names the face by its line and its number among the faces.
  EXPECT_TRUE(throws_naming<io::ObjError>([&] { io::load_obj(path); }, {path, "line 6", "face 2", "4 vertices"}));

  const std::string quad = write("quad4.obj", "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nf 1 2 3 4\n");
  const TriangleMesh m = io::load_obj(quad, io::ObjOptions{true});
  ASSERT_EQ(m.triangles.size(), 2u);
  // The two triangles tile the 2 x 1 rectangle: areas sum to 2 m^2.
  Real area = 0;
  for (const Triangle& t : m.triangles)
    area += Real(0.5) * (m.positions[t[1]] - m.positions[t[0]])
                            .cross(m.positions[t[2]] - m.positions[t[0]])
                            .norm();
  EXPECT_NEAR(area, 2, 8 * kEps);
}

TEST_F(ObjFiles, NegativeIndicesCountFromTheEnd) {
  const std::string path = write("rel.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf -3 -2 -1\n");
  const TriangleMesh m = io::load_obj(path);
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0], (Triangle{1, 2, 3}));
}

TEST_F(ObjFiles, BadFilesNameThePath) {
  const std::string missing = (dir_ / "does_not_exist.obj").string();
  EXPECT_TRUE(throws_naming<io::ObjError>([&] { io::load_obj(missing); }, {missing, "no such file"}));

  const std::string empty = write("nofaces.obj", "# nothing but vertices\nv 0 0 0\nv 1 0 0\n");
  EXPECT_TRUE(throws_naming<io::ObjError>([&] { io::load_obj(empty); }, {empty, "no faces"}));

  const std::string text = write("notes.obj", "this is not an OBJ file\njust words\n");
  EXPECT_TRUE(throws_naming<io::ObjError>([&] { io::load_obj(text); }, {text}));

  // A face using a vertex the file does not have.
  const std::string range = write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  EXPECT_TRUE(throws_naming<io::ObjError>([&] { io::load_obj(range); }, {range, "line 4", "vertex 9", "3 vertices"}));
  const std::string before = write("before.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n");
  EXPECT_TRUE(throws_naming<io::ObjError>([&] { io::load_obj(before); }, {before, "line 4", "-4"}));

  // What tinyobjloader alone would accept silently (a non-number read as 0,
  // a two-vertex face dropped, a fractional index truncated) is an error
  // naming the line.
  const std::string nan = write("nan.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_TRUE(throws_naming<io::ObjError>([&] { io::load_obj(nan); }, {nan, "line 2", "'zero'"}));
  const std::string two = write("two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\n");
  EXPECT_TRUE(throws_naming<io::ObjError>([&] { io::load_obj(two); }, {two, "line 5", "face 2", "2 vertices"}));
  const std::string frac = write("frac.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2.5\n");
  EXPECT_TRUE(throws_naming<io::ObjError>([&] { io::load_obj(frac); }, {frac, "line 4", "'2.5'"}));
  const std::string short_v = write("short.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_TRUE(throws_naming<io::ObjError>([&] { io::load_obj(short_v); }, {short_v, "line 1", "3 coordinates"}));

  // Builder errors come back as ObjError naming the file and the vertex in
  // the file's numbering: vertex 4 is in no face.
  const std::string extra = write("extra.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nf 1 2 3\n");
  SceneDesc s;
  EXPECT_TRUE(throws_naming<io::ObjError>([&] { io::add_obj_mesh(s, extra, TriangleMeshDesc{}); },
                              {extra, "vertex 4", "no triangle"}));
  // ObjError is a SceneError: callers handling bad scenes handle bad files.
  EXPECT_THROW(io::load_obj(missing), SceneError);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd

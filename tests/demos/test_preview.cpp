// preview.png (demos/preview.hpp): a small known scene rendered with gnuplot
// must give a PNG of the requested size with visible content, written
// atomically; a missing or failing gnuplot must give an error naming the
// command and its exit status. Needs gnuplot (scripts/setup.sh installs
// gnuplot-nox): without it these tests fail and say so.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "demos/preview.hpp"

namespace xpbd_demos {
namespace {
namespace XPBD_TEST_FILE_ID {  // one per test file in a unity batch (tests/CMakeLists.txt)

namespace fs = std::filesystem;
using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;

bool gnuplot_installed() { return std::system("gnuplot --version > /dev/null 2>&1") == 0; }

#define REQUIRE_GNUPLOT()                                                                   \
  ASSERT_TRUE(gnuplot_installed())                                                          \
      << "gnuplot is not installed (or not on PATH); the preview needs it: install Debian's " \
         "gnuplot-nox (scripts/setup.sh does)"

struct PngInfo {
  bool signature = false;
  std::uint32_t width = 0, height = 0;
  std::uintmax_t bytes = 0;
};

// The PNG signature and the IHDR chunk, which must come first: length 13,
// "IHDR", then width and height as big-endian 32-bit integers.
PngInfo read_png_header(const fs::path& file) {
  PngInfo info;
  std::ifstream in(file, std::ios::binary);
  unsigned char h[24] = {};
  in.read(reinterpret_cast<char*>(h), sizeof h);
  if (!in) return info;
  const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  info.signature = std::equal(sig, sig + 8, h) && std::string(reinterpret_cast<char*>(h + 12), 4) == "IHDR";
  const auto be32 = [&](int at) {
    return std::uint32_t(h[at]) << 24 | std::uint32_t(h[at + 1]) << 16 | std::uint32_t(h[at + 2]) << 8 |
           std::uint32_t(h[at + 3]);
  };
  info.width = be32(16);
  info.height = be32(20);
  info.bytes = fs::file_size(file);
  return info;
}

// A 16 x 16 cloth of 1 m hanging in the x-y plane from y = 0, bulging in z
// by a time-dependent sine (only a shape to draw), and a sphere below it.
PreviewInput cloth_scene() {
  PreviewInput in;
  in.title = "test_preview: cloth_and_sphere";  // '_' must not become a subscript
  const int n = 16;
  for (Index j = 0; j + 1 < n; ++j)
    for (Index i = 0; i + 1 < n; ++i) {
      const Index a = j * n + i;
      in.triangles.push_back({a, a + 1, a + n + 1});
      in.triangles.push_back({a, a + n + 1, a + n});
    }
  ShapeSpec sphere;
  sphere.radius = Real(0.25);
  for (int f = 0; f < 3; ++f) {
    PreviewFrame fr;
    fr.time = Real(0.5) * Real(f);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Real u = Real(i) / (n - 1), v = Real(j) / (n - 1);
        fr.x.emplace_back(u - Real(0.5), -v, Real(0.2) * Real(f) * std::sin(Real(3) * u) * v);
      }
    fr.bodies.push_back(rigid_mesh(sphere, Vec3(0, Real(-1.3), Real(0.2)), {1, 0, 0, 0}, "."));
    in.frames.push_back(fr);
  }
  return in;
}

class Preview : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("xpbd_preview_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    if (fs::exists(dir_))
      for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    return names;
  }

  fs::path dir_;
};

TEST_F(Preview, ClothAndSphereGiveAPngOfTheRequestedSize) {
  REQUIRE_GNUPLOT();
  PreviewInput in = cloth_scene();
  in.panel_width = 300;
  in.height = 280;
  const fs::path png = dir_ / "preview.png";
  render_preview(png, in);
  // Atomic: the directory was created, holds the picture and nothing else.
  EXPECT_EQ(listing(), std::vector<std::string>{"preview.png"});
  const PngInfo info = read_png_header(png);
  EXPECT_TRUE(info.signature);
  EXPECT_EQ(info.width, 3u * 300u);  // one panel per frame
  EXPECT_EQ(info.height, 280u);

  // Not blank: the same picture without any particle or body (axes and
  // titles only) compresses much better. The shaded cloth and sphere cover a
  // good part of each panel with many colours that deflate cannot squeeze
  // like the white runs they replace, so the file must at least double
  // (measured: 3.3 times). A picture with nothing drawn would stay within a
  // few per cent of the empty one.
  PreviewInput empty = in;
  empty.triangles.clear();
  for (PreviewFrame& fr : empty.frames) {
    fr.x.clear();
    fr.bodies.clear();
  }
  const fs::path blank = dir_ / "blank.png";
  render_preview(blank, empty);
  const PngInfo blank_info = read_png_header(blank);
  EXPECT_TRUE(blank_info.signature);
  EXPECT_GT(double(info.bytes), 2 * double(blank_info.bytes))
      << "cloth picture " << info.bytes << " bytes, empty picture " << blank_info.bytes << " bytes";
}

TEST_F(Preview, RopesLooseParticlesAndPlanesRender) {
  REQUIRE_GNUPLOT();
  PreviewInput in;
  in.title = "rope, points and a ground plane";
  PreviewFrame fr;
  for (int i = 0; i < 5; ++i) fr.x.emplace_back(Real(0.1) * Real(i), Real(1) - Real(0.1) * Real(i), 0);
  fr.x.emplace_back(Real(0.5), Real(0.2), Real(0.1));  // in no line: drawn as a dot
  for (Index i = 0; i < 4; ++i) in.lines.push_back({i, i + 1});
  ShapeSpec plane;
  plane.kind = ShapeKind::plane;  // y = 0, 10 m square: clipped to the view
  fr.bodies.push_back(rigid_mesh(plane, Vec3::Zero(), {1, 0, 0, 0}, "."));
  in.frames.push_back(fr);
  const fs::path png = dir_ / "rope.png";
  render_preview(png, in);
  const PngInfo info = read_png_header(png);
  EXPECT_TRUE(info.signature);
  EXPECT_EQ(info.width, 400u);
  EXPECT_EQ(info.height, 440u);
}

TEST_F(Preview, MissingOrFailingGnuplotNamesTheCommandAndStatus) {
  PreviewInput in = cloth_scene();
  in.gnuplot = "/nonexistent/gnuplot";
  const fs::path png = dir_ / "preview.png";
  try {
    render_preview(png, in);
    ADD_FAILURE() << "no error for a missing gnuplot";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("/nonexistent/gnuplot"), std::string::npos) << msg;
    EXPECT_NE(msg.find("exit status 127"), std::string::npos) << msg;
  }
  // A gnuplot that fails: `false` exits with status 1.
  in.gnuplot = "false";
  try {
    render_preview(png, in);
    ADD_FAILURE() << "no error for a failing gnuplot";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("false"), std::string::npos) << msg;
    EXPECT_NE(msg.find("exit status 1"), std::string::npos) << msg;
  }
  // Nothing is left behind: no picture, no temporary file.
  EXPECT_EQ(listing(), std::vector<std::string>{});
}

// gnuplot exits with status 0 after a failed write. A full disk, made here
// for the picture alone: its temporary file (next to the target, named with
// this process's id) is a link to /dev/full, where every write fails with
// ENOSPC. The picture must not be listed as written: render_preview throws,
// naming preview.png, and leaves no preview.png.
TEST_F(Preview, PictureOnAFullDiskIsAnErrorNamingTheFile) {
  REQUIRE_GNUPLOT();
  ASSERT_TRUE(fs::exists("/dev/full"));
  fs::create_directories(dir_);
  const fs::path png = dir_ / "preview.png";
  fs::create_symlink("/dev/full", dir_ / (".preview.png.tmp." + std::to_string(::getpid())));
  try {
    render_preview(png, cloth_scene());
    ADD_FAILURE() << "no error for a picture written to a full disk";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(png.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("not written"), std::string::npos) << msg;
  }
  EXPECT_FALSE(fs::exists(png));
}

// png_complete on a real picture, and on the same bytes cut short (the end
// chunk lost) or with a foreign first byte.
TEST_F(Preview, TruncatedPngIsRecognised) {
  REQUIRE_GNUPLOT();
  const fs::path png = dir_ / "preview.png";
  render_preview(png, cloth_scene());
  std::string why;
  ASSERT_TRUE(png_complete(png, &why)) << why;
  std::ifstream in(png, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto write = [&](const fs::path& p, const std::string& b) {
    std::ofstream out(p, std::ios::binary);
    out << b;
  };
  const fs::path cut = dir_ / "cut.png", other = dir_ / "other.png";
  write(cut, bytes.substr(0, bytes.size() / 2));
  EXPECT_FALSE(png_complete(cut, &why));
  EXPECT_NE(why.find("IEND"), std::string::npos) << why;
  write(cut, bytes.substr(0, bytes.size() - 1));
  EXPECT_FALSE(png_complete(cut));
  std::string foreign = bytes;
  foreign[0] = 'G';
  write(other, foreign);
  EXPECT_FALSE(png_complete(other, &why));
  EXPECT_NE(why.find("signature"), std::string::npos) << why;
  EXPECT_FALSE(png_complete(dir_ / "missing.png", &why));
  EXPECT_FALSE(png_complete(dir_, &why));  // a directory
}

TEST(PreviewInputCheck, BadInputIsNamed) {
  PreviewInput in;
  EXPECT_THROW(render_preview("unused.png", in), std::invalid_argument);  // no frames
  in = cloth_scene();
  in.triangles[7][1] = 256;
  try {
    render_preview("unused.png", in);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("triangles[7]"), std::string::npos) << e.what();
  }
  in = cloth_scene();
  in.frames[1].x[3].x() = std::numeric_limits<Real>::infinity();
  try {
    render_preview("unused.png", in);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("frames[1]: particle 3"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists("unused.png"));
}

TEST(PreviewFrameNumbers, SpreadEvenlyWithFirstAndLast) {
  // k (frames - 1) / (panels - 1) rounded: 179 / 3 = 59.67 -> 60, 119.33 -> 119.
  EXPECT_EQ(preview_frame_numbers(180, 4), (std::vector<int>{0, 60, 119, 179}));
  EXPECT_EQ(preview_frame_numbers(7, 4), (std::vector<int>{0, 2, 4, 6}));
  EXPECT_EQ(preview_frame_numbers(3, 4), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(preview_frame_numbers(10, 1), (std::vector<int>{9}));
  EXPECT_THROW((void)preview_frame_numbers(0, 4), std::invalid_argument);
  EXPECT_THROW((void)preview_frame_numbers(10, 0), std::invalid_argument);
}

}  // namespace XPBD_TEST_FILE_ID
}  // namespace
}  // namespace xpbd_demos

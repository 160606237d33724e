#include "demos/preview.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <system_error>

#include "demos/output.hpp"

namespace xpbd_demos {

namespace fs = std::filesystem;
using xpbd::Index;
using xpbd::Real;
using xpbd::Vec3;

namespace {

// Colours (red, green, blue in [0, 1]): soft body orange, rigid bodies steel
// blue, planes grey; ropes and loose particles dark red.
constexpr std::array<double, 3> kSoftColour{0.88, 0.54, 0.24};
constexpr std::array<double, 3> kRigidColour{0.44, 0.56, 0.75};
constexpr std::array<double, 3> kPlaneColour{0.78, 0.78, 0.76};
constexpr const char* kLineColour = "#8b1a1a";
// Above this many triangles per panel the polygon edges are left out: on a
// dense mesh they would hide the shading.
constexpr std::size_t kMaxTrianglesWithEdges = 4000;

// Flat shading, done here rather than by gnuplot (whose pm3d light is fixed
// relative to the viewer and lights the scene from below at this view): a
// polygon with unit normal n gets brightness kAmbient + (1 - kAmbient) |n.l|
// (both sides lit alike: cloth has no inside) for a light from the upper
// front left, in the scene's frame (y up, the viewer on the +z side).
// gnuplot 5.4 cannot colour polygons one by one ("fillcolor rgb variable"
// is ignored by `with polygons`), so the brightness is rounded to kShades
// levels and each level is drawn as its own plot clause of one colour.
constexpr double kAmbient = 0.35;
constexpr int kShades = 12;
const Vec3 kLight = Vec3(Real(-0.4), Real(1), Real(0.5)).normalized();

std::string shade(const std::array<double, 3>& rgb, int level) {
  const double b = kAmbient + (1 - kAmbient) * double(level) / double(kShades - 1);
  char hex[16];
  std::snprintf(hex, sizeof hex, "#%02x%02x%02x", int(rgb[0] * b * 255 + 0.5), int(rgb[1] * b * 255 + 0.5),
                int(rgb[2] * b * 255 + 0.5));
  return hex;
}

// Removes a temporary directory and everything in it when it goes out of scope.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "xpbd-preview-XXXXXX").string();
    if (::mkdtemp(tmpl.data()) == nullptr)
      throw std::runtime_error("render_preview: cannot create a temporary directory '" + tmpl + "'");
    path = fs::absolute(tmpl);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

// A string literal for a gnuplot script: in single quotes nothing is
// special except the quote itself, which is doubled.
std::string gp_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') q += '\'';
    // Control characters (a newline would end the command) become spaces.
    q += static_cast<unsigned char>(c) < ' ' ? ' ' : c;
  }
  return q + "'";
}

// A word for sh: in single quotes, a quote is written as '\''.
std::string sh_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'')
      q += "'\\''";
    else
      q += c;
  }
  return q + "'";
}

void append_number(std::string& s, double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}

// One vertex of a data file in gnuplot's axes: gnuplot draws its z axis
// upwards, so the scene's (x, y, z) is written as (z, x, y), a cyclic
// permutation that keeps the picture right-handed (z x x = y). (Writing
// (x, -z, y), or (x, z, y) with a reversed y range, would keep x as gnuplot's
// x, but gnuplot 5.4's `set view equal xyz` turns the picture upside down
// with a reversed range.)
void append_vertex(std::string& s, const Vec3& p) {
  append_number(s, double(p.z()));
  s += ' ';
  append_number(s, double(p.x()));
  s += ' ';
  append_number(s, double(p.y()));
  s += '\n';
}

void write_file(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
  out.flush();
  if (!out) throw std::runtime_error("render_preview: cannot write '" + file.string() + "'");
}

// Sutherland-Hodgman: the part of a convex polygon inside the axis-aligned
// box [lo, hi] (each clipping step keeps the polygon convex).
std::vector<Vec3> clip_to_box(std::vector<Vec3> poly, const Vec3& lo, const Vec3& hi) {
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      if (poly.empty()) return poly;
      const Real bound = side ? hi[axis] : lo[axis];
      // Signed distance to the clip plane, >= 0 inside.
      const auto inside = [&](const Vec3& p) { return side ? bound - p[axis] : p[axis] - bound; };
      std::vector<Vec3> out;
      for (std::size_t i = 0; i < poly.size(); ++i) {
        const Vec3& a = poly[i];
        const Vec3& b = poly[(i + 1) % poly.size()];
        const Real da = inside(a), db = inside(b);
        if (da >= 0) out.push_back(a);
        if ((da >= 0) != (db >= 0)) {
          Vec3 p = a + (b - a) * (da / (da - db));
          p[axis] = bound;  // exactly on the plane despite rounding
          out.push_back(p);
        }
      }
      poly = std::move(out);
    }
  }
  return poly;
}

void check_input(const PreviewInput& in) {
  if (in.frames.empty()) throw std::invalid_argument("render_preview: no frames to show");
  if (in.frames.size() > 8)
    throw std::invalid_argument("render_preview: at most 8 frames, got " + std::to_string(in.frames.size()));
  if (in.panel_width < 100)
    throw std::invalid_argument("render_preview: panel_width must be >= 100, got " +
                                std::to_string(in.panel_width));
  if (in.height < 100)
    throw std::invalid_argument("render_preview: height must be >= 100, got " + std::to_string(in.height));
  for (std::size_t f = 0; f < in.frames.size(); ++f) {
    const PreviewFrame& fr = in.frames[f];
    const std::string where = "render_preview: frames[" + std::to_string(f) + "]";
    const std::size_t n = fr.x.size();
    if (n != in.frames.front().x.size())
      throw std::invalid_argument(where + ": " + std::to_string(n) + " particles, frames[0] has " +
                                  std::to_string(in.frames.front().x.size()));
    for (std::size_t i = 0; i < n; ++i)
      if (!fr.x[i].allFinite())
        throw std::invalid_argument(where + ": particle " + std::to_string(i) + " has a non-finite position");
    const auto check = [&](const std::string& element, Index i, std::size_t count) {
      if (i < 0 || static_cast<std::size_t>(i) >= count)
        throw std::invalid_argument(where + ": " + element + ": index " + std::to_string(i) +
                                    " out of range (" + std::to_string(count) + ")");
    };
    for (std::size_t t = 0; t < in.triangles.size(); ++t)
      for (Index i : in.triangles[t]) check("triangles[" + std::to_string(t) + "]", i, n);
    for (std::size_t l = 0; l < in.lines.size(); ++l)
      for (Index i : in.lines[l]) check("lines[" + std::to_string(l) + "]", i, n);
    for (std::size_t b = 0; b < fr.bodies.size(); ++b) {
      const RigidMesh& m = fr.bodies[b];
      for (const Vec3& v : m.vertices)
        if (!v.allFinite())
          throw std::invalid_argument(where + ": bodies[" + std::to_string(b) + "] has a non-finite vertex");
      for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (Index i : m.triangles[t])
          check("bodies[" + std::to_string(b) + "].triangles[" + std::to_string(t) + "]", i, m.vertices.size());
    }
  }
}

// Runs `command` through sh; throws naming it and its exit status on failure.
void run(const std::string& command, const fs::path& stderr_file) {
  const int status = std::system(command.c_str());
  if (status == 0) return;
  std::string why;
  if (status == -1) {
    why = "could not start a shell";
  } else if (WIFEXITED(status)) {
    why = "exit status " + std::to_string(WEXITSTATUS(status));
    if (WEXITSTATUS(status) == 127) why += " (command not found: install gnuplot, e.g. Debian's gnuplot-nox)";
  } else if (WIFSIGNALED(status)) {
    why = "killed by signal " + std::to_string(WTERMSIG(status));
  } else {
    why = "wait status " + std::to_string(status);
  }
  // gnuplot's first few error lines say what went wrong.
  std::ifstream err(stderr_file);
  std::string line, text;
  for (int k = 0; k < 6 && std::getline(err, line); ++k) text += "\n  " + line;
  throw std::runtime_error("render_preview: '" + command + "' failed: " + why + text);
}

}  // namespace

std::vector<int> preview_frame_numbers(int frames, int panels) {
  if (frames < 1)
    throw std::invalid_argument("preview_frame_numbers: frames must be >= 1, got " + std::to_string(frames));
  if (panels < 1)
    throw std::invalid_argument("preview_frame_numbers: panels must be >= 1, got " + std::to_string(panels));
  std::vector<int> out;
  if (panels == 1) return {frames - 1};
  if (frames <= panels) {
    for (int f = 0; f < frames; ++f) out.push_back(f);
    return out;
  }
  // round(k (frames - 1) / (panels - 1)) in integers (half rounds up).
  const long long last = frames - 1, div = panels - 1;
  for (long long k = 0; k < panels; ++k) out.push_back(int((2 * k * last + div) / (2 * div)));
  return out;
}

bool png_complete(const fs::path& file, std::string* why) {
  auto no = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return no("is not a regular file");
  const std::string bytes = read_file(file);
  static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  // The IEND chunk: length 0, type, CRC-32 of the type.
  static constexpr unsigned char kEnd[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
  if (bytes.size() < sizeof kSignature + sizeof kEnd)
    return no("has " + std::to_string(bytes.size()) + " bytes, too few for a PNG");
  if (!std::equal(kSignature, kSignature + 8, bytes.begin(), [](unsigned char a, char b) { return a == static_cast<unsigned char>(b); }))
    return no("does not start with the PNG signature");
  if (!std::equal(kEnd, kEnd + 12, bytes.end() - 12, [](unsigned char a, char b) { return a == static_cast<unsigned char>(b); }))
    return no("does not end with the PNG end chunk (IEND): truncated");
  return true;
}

void render_preview(const fs::path& png, const PreviewInput& in) {
  check_input(in);

  // The region shown: the bounding box of every particle and every bounded
  // rigid body over all frames, made a cube (equal scales) with a 10 % margin.
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::max());
  Vec3 hi = -lo;
  bool any = false;
  for (const PreviewFrame& fr : in.frames) {
    for (const Vec3& p : fr.x) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      any = true;
    }
    for (const RigidMesh& m : fr.bodies)
      if (!m.unbounded)
        for (const Vec3& p : m.vertices) {
          lo = lo.cwiseMin(p);
          hi = hi.cwiseMax(p);
          any = true;
        }
  }
  const Vec3 centre = any ? Vec3((lo + hi) / 2) : Vec3::Zero();
  // m; at least 1 cm so that a single point still gets a view.
  const Real half = any ? std::max(Real(0.55) * (hi - lo).maxCoeff(), Real(0.01)) : Real(1);
  const Vec3 box_lo = centre - Vec3::Constant(half), box_hi = centre + Vec3::Constant(half);
  // Clip a hair inside the axis ranges: gnuplot drops a polygon with any
  // vertex out of range.
  const Vec3 clip_lo = centre - Vec3::Constant(half * Real(0.999)),
             clip_hi = centre + Vec3::Constant(half * Real(0.999));

  // Particles in no triangle and no line are drawn as dots.
  std::vector<char> loose(in.frames.front().x.size(), 1);
  for (const auto& t : in.triangles)
    for (Index i : t) loose[static_cast<std::size_t>(i)] = 0;
  for (const auto& l : in.lines)
    for (Index i : l) loose[static_cast<std::size_t>(i)] = 0;

  TempDir tmp;
  std::size_t max_triangles = 0;
  std::vector<std::string> plots;  // the splot command of each panel
  for (std::size_t f = 0; f < in.frames.size(); ++f) {
    const PreviewFrame& fr = in.frames[f];
    const std::string stem = "frame" + std::to_string(f);
    std::vector<std::string> clauses;
    const auto add = [&](const std::string& suffix, const std::string& data, const std::string& style) {
      if (data.empty()) return;
      // Relative to the temporary directory: the script starts with a cd.
      const std::string name = stem + suffix + ".dat";
      write_file(tmp.path / name, data);
      clauses.push_back(gp_quote(name) + " " + style);
    };
    // Polygons: one vertex per line, a blank line after each polygon, in
    // one buffer per colour (0 soft, 1 rigid, 2 plane) and shade.
    std::array<std::array<std::string, kShades>, 3> polys;
    const auto add_polygon = [&](int colour, const std::vector<Vec3>& poly) {
      // Newell's normal: exact for a planar polygon of any vertex count.
      Vec3 n = Vec3::Zero();
      for (std::size_t k = 0; k < poly.size(); ++k) n += poly[k].cross(poly[(k + 1) % poly.size()]);
      const Real len = n.norm();
      const Real c = len > 0 ? std::abs(n.dot(kLight)) / len : Real(1);
      std::string& data = polys[static_cast<std::size_t>(colour)][static_cast<std::size_t>(
          std::lround(double(c) * (kShades - 1)))];
      for (const Vec3& p : poly) append_vertex(data, p);
      data += '\n';
    };
    std::size_t triangles = in.triangles.size();
    for (const auto& t : in.triangles)
      add_polygon(0, {fr.x[static_cast<std::size_t>(t[0])], fr.x[static_cast<std::size_t>(t[1])],
                      fr.x[static_cast<std::size_t>(t[2])]});
    for (const RigidMesh& m : fr.bodies) {
      triangles += m.triangles.size();
      for (const auto& t : m.triangles) {
        const std::vector<Vec3> poly = clip_to_box(
            {m.vertices[static_cast<std::size_t>(t[0])], m.vertices[static_cast<std::size_t>(t[1])],
             m.vertices[static_cast<std::size_t>(t[2])]},
            clip_lo, clip_hi);
        if (poly.size() >= 3) add_polygon(m.unbounded ? 2 : 1, poly);
      }
    }
    std::string lines, dots;
    for (const auto& l : in.lines) {
      append_vertex(lines, fr.x[static_cast<std::size_t>(l[0])]);
      append_vertex(lines, fr.x[static_cast<std::size_t>(l[1])]);
      lines += '\n';
    }
    for (std::size_t i = 0; i < fr.x.size(); ++i)
      if (loose[i]) append_vertex(dots, fr.x[i]);
    max_triangles = std::max(max_triangles, triangles);
    const std::array<std::array<double, 3>, 3> colours{kSoftColour, kRigidColour, kPlaneColour};
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < kShades; ++k)
        add("_poly" + std::to_string(c) + "_" + std::to_string(k),
            polys[static_cast<std::size_t>(c)][static_cast<std::size_t>(k)],
            "with polygons fs solid 1.0 fillcolor rgb '" + shade(colours[static_cast<std::size_t>(c)], k) + "'");
    add("_lines", lines, std::string("with lines lw 2 lc rgb '") + kLineColour + "'");
    add("_dots", dots, std::string("with points pt 7 ps 0.4 lc rgb '") + kLineColour + "'");
    if (clauses.empty()) {
      // Nothing to draw: an invisible point keeps splot from failing.
      std::string centre_point;
      append_vertex(centre_point, centre);
      add("_empty", centre_point, "with dots lc rgb '#ffffff'");
    }
    char title[64];
    std::snprintf(title, sizeof title, "t = %.2f s", double(fr.time));
    std::string plot = "set title " + gp_quote(title) + "\nsplot ";
    for (std::size_t c = 0; c < clauses.size(); ++c) plot += (c ? ", " : "") + clauses[c];
    plots.push_back(plot + "\n");
  }

  // gnuplot writes next to the target, which is then renamed over it.
  const fs::path dir = png.has_parent_path() ? png.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    throw std::runtime_error("render_preview: cannot create directory '" + dir.string() + "': " + ec.message());
  std::string tmp_name = ".";
  tmp_name += png.filename().string();
  tmp_name += ".tmp.";
  tmp_name += std::to_string(::getpid());
  // Absolute: the script runs in the temporary directory.
  const fs::path tmp_png = fs::absolute(dir / tmp_name);

  std::string s;
  const int width = in.panel_width * int(in.frames.size());
  s += "cd " + gp_quote(tmp.path.string()) + "\n";
  s += "set terminal pngcairo noenhanced size " + std::to_string(width) + "," + std::to_string(in.height) +
       " font 'Sans,10'\n";
  s += "set output " + gp_quote(tmp_png.string()) + "\n";
  s += "set multiplot layout 1," + std::to_string(in.frames.size()) + " title " + gp_quote(in.title) +
       " font 'Sans,13'\n";
  // View: 65 degrees down from the vertical, turned so that the scene's x
  // runs left to right and its z towards the viewer (front view from above).
  s += "unset key\nset view 65, 120, 1.2\nset view equal xyz\n";
  const auto range = [&](const char* axis, Real a, Real b) {
    s += std::string("set ") + axis + "range [";
    append_number(s, double(a));
    s += ':';
    append_number(s, double(b));
    s += "]\n";
  };
  range("x", box_lo.z(), box_hi.z());  // gnuplot's x, y, z = the scene's z, x, y
  range("y", box_lo.x(), box_hi.x());
  range("z", box_lo.y(), box_hi.y());
  s += "set xyplane relative 0\n";
  s += "set xlabel 'z (m)'\nset ylabel 'x (m)'\nset zlabel 'y (m)' rotate parallel\n";
  s += "set tics font ',8'\n";
  s += max_triangles <= kMaxTrianglesWithEdges ? "set pm3d depthorder border lc rgb '#A0301000' lw 0.5\n"
                                               : "set pm3d depthorder noborder\n";
  for (const std::string& p : plots) s += p;
  s += "unset multiplot\nset output\n";
  const fs::path script = tmp.path / "preview.gp";
  write_file(script, s);

  const fs::path err = tmp.path / "gnuplot.err";
  const std::string command = in.gnuplot + " " + sh_quote(script.string());
  try {
    run(command + " 2> " + sh_quote(err.string()), err);
    std::string why;
    if (!png_complete(tmp_png, &why))
      throw std::runtime_error("render_preview: '" + png.string() + "' was not written: '" + command +
                               "' exited with status 0, but its picture '" + tmp_png.string() + "' " + why);
    fs::rename(tmp_png, png, ec);
    if (ec)
      throw std::runtime_error("render_preview: cannot rename '" + tmp_png.string() + "' to '" + png.string() +
                               "': " + ec.message());
  } catch (...) {
    std::error_code ignore;
    fs::remove(tmp_png, ignore);
    throw;
  }
}

}  // namespace xpbd_demos

#include "demos/compare/compare.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "demos/builtin_scenes.hpp"
#include "demos/scene_file.hpp"

namespace xpbd_compare {

using xpbd_demos::SceneSpec;

std::vector<Budget> sweep_budgets(bool quick) {
  if (quick) return {{1, 1}, {5, 1}, {1, 5}};
  std::vector<Budget> b;
  for (int s : {1, 2, 5, 10, 20, 50, 100}) b.push_back({s, 1});
  for (int i : {2, 5, 10, 20, 50, 100}) b.push_back({1, i});
  for (Budget m : {Budget{2, 5}, Budget{5, 2}, Budget{5, 5}, Budget{10, 2}, Budget{10, 5}, Budget{20, 5}})
    b.push_back(m);
  return b;
}

// ---------------------------------------------------------------------------
// The chain.

SceneSpec chain_scene(const ChainParams& p, int frames) {
  SceneSpec s;
  s.name = "hanging_chain";
  s.description = "vertical chain of 20 particles of 1 kg, 1 cm links, pinned at the top (support force 190 N)";
  xpbd::RopeDesc r;
  r.n = p.n;
  r.start = p.top;
  r.dir = -Vec3::UnitY();
  r.spacing = p.spacing;
  r.mass = p.mass;
  r.pin_first = true;
  r.mat.compliance = p.compliance;
  s.soft.generators.push_back(r);
  s.solver.gravity = Vec3(0, -p.g, 0);
  s.solver.drag = p.drag;
  s.solver.frames = frames;
  return s;
}

std::vector<Vec3> chain_equilibrium(const ChainParams& p) {
  std::vector<Vec3> x(static_cast<std::size_t>(p.n));
  x[0] = p.top;
  for (int k = 0; k + 1 < p.n; ++k) {
    // Link k carries the n-1-k particles below it.
    const double tension = double(p.n - 1 - k) * double(p.mass) * double(p.g);
    const double len = double(p.spacing) + double(p.compliance) * tension;
    x[k + 1] = x[k] - Vec3::UnitY() * Real(len);
  }
  return x;
}

double chain_support_force(const ChainParams& p) { return double(p.n - 1) * double(p.mass) * double(p.g); }

double support_force_from_positions(std::span<const Vec3> x, const ChainParams& p) {
  if (x.size() < 2) throw std::invalid_argument("support_force_from_positions: need >= 2 particles");
  const double len = (x[1] - x[0]).template cast<double>().norm();
  return (len - double(p.spacing)) / double(p.compliance);
}

// ---------------------------------------------------------------------------
// Scenes.

std::vector<CompareScene> compare_scenes(bool quick) {
  const int frames = quick ? 30 : 120;  // 2 s at 60 Hz (quick: 0.5 s)
  std::vector<CompareScene> v;
  auto builtin = [&](const char* name) {
    const SceneSpec* s = xpbd_demos::find_builtin_scene(name);
    if (!s) throw std::logic_error(std::string("compare_scenes: no built-in scene ") + name);
    SceneSpec c = *s;
    c.solver.frames = frames;
    return c;
  };
  // A scene with a run reference; `dynamic`: it has a dynamic rigid body,
  // `rigid`: Bullet is stepped at every substep (CompareScene).
  auto scene = [](std::string id, SceneSpec spec, bool dynamic = false, bool rigid = false) {
    CompareScene c;
    c.id = std::move(id);
    c.spec = std::move(spec);
    c.dynamic_bodies = dynamic;
    c.rigid_substeps = rigid;
    return c;
  };
  v.push_back(scene("hanging_cloth_32", builtin("hanging_cloth")));
  {
    SceneSpec c = xpbd_demos::apply_sets(builtin("hanging_cloth"),
                                         {"soft.generators.0.cloth.nx=64", "soft.generators.0.cloth.ny=64",
                                          "soft.generators.0.cloth.pinned=[[0,0],[63,0]]"},
                                         "compare");
    c.name = "hanging_cloth_64";
    v.push_back(scene("hanging_cloth_64", c));
  }
  // Scenes with a dynamic body: cloth_on_sphere's light box lies on the
  // ground (a Bullet contact) under the cloth, so Bullet is stepped at every
  // substep; the trampoline's ball touches only the cloth.
  v.push_back(scene("cloth_on_sphere", builtin("cloth_on_sphere"), true, true));
  {
    ChainParams p;
    CompareScene c = scene("hanging_chain", chain_scene(p, frames));
    c.chain = p;
    v.push_back(c);
  }
  {
    // The chain between two supports (catenary.hpp): released 0.5 rad out
    // of its vertical plane, it swings and settles (drag) to the discrete
    // elastic catenary.
    CatenaryParams p;
    p.start_angle = Real(0.5);
    CompareScene c = scene("catenary", catenary_scene(p, frames));
    c.catenary = p;
    v.push_back(c);
  }
  {
    // The same physics in every solver: the built-in trampoline's membrane
    // has constraint damping (10 N s/m on stretch and shear), which PBD and
    // btSoftBody cannot express; here it is 0. Its compliance stays (1e-5
    // m/N: the ball sinks because the membrane stretches); btSoftBody's kLST
    // is calibrated to the reference's strain at the deepest dip
    // (ReferenceData::calibration_frame).
    SceneSpec t = builtin("trampoline");
    for (auto& g : t.soft.generators)
      if (auto* c = std::get_if<xpbd::ClothGridDesc>(&g)) c->stretch.damping = c->shear_mat.damping = c->bend_mat.damping = 0;
    t.description += "; constraint damping 0";
    v.push_back(scene("trampoline", t, true));
  }
  {
    // A 0.2 m soft cube of tetrahedra (4x4x4 cells, 1 kg, bulk modulus
    // 1 MPa, edges 1e-6 m/N) dropped from 5 cm onto a ground plane.
    SceneSpec s;
    s.name = "soft_cube";
    s.description = "0.2 m tetrahedral soft cube dropped from 5 cm onto a ground plane";
    xpbd::TetBoxDesc c;
    c.nx = c.ny = c.nz = 4;
    c.size = Vec3::Constant(Real(0.2));
    c.origin = Vec3(Real(-0.1), Real(0.05), Real(-0.1));
    c.mass = 1;
    c.bulk_modulus = Real(1e6);
    c.edge_mat.compliance = Real(1e-6);
    s.soft.generators.push_back(c);
    xpbd_demos::RigidSpec g;
    g.name = "ground";
    g.shape.kind = xpbd_demos::ShapeKind::plane;
    g.shape.normal = Vec3::UnitY();
    s.bodies.push_back(g);
    s.solver.frames = frames;
    v.push_back(scene("soft_cube", s));
  }
  return v;
}

bool static_reference(const std::string& scene) { return scene == "hanging_chain" || scene == "catenary"; }

// ---------------------------------------------------------------------------

PositionError position_error(std::span<const Vec3> a, std::span<const Vec3> b) {
  if (a.size() != b.size())
    throw std::invalid_argument("position_error: " + std::to_string(a.size()) + " vs " +
                                std::to_string(b.size()) + " particles");
  PositionError e;
  if (a.empty()) return e;
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double d = (a[i].template cast<double>() - b[i].template cast<double>()).norm();
    if (!std::isfinite(d)) return {std::nan(""), std::nan("")};
    sum += d * d;
    e.max = std::max(e.max, d);
  }
  e.rms = std::sqrt(sum / double(a.size()));
  return e;
}

std::vector<int> sample_frames(int frames, int every) {
  std::vector<int> f;
  for (int k = every; k < frames; k += every) f.push_back(k);
  f.push_back(frames);
  return f;
}

// ---------------------------------------------------------------------------
// CSV.

namespace {

const char* kColumns[] = {"scene", "method", "scalar", "substeps", "iterations", "frames",
                          "frames_completed", "status", "particles", "projections_per_frame",
                          "wall_ms_median", "wall_ms_mean", "err_rms_final", "err_max_final",
                          "err_rms_worst", "err_max_worst", "err_body_worst", "err_mean", "err_worst",
                          "err_series", "max_strain",
                          "mean_strain", "max_penetration", "energy_drift", "support_force", "note"};
constexpr std::size_t kNumColumns = sizeof(kColumns) / sizeof(kColumns[0]);

std::string num(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream o;
  o.precision(9);
  o << v;
  return o.str();
}

}  // namespace

std::string quote(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += c == '\n' ? ' ' : c;
  }
  return q + "\"";
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool in_q = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (in_q) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cur += '"';
        ++i;
      } else if (c == '"') {
        in_q = false;
      } else {
        cur += c;
      }
    } else if (c == '"') {
      in_q = true;
    } else if (c == ',') {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

namespace {

double to_d(const std::string& s, const std::string& where) {
  if (s == "nan" || s.empty()) return std::nan("");
  if (s == "inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  std::size_t pos = 0;
  double v = 0;
  try {
    v = std::stod(s, &pos);
  } catch (const std::exception&) {
    pos = 0;
  }
  if (pos != s.size()) throw std::runtime_error(where + ": not a number: \"" + s + "\"");
  return v;
}

long long to_ll(const std::string& s, const std::string& where) {
  std::size_t pos = 0;
  long long v = 0;
  try {
    v = std::stoll(s, &pos);
  } catch (const std::exception&) {
    pos = 0;
  }
  if (pos != s.size() || s.empty()) throw std::runtime_error(where + ": not an integer: \"" + s + "\"");
  return v;
}

}  // namespace

std::string Row::key() const {
  return scene + "/" + method + "/" + std::to_string(substeps) + "x" + std::to_string(iterations);
}

const char* csv_header() {
  static const std::string h = [] {
    std::string s;
    for (std::size_t i = 0; i < kNumColumns; ++i) s += (i ? "," : "") + std::string(kColumns[i]);
    return s;
  }();
  return h.c_str();
}

std::string to_csv(const Row& r) {
  std::ostringstream o;
  o << quote(r.scene) << ',' << quote(r.method) << ',' << quote(r.scalar) << ',' << r.substeps << ','
    << r.iterations << ',' << r.frames << ',' << r.frames_completed << ',' << quote(r.status) << ','
    << r.particles << ',' << r.projections_per_frame << ',' << num(r.wall_ms_median) << ','
    << num(r.wall_ms_mean) << ',' << num(r.err_rms_final) << ',' << num(r.err_max_final) << ','
    << num(r.err_rms_worst) << ',' << num(r.err_max_worst) << ',' << num(r.err_body_worst) << ','
    << num(r.err_mean) << ',' << num(r.err_worst) << ',' << quote(r.err_series) << ','
    << num(r.max_strain) << ',' << num(r.mean_strain) << ',' << num(r.max_penetration) << ','
    << num(r.energy_drift) << ',' << num(r.support_force) << ',' << quote(r.note);
  return o.str();
}

std::vector<Row> read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::vector<Row> rows;
  std::string line;
  int ln = 0;
  while (std::getline(in, line)) {
    ++ln;
    if (line.empty()) continue;
    const std::string where = path + ":" + std::to_string(ln);
    if (ln == 1) {
      if (line != csv_header()) throw std::runtime_error(where + ": header is not the xpbd-compare header");
      continue;
    }
    const auto f = split_csv(line);
    if (f.size() != kNumColumns)
      throw std::runtime_error(where + ": " + std::to_string(f.size()) + " fields, expected " +
                               std::to_string(kNumColumns) + " (a truncated last line? delete it)");
    Row r;
    std::size_t i = 0;
    r.scene = f[i++];
    r.method = f[i++];
    r.scalar = f[i++];
    r.substeps = int(to_ll(f[i++], where + " substeps"));
    r.iterations = int(to_ll(f[i++], where + " iterations"));
    r.frames = int(to_ll(f[i++], where + " frames"));
    r.frames_completed = int(to_ll(f[i++], where + " frames_completed"));
    r.status = f[i++];
    r.particles = int(to_ll(f[i++], where + " particles"));
    r.projections_per_frame = to_ll(f[i++], where + " projections_per_frame");
    r.wall_ms_median = to_d(f[i++], where + " wall_ms_median");
    r.wall_ms_mean = to_d(f[i++], where + " wall_ms_mean");
    r.err_rms_final = to_d(f[i++], where + " err_rms_final");
    r.err_max_final = to_d(f[i++], where + " err_max_final");
    r.err_rms_worst = to_d(f[i++], where + " err_rms_worst");
    r.err_max_worst = to_d(f[i++], where + " err_max_worst");
    r.err_body_worst = to_d(f[i++], where + " err_body_worst");
    r.err_mean = to_d(f[i++], where + " err_mean");
    r.err_worst = to_d(f[i++], where + " err_worst");
    r.err_series = f[i++];
    r.max_strain = to_d(f[i++], where + " max_strain");
    r.mean_strain = to_d(f[i++], where + " mean_strain");
    r.max_penetration = to_d(f[i++], where + " max_penetration");
    r.energy_drift = to_d(f[i++], where + " energy_drift");
    r.support_force = to_d(f[i++], where + " support_force");
    r.note = f[i++];
    rows.push_back(r);
  }
  return rows;
}

// ---------------------------------------------------------------------------
// Reference files.

bool have_reference(const std::string& dir, const std::string& scene) {
  return !dir.empty() && std::filesystem::exists(dir + "/" + scene + ".ref");
}

void write_reference(const std::string& dir, const std::string& scene, const ReferenceData& ref) {
  const Snapshots& snaps = ref.snaps;
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/" + scene + ".ref";
  {
    std::ofstream o(path + ".tmp");
    o.precision(17);
    const std::size_t n = snaps.empty() ? 0 : snaps.begin()->second.x.size();
    const std::size_t nb = snaps.empty() ? 0 : snaps.begin()->second.bodies.size();
    o << "xpbd-compare reference2 " << scene << ' ' << snaps.size() << ' ' << n << ' ' << nb << ' '
      << ref.calibration_frame << ' ' << ref.calibration_strain << '\n';
    for (const auto& [f, s] : snaps) {
      if (s.x.size() != n || s.bodies.size() != nb)
        throw std::invalid_argument(path + ": frame " + std::to_string(f) + " has another particle or body count");
      o << "frame " << f << '\n';
      for (const auto* v : {&s.x, &s.bodies})
        for (const Vec3& p : *v) o << double(p.x()) << ' ' << double(p.y()) << ' ' << double(p.z()) << '\n';
    }
    if (!o) throw std::runtime_error(path + ".tmp: write failed");
  }
  std::filesystem::rename(path + ".tmp", path);
}

ReferenceData read_reference(const std::string& dir, const std::string& scene, std::size_t particles,
                             std::size_t bodies) {
  const std::string path = dir + "/" + scene + ".ref";
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error(path + ": cannot open (the double reference of scene " + scene +
                             "; run the double sweep with --reference-dir " + dir + " first)");
  std::string magic, kind, name;
  std::size_t samples = 0, n = 0, nb = 0;
  ReferenceData ref;
  in >> magic >> kind >> name;
  if (!in || magic != "xpbd-compare" || kind != "reference2" || name != scene)
    throw std::runtime_error(path + ": not the xpbd-compare reference of scene " + scene +
                             " (or one of an older format: delete it to recompute it)");
  in >> samples >> n >> nb >> ref.calibration_frame >> ref.calibration_strain;
  if (!in) throw std::runtime_error(path + ": malformed first line");
  if (n != particles)
    throw std::runtime_error(path + ": " + std::to_string(n) + " particles, the scene has " +
                             std::to_string(particles));
  if (nb != bodies)
    throw std::runtime_error(path + ": " + std::to_string(nb) + " dynamic bodies, the scene has " +
                             std::to_string(bodies));
  Snapshots& snaps = ref.snaps;
  for (std::size_t k = 0; k < samples; ++k) {
    std::string word;
    int f = 0;
    in >> word >> f;
    if (!in || word != "frame") throw std::runtime_error(path + ": sample " + std::to_string(k) + ": expected \"frame F\"");
    Sample& s = snaps[f];
    s.x.resize(n);
    s.bodies.resize(nb);
    for (std::size_t i = 0; i < n + nb; ++i) {
      double a = 0, b = 0, c = 0;
      in >> a >> b >> c;
      if (!in)
        throw std::runtime_error(path + ": frame " + std::to_string(f) + ", " +
                                 (i < n ? "particle " + std::to_string(i) : "body " + std::to_string(i - n)) +
                                 ": expected 3 numbers");
      (i < n ? s.x[i] : s.bodies[i - n]) = Vec3(Real(a), Real(b), Real(c));
    }
  }
  return ref;
}

// ---------------------------------------------------------------------------
// Pareto fronts.

std::vector<Point> pareto_front(std::vector<Point> pts) {
  std::erase_if(pts, [](const Point& p) {
    return !(std::isfinite(p.ms) && std::isfinite(p.err) && p.ms > 0 && p.err > 0);
  });
  std::sort(pts.begin(), pts.end(), [](const Point& a, const Point& b) {
    return a.ms != b.ms ? a.ms < b.ms : a.err < b.err;
  });
  // Scanning by increasing time, a point is on the front iff its error is
  // below every error seen so far.
  std::vector<Point> front;
  for (const Point& p : pts)
    if (front.empty() || p.err < front.back().err) front.push_back(p);
  return front;
}

namespace {
// Linear interpolation of log(y) in log(x) between (x0, y0) and (x1, y1).
double loglog(double x, double x0, double y0, double x1, double y1) {
  if (x1 == x0) return y0;
  const double t = (std::log(x) - std::log(x0)) / (std::log(x1) - std::log(x0));
  return std::exp(std::log(y0) + t * (std::log(y1) - std::log(y0)));
}
}  // namespace

std::optional<double> error_at_time(const std::vector<Point>& f, double ms) {
  if (f.empty() || !(ms >= f.front().ms)) return std::nullopt;
  if (ms >= f.back().ms) return f.back().err;
  for (std::size_t i = 0; i + 1 < f.size(); ++i)
    if (ms <= f[i + 1].ms) return loglog(ms, f[i].ms, f[i].err, f[i + 1].ms, f[i + 1].err);
  return f.back().err;
}

std::optional<double> time_at_error(const std::vector<Point>& f, double err) {
  if (f.empty() || !(err >= f.back().err)) return std::nullopt;
  if (err >= f.front().err) return f.front().ms;
  // Errors descend along the front.
  for (std::size_t i = 0; i + 1 < f.size(); ++i)
    if (err >= f[i + 1].err) return loglog(err, f[i].err, f[i].ms, f[i + 1].err, f[i + 1].ms);
  return f.back().ms;
}

}  // namespace xpbd_compare

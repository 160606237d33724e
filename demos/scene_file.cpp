#include "demos/scene_file.hpp"
#include "demos/scene_file_format.hpp"
#include "demos/scene_file_read.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <string_view>
#include <type_traits>

#include "xpbd/compile.hpp"
#include "xpbd/error.hpp"
#include "xpbd/io/obj.hpp"

namespace xpbd_demos {

SceneFileError::SceneFileError(std::string file, std::string json_path, std::string reason)
    : std::runtime_error(file + ": " + (json_path.empty() ? std::string() : json_path + ": ") + reason),
      file_(std::move(file)),
      path_(std::move(json_path)),
      reason_(std::move(reason)) {}

namespace {

using namespace scene_read;

// ---------------------------------------------------------------------------
// Reading: every function gets the JSON value and its path; errors throw
// SceneFileError(file, path, reason).

// ---------------------------------------------------------------------------
// Sections.

SolverSpec read_solver(const Ctx& c, const json& v, const std::string& path) {
  const Obj o(c, v, path, kSolverKeys);
  SolverSpec s;
  o.enumeration("method", s.method, kSolvers);
  o.real("dt", s.dt);
  positive(c, s.dt, o.at("dt"));
  o.integer("substeps", s.substeps);
  at_least(c, s.substeps, 1, o.at("substeps"));
  o.integer("iterations", s.iterations);
  at_least(c, s.iterations, 1, o.at("iterations"));
  o.integer("frames", s.frames);
  at_least(c, s.frames, 1, o.at("frames"));
  o.real("drag", s.drag);
  non_negative(c, s.drag, o.at("drag"));
  o.boolean("alternate_sweeps", s.alternate_sweeps);
  o.boolean("coloured", s.coloured);
  o.boolean("direct_chains", s.direct_chains);
  o.integer("chain_passes", s.chain_passes);
  at_least(c, s.chain_passes, 1, o.at("chain_passes"));
  o.real("chain_tolerance", s.chain_tolerance);
  non_negative(c, s.chain_tolerance, o.at("chain_tolerance"));
  o.boolean("hierarchy", s.hierarchy);
  o.real("hierarchy_slack", s.hierarchy_slack);
  non_negative(c, s.hierarchy_slack, o.at("hierarchy_slack"));
  o.vec("gravity", s.gravity);
  o.real("bullet_kLST", s.bullet_kLST);
  c.require(s.bullet_kLST > Real(0) && s.bullet_kLST <= Real(1), o.at("bullet_kLST"),
            "must be in (0, 1], got " + num(s.bullet_kLST));
  o.number("max_strain", s.max_strain);
  c.require(s.max_strain > 0, o.at("max_strain"), "must be > 0, got " + num(s.max_strain));
  o.number("tolerance", s.tolerance);
  c.require(s.tolerance >= 0, o.at("tolerance"), "must be >= 0, got " + num(s.tolerance));
  o.enumeration("tolerance_measure", s.tolerance_measure, kToleranceMeasures);
  o.number("penetration_tolerance", s.penetration_tolerance);
  c.require(s.penetration_tolerance >= 0, o.at("penetration_tolerance"),
            "must be >= 0, got " + num(s.penetration_tolerance));
  o.integer("max_substeps", s.max_substeps);
  at_least(c, s.max_substeps, 1, o.at("max_substeps"));
  return s;
}

// ---------------------------------------------------------------------------
// SceneError messages ("distances[3].mat.compliance: reason") -> JSON paths.

struct SplitError {
  std::vector<std::string> tokens;  // "distances", "3", "mat", "compliance"
  std::string dotted;               // "distances[3].mat.compliance"
  std::string reason;
};

// Splits "<dotted path>: <reason>". The dotted path is xpbd's naming:
// fields joined by '.', indices in brackets, "p0".."p3" for element
// particles, "p0..p3" for all of them, "nx/ny" for a pair of fields.
std::optional<SplitError> split_error(const std::string& msg) {
  const auto colon = msg.find(": ");
  if (colon == std::string::npos) return std::nullopt;
  SplitError e;
  e.dotted = msg.substr(0, colon);
  e.reason = msg.substr(colon + 2);
  std::string d = e.dotted;
  for (const char* range : {"p0..p3", "p1..p3"}) {
    const auto at = d.find(range);
    if (at != std::string::npos) d.replace(at, std::strlen(range), "p");
  }
  std::string cur;
  auto flush = [&] {
    if (cur.empty()) return;
    const auto slash = cur.find('/');  // "nx/ny": name the first
    if (slash != std::string::npos) cur.resize(slash);
    // "p2" -> "p", "2"
    if (cur.size() >= 2 && cur[0] == 'p' &&
        std::all_of(cur.begin() + 1, cur.end(), [](char ch) { return ch >= '0' && ch <= '9'; })) {
      e.tokens.push_back("p");
      e.tokens.push_back(cur.substr(1));
    } else {
      e.tokens.push_back(cur);
    }
    cur.clear();
  };
  for (char ch : d) {
    if (ch == '.' || ch == '[') {
      flush();
    } else if (ch == ']') {
      e.tokens.push_back(cur);
      cur.clear();
    } else if (ch == ' ') {
      return std::nullopt;  // not a dotted path (e.g. a file path with spaces)
    } else {
      cur += ch;
    }
  }
  flush();
  if (e.tokens.empty()) return std::nullopt;
  return e;
}

std::string join(const std::string& base, const std::vector<std::string>& tokens, std::size_t from) {
  std::string p = base;
  for (std::size_t i = from; i < tokens.size(); ++i)
    if (tokens[i] != "indices") p = child(p, tokens[i]);
  return p;
}

const char* generator_kind(const Generator& g) {
  switch (g.index()) {
    case 0:
      return "cloth";
    case 1:
      return "rope";
    case 2:
      return "tet_box";
    default:
      return "obj";
  }
}

// Rethrows a SceneError of expand() or compile() as a SceneFileError at the
// JSON path of the element it names.
[[noreturn]] void map_soft_error(const Ctx& c, const xpbd::SceneError& err, const SoftSpec& soft,
                                 const ExpandedSoft* ex) {
  const std::string msg = err.what();
  const auto e = split_error(msg);
  if (!e) c.fail("/soft", msg);
  const auto& t = e->tokens;
  const std::string soft_path = "/soft";
  if (t[0] == "generators" || t[0] == "self_collision" ||
      (t[0] == "particles" && t.size() > 1 && t[1] == "positions"))
    c.fail(join(soft_path, t, 0), e->reason);
  if (t[0] == "scene" && t.size() == 2) c.fail(join(soft_path + "/particles", t, 1), e->reason);
  if (!ex || ex->part_sizes.empty() || t.size() < 2) c.fail(soft_path, msg);
  std::size_t k = 0;
  try {
    k = std::stoul(t[1]);
  } catch (const std::exception&) {
    c.fail(soft_path, msg);
  }
  const std::string array = t[0] == "particles" ? "positions" : t[0];
  const auto it = ex->part_sizes[0].find(array);
  if (it == ex->part_sizes[0].end()) c.fail(soft_path, msg);
  if (k < it->second) {
    // An explicit element.
    if (t[0] == "particles") {
      static const std::map<std::string, std::string> field = {
          {"position", "positions"}, {"mass", "masses"}, {"velocity", "velocities"}, {"radius", "radii"}};
      const auto f = t.size() > 2 ? field.find(t[2]) : field.end();
      if (f != field.end()) c.fail(soft_path + "/particles/" + f->second + "/" + t[1], e->reason);
      c.fail(soft_path + "/particles", msg);
    }
    c.fail(join(soft_path, t, 0), e->reason);
  }
  // A generated element: name the generator that made it.
  for (std::size_t g = 0; g + 1 < ex->part_sizes.size(); ++g)
    if (k < ex->part_sizes[g + 1].at(array))
      c.fail(soft_path + "/generators/" + std::to_string(g) + "/" + generator_kind(soft.generators[g]),
             "generated " + e->dotted + ": " + e->reason);
  c.fail(soft_path, msg);
}

// Full validation of what needs more than one field: the expanded and
// compiled particle system, indices into it, the bodies' meshes.
void validate(const Ctx& c, const SceneSpec& s) {
  ExpandedSoft ex;
  try {
    ex = expand(s.soft, s.base_dir);
  } catch (const xpbd::SceneError& e) {
    map_soft_error(c, e, s.soft, nullptr);
  }
  try {
    (void)xpbd::compile(ex.scene);
  } catch (const xpbd::SceneError& e) {
    map_soft_error(c, e, s.soft, &ex);
  }
  const Index n = ex.scene.num_particles();
  for (std::size_t b = 0; b < s.bodies.size(); ++b) {
    if (s.bodies[b].shape.kind != ShapeKind::mesh) continue;
    const std::string base = "/bodies/" + std::to_string(b) + "/shape";
    try {
      (void)body_mesh(s.bodies[b].shape, s.base_dir);
    } catch (const xpbd::io::ObjError& e) {
      c.fail(base + "/mesh/path", e.what());
    } catch (const xpbd::SceneError& e) {
      const auto se = split_error(e.what());
      if (!se) c.fail(base, e.what());
      c.fail(join(base, se->tokens, 1), se->reason);
    }
  }
  for (std::size_t a = 0; a < s.attachments.size(); ++a) {
    const AttachmentSpec& at = s.attachments[a];
    const std::string p = "/attachments/" + std::to_string(a);
    c.require(at.particle >= 0 && at.particle < n, p + "/particle",
              "index " + std::to_string(at.particle) + " out of range [0, " + std::to_string(n) + ")");
    c.require(
        at.body >= 0 && std::size_t(at.body) < s.bodies.size(), p + "/body",
        "index " + std::to_string(at.body) + " out of range [0, " + std::to_string(s.bodies.size()) + ")");
  }
  // Last, so an error in an element is named first.
  c.require(n > 0, "/soft",
            "the scene has no particles: give soft.particles or a generator (docs/scene-format.md)");
}

// ---------------------------------------------------------------------------
// JSON text: position tracking for messages the parser cannot place.

struct Tracker {
  struct Frame {
    bool array = false;
    std::size_t count = 0;  // arrays: elements started
    std::string key;        // objects: current key
    std::set<std::string> keys;
  };
  std::vector<Frame> stack;
  std::string duplicate;  // path of the first duplicate key

  // Path of the value being parsed.
  std::string path() const {
    std::string p;
    for (std::size_t i = 0; i < stack.size(); ++i) {
      const Frame& f = stack[i];
      const bool inner = i + 1 < stack.size();  // an element of f is a container being parsed
      if (f.array)
        p = child(p, inner ? f.count - 1 : f.count);
      else if (!f.key.empty() || !f.keys.empty())
        p = child(p, f.key);
    }
    return p;
  }

  bool operator()(int, json::parse_event_t ev, json& parsed) {
    switch (ev) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        if (!stack.empty() && stack.back().array) ++stack.back().count;
        stack.push_back(Frame{ev == json::parse_event_t::array_start, 0, {}, {}});
        break;
      case json::parse_event_t::key: {
        Frame& f = stack.back();
        f.key = parsed.get<std::string>();
        if (!f.keys.insert(f.key).second && duplicate.empty()) duplicate = path();
        break;
      }
      case json::parse_event_t::value:
        if (!stack.empty() && stack.back().array) ++stack.back().count;
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        stack.pop_back();
        break;
    }
    return true;
  }
};

bool valid_name(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](char ch) {
    return (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_' || ch == '-';
  });
}

}  // namespace

// ---------------------------------------------------------------------------

SceneSpec parse_scene(const json& j, const std::string& file_label, const std::filesystem::path& base_dir) {
  const Ctx c{file_label};
  const Obj o(c, j, "", kTopKeys);
  SceneSpec s;
  s.base_dir = base_dir;
  o.string("name", s.name);
  c.require(valid_name(s.name), o.at("name"),
            "may contain only a-z, 0-9, '_' and '-', got " + show(json(s.name)));
  o.string("description", s.description);
  if (const json* v = o.get("solver")) s.solver = read_solver(c, *v, o.at("solver"));
  if (const json* v = o.get("soft")) s.soft = read_soft(c, *v, o.at("soft"));
  if (const json* v = o.get("bodies"))
    s.bodies = read_list<RigidSpec>(c, *v, o.at("bodies"),
                                    [&](const json& e, const std::string& q) { return read_body(c, e, q); });
  // Body names: optional, unique when given (attachments may use them).
  for (std::size_t a = 0; a < s.bodies.size(); ++a)
    for (std::size_t b = 0; b < a; ++b)
      if (!s.bodies[a].name.empty() && s.bodies[a].name == s.bodies[b].name)
        c.fail("/bodies/" + std::to_string(a) + "/name", "duplicate body name " +
                                                             show(json(s.bodies[a].name)) +
                                                             " (also /bodies/" + std::to_string(b) + ")");
  if (const json* v = o.get("attachments"))
    s.attachments =
        read_list<AttachmentSpec>(c, *v, o.at("attachments"), [&](const json& e, const std::string& q) {
          const Obj a(c, e, q, kAttachmentKeys);
          AttachmentSpec at;
          const json* particle = a.get("particle");
          c.require(particle != nullptr, q, "missing key \"particle\" (a particle index)");
          at.particle = read_int(c, *particle, a.at("particle"));
          const json* body = a.get("body");
          c.require(body != nullptr, q, "missing key \"body\" (a body index or name)");
          if (body->is_string()) {
            const std::string name = body->get<std::string>();
            const auto it = std::find_if(s.bodies.begin(), s.bodies.end(),
                                         [&](const RigidSpec& r) { return !name.empty() && r.name == name; });
            c.require(it != s.bodies.end(), a.at("body"), "no body is named " + show(*body));
            at.body = int(it - s.bodies.begin());
          } else {
            at.body = read_int(c, *body, a.at("body"));
          }
          if (const json* l = a.get("local")) at.local = read_vec(c, *l, a.at("local"));
          a.real("compliance", at.compliance);
          non_negative(c, at.compliance, a.at("compliance"));
          return at;
        });
  try {
    validate(c, s);
  } catch (const SceneFileError&) {
    throw;
  } catch (const std::bad_alloc&) {
    c.fail("/soft", "out of memory while building the scene");
  } catch (const std::length_error&) {
    c.fail("/soft", "out of memory while building the scene");
  } catch (const std::exception& e) {
    throw SceneFileError(file_label, "", e.what());
  }
  return s;
}

json parse_json_text(const std::string& text, const std::string& file_label) {
  if (std::all_of(text.begin(), text.end(),
                  [](char ch) { return ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r'; }))
    throw SceneFileError(file_label, "", "the file is empty; a scene is a JSON object { ... }");
  Tracker tracker;
  json j;
  try {
    j = json::parse(
        text, [&](int depth, json::parse_event_t ev, json& parsed) { return tracker(depth, ev, parsed); });
  } catch (const json::parse_error& e) {
    // "[json.exception.parse_error.101] parse error at line 3, column 7: ..."
    std::string what = e.what();
    const auto close = what.find("] ");
    if (close != std::string::npos) what = what.substr(close + 2);
    throw SceneFileError(file_label, "", "invalid JSON: " + what);
  } catch (const json::exception& e) {
    // Number overflow (1e999): the parser has no line here, but the tracker
    // knows which value it was reading.
    std::string what = e.what();
    const auto close = what.find("] ");
    if (close != std::string::npos) what = what.substr(close + 2);
    throw SceneFileError(file_label, tracker.path().empty() ? "/" : tracker.path(),
                         what + " (must be a finite number)");
  }
  if (!tracker.duplicate.empty())
    throw SceneFileError(file_label, tracker.duplicate,
                         "duplicate key (each key may appear once per object)");
  return j;
}

SceneSpec load_scene_file(const std::filesystem::path& file) {
  const std::string label = file.string();
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw SceneFileError(label, "", "cannot open: Is a directory");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw SceneFileError(label, "", std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream buf;
  buf << in.rdbuf();
  if (in.bad()) throw SceneFileError(label, "", std::string("cannot read: ") + std::strerror(errno));
  const json j = parse_json_text(buf.str(), label);
  return parse_scene(j, label, file.parent_path());
}

void apply_set(json& j, const std::string& assignment) {
  const std::string label = "--set";
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneFileError(label, "",
                         "expected path=value (e.g. solver.substeps=20), got \"" + assignment + "\"");
  const std::string path = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  json* node = &j;
  std::string pointer;
  std::size_t start = 0;
  while (start <= path.size()) {
    const auto dot = path.find('.', start);
    const std::string key = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    start = dot == std::string::npos ? path.size() + 1 : dot + 1;
    if (key.empty()) throw SceneFileError(label, "", "empty field name in path \"" + path + "\"");
    if (node->is_object()) {
      pointer = child(pointer, key);
      const auto it = node->find(key);
      if (it == node->end()) {
        std::string list;
        for (const auto& item : node->items()) list += (list.empty() ? "" : ", ") + item.key();
        throw SceneFileError(label, pointer, "no such field in the scene (here: " + list + ")");
      }
      node = &*it;
    } else if (node->is_array()) {
      std::size_t i = 0;
      const auto r = std::from_chars(key.data(), key.data() + key.size(), i);
      pointer = child(pointer, key);
      if (r.ec != std::errc() || r.ptr != key.data() + key.size())
        throw SceneFileError(label, pointer, "expected an array index (0, 1, ...), got \"" + key + "\"");
      if (i >= node->size())
        throw SceneFileError(label, pointer,
                             "index " + key + " out of range [0, " + std::to_string(node->size()) + ")");
      node = &(*node)[i];
    } else {
      throw SceneFileError(label, pointer,
                           "is a " + std::string(node->type_name()) + ", it has no field \"" + key + "\"");
    }
  }
  json value;
  try {
    value = json::parse(text);
  } catch (const json::exception&) {
    value = text;  // not JSON: a string
  }
  *node = value;
}

SceneSpec apply_sets(const SceneSpec& s, const std::vector<std::string>& assignments,
                     const std::string& file_label) {
  json j = to_json(s);
  for (const std::string& a : assignments) apply_set(j, a);
  return parse_scene(j, file_label, s.base_dir);
}

}  // namespace xpbd_demos

#pragma once
// Reading scene files: the checked readers of JSON values (every one gets
// the value and its JSON path; errors throw SceneFileError(file, path,
// reason)) and the section readers, shared by scene_file.cpp (top level,
// solver, validation, --set), scene_file_soft.cpp (the particle system) and
// scene_file_bodies.cpp (rigid bodies). Internal to xpbd-demo.
#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "demos/scene_file.hpp"
#include "demos/scene_file_format.hpp"
#include "demos/scene_spec.hpp"

namespace xpbd_demos::scene_read {

using namespace scene_format;

struct Ctx {
  std::string file;
  [[noreturn]] void fail(const std::string& path, const std::string& reason) const {
    throw SceneFileError(file, path.empty() ? "/" : path, reason);
  }
  void require(bool ok, const std::string& path, const std::string& reason) const {
    if (!ok) fail(path, reason);
  }
};

inline Real read_real(const Ctx& c, const json& v, const std::string& path) {
  if (!v.is_number()) c.fail(path, "expected a number, got " + show(v));
  const double d = v.get<double>();
  const Real r = static_cast<Real>(d);
  if (!std::isfinite(r))
    c.fail(path,
           "must be a finite number" +
               std::string(std::is_same_v<Real, float> ? " within the float range (|x| < 3.4e38)" : "") +
               ", got " + show(v));
  return r;
}

inline int read_int(const Ctx& c, const json& v, const std::string& path) {
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    if (u > std::uint64_t(std::numeric_limits<int>::max()))
      c.fail(path, "integer " + show(v) + " is too large (max " +
                       std::to_string(std::numeric_limits<int>::max()) + ")");
    return static_cast<int>(u);
  }
  if (v.is_number_integer()) {
    const auto i = v.get<std::int64_t>();
    if (i < std::int64_t(std::numeric_limits<int>::min()))
      c.fail(path, "integer " + show(v) + " is too small");
    return static_cast<int>(i);
  }
  c.fail(path, "expected an integer, got " + show(v));
}

inline bool read_bool(const Ctx& c, const json& v, const std::string& path) {
  if (!v.is_boolean()) c.fail(path, "expected true or false, got " + show(v));
  return v.get<bool>();
}

inline std::string read_string(const Ctx& c, const json& v, const std::string& path) {
  if (!v.is_string()) c.fail(path, "expected a string, got " + show(v));
  return v.get<std::string>();
}

inline const json& read_array(const Ctx& c, const json& v, const std::string& path) {
  if (!v.is_array()) c.fail(path, "expected an array [ ... ], got " + show(v));
  return v;
}

inline Vec3 read_vec(const Ctx& c, const json& v, const std::string& path) {
  if (!v.is_array() || v.size() != 3)
    c.fail(path, "expected [x, y, z] (an array of 3 numbers), got " + show(v));
  return Vec3(read_real(c, v[0], child(path, 0)), read_real(c, v[1], child(path, 1)),
              read_real(c, v[2], child(path, 2)));
}

template <std::size_t N>
std::array<int, N> read_ints(const Ctx& c, const json& v, const std::string& path) {
  if (!v.is_array() || v.size() != N)
    c.fail(path, "expected an array of " + std::to_string(N) + " integers, got " + show(v));
  std::array<int, N> a{};
  for (std::size_t i = 0; i < N; ++i) a[i] = read_int(c, v[i], child(path, i));
  return a;
}

template <class T, class F>
std::vector<T> read_list(const Ctx& c, const json& v, const std::string& path, F&& read_one) {
  read_array(c, v, path);
  std::vector<T> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out.push_back(read_one(v[i], child(path, i)));
  return out;
}

template <class E, std::size_t N>
E read_enum(const Ctx& c, const json& v, const std::string& path, const EnumName<E> (&table)[N]) {
  std::string names;
  for (std::size_t i = 0; i < N; ++i) names += (i ? ", \"" : "\"") + std::string(table[i].name) + "\"";
  if (!v.is_string()) c.fail(path, "expected one of " + names + ", got " + show(v));
  const std::string s = v.get<std::string>();
  for (const auto& e : table)
    if (s == e.name) return e.value;
  c.fail(path, "must be one of " + names + ", got " + show(v));
}

// Range checks.
inline void positive(const Ctx& c, Real v, const std::string& path) {
  c.require(v > Real(0), path, "must be > 0, got " + num(v));
}
inline void non_negative(const Ctx& c, Real v, const std::string& path) {
  c.require(v >= Real(0), path, "must be >= 0, got " + num(v));
}
inline void unit_interval(const Ctx& c, Real v, const std::string& path) {
  c.require(v >= Real(0) && v <= Real(1), path, "must be in [0, 1], got " + num(v));
}
inline void at_least(const Ctx& c, int v, int lo, const std::string& path) {
  c.require(v >= lo, path, "must be >= " + std::to_string(lo) + ", got " + std::to_string(v));
}

// A JSON object with a fixed set of keys: unknown keys are errors (reported
// before any value is read, since a misspelt key is the likeliest mistake).
class Obj {
 public:
  Obj(const Ctx& c, const json& j, std::string path, const Keys& keys)
      : c_(c), j_(j), path_(std::move(path)), keys_(keys) {
    if (!j.is_object()) c.fail(path_, "expected an object { ... }, got " + show(j));
    for (const auto& item : j.items()) {
      if (std::find_if(keys_.begin(), keys_.end(), [&](const char* k) { return item.key() == k; }) ==
          keys_.end()) {
        std::string list;
        for (const char* k : keys_) list += (list.empty() ? "" : ", ") + std::string(k);
        c.fail(at(item.key()), "unknown key (expected one of: " + list + ")");
      }
    }
  }

  const Ctx& ctx() const { return c_; }
  const std::string& path() const { return path_; }
  std::string at(std::string_view key) const { return child(path_, key); }

  // The value of `key`, or nullptr if absent.
  const json* get(const char* key) const {
    const auto it = j_.find(key);
    return it == j_.end() ? nullptr : &*it;
  }

  // Optional fields: left unchanged when absent.
  void real(const char* key, Real& out) const {
    if (const json* v = get(key)) out = read_real(c_, *v, at(key));
  }
  // A finite double whatever the build's Real (thresholds the solver keeps
  // in double, so that they round-trip exactly).
  void number(const char* key, double& out) const {
    if (const json* v = get(key)) {
      if (!v->is_number()) c_.fail(at(key), "expected a number, got " + show(*v));
      out = v->get<double>();
      if (!std::isfinite(out)) c_.fail(at(key), "must be a finite number, got " + show(*v));
    }
  }
  void integer(const char* key, int& out) const {
    if (const json* v = get(key)) out = read_int(c_, *v, at(key));
  }
  void boolean(const char* key, bool& out) const {
    if (const json* v = get(key)) out = read_bool(c_, *v, at(key));
  }
  void string(const char* key, std::string& out) const {
    if (const json* v = get(key)) out = read_string(c_, *v, at(key));
  }
  void vec(const char* key, Vec3& out) const {
    if (const json* v = get(key)) out = read_vec(c_, *v, at(key));
  }
  void material(const char* key, Material& out) const;
  template <class E, std::size_t N>
  void enumeration(const char* key, E& out, const EnumName<E> (&table)[N]) const {
    if (const json* v = get(key)) out = read_enum(c_, *v, at(key), table);
  }

 private:
  const Ctx& c_;
  const json& j_;
  std::string path_;
  Keys keys_;
};

inline Material read_material(const Ctx& c, const json& v, const std::string& path) {
  const Obj o(c, v, path, kMaterialKeys);
  Material m;
  o.real("compliance", m.compliance);
  o.real("damping", m.damping);
  o.real("stiffness", m.stiffness);
  non_negative(c, m.compliance, o.at("compliance"));
  non_negative(c, m.damping, o.at("damping"));
  unit_interval(c, m.stiffness, o.at("stiffness"));
  return m;
}

inline void Obj::material(const char* key, Material& out) const {
  if (const json* v = get(key)) out = read_material(c_, *v, at(key));
}

// An object with exactly one key naming its kind ({"cloth": {...}}); returns
// that key, checked against `kinds`.
inline std::string single_kind(const Ctx& c, const json& v, const std::string& path,
                        std::initializer_list<const char*> kinds, const char* what) {
  std::string list;
  for (const char* k : kinds) list += (list.empty() ? "" : ", ") + std::string(k);
  if (!v.is_object() || v.size() != 1)
    c.fail(path, std::string("expected an object with exactly one key, the ") + what + " (" + list +
                     "), got " + show(v));
  const std::string kind = v.begin().key();
  if (std::find_if(kinds.begin(), kinds.end(), [&](const char* k) { return kind == k; }) == kinds.end())
    c.fail(child(path, kind), std::string("unknown ") + what + " (expected one of: " + list + ")");
  return kind;
}

// The sections in their own files.
SoftSpec read_soft(const Ctx& c, const json& v, const std::string& path);     // scene_file_soft.cpp
RigidSpec read_body(const Ctx& c, const json& v, const std::string& path);    // scene_file_bodies.cpp

}  // namespace xpbd_demos::scene_read

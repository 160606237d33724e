#pragma once
// Scene files: the JSON format of docs/scene-format.md <-> SceneSpec.
//
//   load_scene_file(path)       read, parse and validate a scene file
//   parse_scene(json, ...)      the same for a JSON value already in memory
//   to_json(spec)               the complete scene (every field, defaults
//                               included): parse_scene(to_json(s)) == s
//   apply_set(json, "a.b.0=v")  the --set override of the command line
//   scene_text(json)            JSON text for people (short arrays on one line)
//
// Validation is complete before anything runs: types, unknown keys, ranges,
// the generators (expanded), the particle system (compiled with
// xpbd::compile), indices that refer to particles or bodies, and the files a
// scene names (OBJ meshes). Every problem is a SceneFileError.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "demos/scene_spec.hpp"

namespace xpbd_demos {

// what() is "<file>: <json path>: <reason>", e.g.
//   scene.json: /bodies/2/mass: must be finite and >= 0 (0 = static), got -1
// or "<file>: <reason>" when no JSON path applies (unreadable file, invalid
// JSON syntax). The path is a JSON pointer (RFC 6901); "/" is the whole
// document.
class SceneFileError : public std::runtime_error {
 public:
  SceneFileError(std::string file, std::string json_path, std::string reason);
  const std::string& file() const { return file_; }
  const std::string& json_path() const { return path_; }  // empty if none
  const std::string& reason() const { return reason_; }

 private:
  std::string file_, path_, reason_;
};

// Parses and fully validates a scene. `file_label` starts every error
// message; relative file paths in the scene are resolved against base_dir
// (stored in the result's base_dir).
SceneSpec parse_scene(const nlohmann::json& j, const std::string& file_label,
                      const std::filesystem::path& base_dir);

// Reads `file` (its path as given labels the errors, relative paths inside it
// are resolved against its directory) and calls parse_scene. Duplicate keys
// in an object are an error (JSON parsers would otherwise keep the last).
SceneSpec load_scene_file(const std::filesystem::path& file);

// Parses JSON text with the checks of load_scene_file (syntax, duplicate
// keys, numbers out of range) but no scene validation.
nlohmann::json parse_json_text(const std::string& text, const std::string& file_label);

// The complete scene: every field, defaults included (an empty optional
// field, such as a distance's rest length, is left out). Numbers round-trip
// exactly in both the double and the float build. A shape writes only the
// fields of its kind (a sphere has no half_extents).
nlohmann::json to_json(const SceneSpec& s);

// One command-line override "path=value", applied to a complete scene (as
// written by to_json). The path uses dots between keys and array indices:
//   solver.substeps=20   bodies.0.mass=2   soft.generators.0.cloth.nx=16
// The value is parsed as JSON (20, 2.5, true, [0,1,0], {"compliance":1e-6},
// "text"); if it is not valid JSON it is taken as a string, so
// solver.method=pbd works without quotes. Throws SceneFileError (file label
// "--set") if the assignment has no '=' or the path does not exist.
void apply_set(nlohmann::json& j, const std::string& assignment);

// to_json(s), every apply_set, then parse_scene (with s.base_dir): a scene
// with command-line overrides, validated like a file.
SceneSpec apply_sets(const SceneSpec& s, const std::vector<std::string>& assignments,
                     const std::string& file_label);

// JSON text for people: two-space indentation, arrays of numbers (vectors,
// index lists) on one line. Parses back to exactly `j`.
std::string scene_text(const nlohmann::json& j);

}  // namespace xpbd_demos

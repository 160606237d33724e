#include "xpbd/io/obj.hpp"

#include <tiny_obj_loader.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

namespace xpbd::io {
namespace {

[[noreturn]] void fail_at(const std::string& path, std::size_t line, const std::string& what) {
  throw ObjError(path + ": line " + std::to_string(line) + ": " + what);
}

// True if all of `s` is a finite number (an optional leading '+' allowed,
// which std::from_chars does not take).
bool parse_number(const std::string& s, double& x) {
  const char* first = s.data() + (!s.empty() && s[0] == '+' ? 1 : 0);
  const char* last = s.data() + s.size();
  const auto r = std::from_chars(first, last, x);
  return first != last && r.ec == std::errc() && r.ptr == last && std::isfinite(x);
}

// Strict check of the 'v' and 'f' lines before tinyobjloader reads the file.
// tinyobjloader is lenient: it reads a coordinate that is not a number as 0,
// drops a face with fewer than 3 vertices and accepts "f 1 2 3.5"; such a
// file is an error here, named by line.
void check_syntax(const std::string& path, const ObjOptions& opt) {
  std::ifstream in(path);
  if (!in) throw ObjError(path + ": cannot open for reading");
  std::string line;
  std::size_t lineno = 0, vertices = 0, faces = 0;
  long max_ref = 0;  // largest positive vertex reference
  std::size_t max_ref_line = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ss(line);
    std::string key, tok;
    ss >> key;
    if (key == "v") {
      int count = 0;
      for (; ss >> tok; ++count) {
        double x;
        if (!parse_number(tok, x))
          fail_at(path, lineno, "vertex coordinate '" + tok + "' is not a finite number");
      }
      if (count < 3)
        fail_at(path, lineno, "a vertex needs 3 coordinates, got " + std::to_string(count));
      ++vertices;
    } else if (key == "f") {
      ++faces;
      int count = 0;
      for (; ss >> tok; ++count) {
        // v, v/vt, v//vn or v/vt/vn: the vertex number is before the first '/'.
        const std::string v = tok.substr(0, tok.find('/'));
        long idx = 0;
        const auto r = std::from_chars(v.data(), v.data() + v.size(), idx);
        if (r.ec != std::errc() || r.ptr != v.data() + v.size() || idx == 0)
          fail_at(path, lineno,
                  "face " + std::to_string(faces) + ": vertex reference '" + tok +
                      "' is not a non-zero integer");
        // Negative: relative to the vertices read so far (-1 = the last one).
        if (idx < 0 && std::size_t(-idx) > vertices)
          fail_at(path, lineno,
                  "face " + std::to_string(faces) + ": vertex reference " + std::to_string(idx) +
                      " reaches before the first vertex (" + std::to_string(vertices) +
                      " read so far)");
        if (idx > max_ref) {
          max_ref = idx;
          max_ref_line = lineno;
        }
      }
      if (count < 3)
        fail_at(path, lineno,
                "face " + std::to_string(faces) + " has " + std::to_string(count) +
                    " vertices; a face needs at least 3");
      if (count > 3 && !opt.triangulate)
        fail_at(path, lineno,
                "face " + std::to_string(faces) + " has " + std::to_string(count) +
                    " vertices; only triangles are accepted (or load with "
                    "ObjOptions::triangulate = true)");
    }
  }
  if (std::size_t(max_ref) > vertices)
    fail_at(path, max_ref_line,
            "a face uses vertex " + std::to_string(max_ref) + ", but the file has " +
                std::to_string(vertices) + " vertices");
  if (faces == 0) throw ObjError(path + ": contains no faces ('f' lines)");
}

}  // namespace

TriangleMesh load_obj(const std::string& path, const ObjOptions& opt) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw ObjError(path + ": no such file (or not a regular file)");
  check_syntax(path, opt);
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = opt.triangulate;
  cfg.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, cfg)) {
    std::string why = reader.Error();
    while (!why.empty() && (why.back() == '\n' || why.back() == '\r')) why.pop_back();
    throw ObjError(path + ": cannot parse as OBJ: " + (why.empty() ? "unknown error" : why));
  }
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  TriangleMesh mesh;
  const std::size_t nv = attrib.vertices.size() / 3;
  mesh.positions.reserve(nv);
  for (std::size_t v = 0; v < nv; ++v)
    mesh.positions.emplace_back(Real(attrib.vertices[3 * v]), Real(attrib.vertices[3 * v + 1]),
                                Real(attrib.vertices[3 * v + 2]));
  // check_syntax has vetted every face; these checks only guard against a
  // disagreement between it and tinyobjloader.
  std::size_t face = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    std::size_t offset = 0;
    for (const unsigned char count : shape.mesh.num_face_vertices) {
      ++face;
      if (count != 3)
        throw ObjError(path + ": face " + std::to_string(face) + " has " +
                       std::to_string(int(count)) + " vertices after reading; expected 3");
      Triangle t;
      for (int c = 0; c < 3; ++c) {
        const int idx = shape.mesh.indices[offset + std::size_t(c)].vertex_index;
        if (idx < 0 || std::size_t(idx) >= nv)
          throw ObjError(path + ": face " + std::to_string(face) + " uses vertex " +
                         std::to_string(idx + 1) + ", but the file has " + std::to_string(nv) +
                         " vertices");
        t[std::size_t(c)] = Index(idx);
      }
      mesh.triangles.push_back(t);
      offset += count;
    }
  }
  if (mesh.triangles.empty()) throw ObjError(path + ": contains no faces ('f' lines)");
  return mesh;
}

MeshResult add_obj_mesh(SceneDesc& scene, const std::string& path, TriangleMeshDesc d,
                        const ObjOptions& opt) {
  const TriangleMesh mesh = load_obj(path, opt);
  d.name = path;
  d.index_base = 1;
  try {
    return add_triangle_mesh(scene, mesh, d);
  } catch (const ObjError&) {
    throw;
  } catch (const SceneError& e) {
    throw ObjError(e.what());  // already starts with the path
  }
}

}  // namespace xpbd::io

#pragma once
// Wavefront OBJ meshes as xpbd scenes (library xpbd_io, target xpbd_bullet::io).
//
// Only vertex positions ('v') and faces ('f') are read; normals, texture
// coordinates, materials, lines and points are ignored. All objects and
// groups of the file are merged into one mesh with the file's vertex
// numbering (OBJ counts from 1; TriangleMesh counts from 0, and error
// messages use the file's numbering).
#include <string>

#include "xpbd/builders.hpp"
#include "xpbd/error.hpp"

namespace xpbd::io {

// Thrown for a file that cannot be read or is not a usable triangle mesh.
// The message starts with the file's path. Derives from SceneError, so code
// that handles bad scene input handles bad files too.
class ObjError : public SceneError {
 public:
  using SceneError::SceneError;
};

struct ObjOptions {
  // false: a face with more than 3 vertices is an error naming the face.
  // true: polygons are split into triangles by tinyobjloader.
  bool triangulate = false;
};

// Reads the vertices and triangles of an OBJ file.
TriangleMesh load_obj(const std::string& path, const ObjOptions& opt = {});

// load_obj, then add_triangle_mesh with d (d.name and d.index_base are set
// to the path and 1, so builder errors name the file and its vertex
// numbers). Builder errors are rethrown as ObjError.
MeshResult add_obj_mesh(SceneDesc& scene, const std::string& path, TriangleMeshDesc d,
                        const ObjOptions& opt = {});

}  // namespace xpbd::io

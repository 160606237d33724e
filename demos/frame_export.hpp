#pragma once
// Frames of a run as files for other programs: Wavefront OBJ (Blender) and
// legacy ASCII VTK POLYDATA (ParaView), plus the triangulated rigid bodies
// both of them and the preview picture (preview.hpp) need.
//
// Coordinates are written in the scene's units (m) and frame (y up), with the
// shortest decimal form that reads back to the same xpbd::Real (std::to_chars),
// so a file read back with a correctly rounding parser gives the exact values.
#include <array>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "demos/scene_spec.hpp"
#include "xpbd/types.hpp"

namespace xpbd_demos {

// A rigid body as a triangle mesh.
struct RigidMesh {
  std::string name;                                   // object name in OBJ files; empty = "body_<k>"
  std::vector<xpbd::Vec3> vertices;                   // m
  std::vector<std::array<xpbd::Index, 3>> triangles;  // 0-based; built-in shapes: counter-clockwise seen from outside
  // True for a plane's finite stand-in (a square): views leave it out of the
  // region they frame (preview.hpp) and clip it instead.
  bool unbounded = false;
};

struct TessellationOptions {
  int segments = 12;  // around the local y axis: sphere, capsule, cylinder (>= 3)
  int rings = 8;      // pole to pole (>= 2): sphere; capsule: rings / 2 (rounded down) per cap
  xpbd::Real plane_half_size = 5;  // m, half the side of the square standing for a plane (> 0)
};

// The shape in its body frame. Sphere: `segments` x `rings` latitude/longitude
// grid. Capsule: two hemispheres joined by a cylinder, along local y.
// Cylinder: along local y, with flat caps. Box: 12 triangles. Plane
// { x : n.x = offset } with n = normal / |normal| (offset is the signed
// distance from the body origin, as demos/rigid_world.cpp builds Bullet's
// plane): a square of side 2 * plane_half_size centred at the point of the
// plane nearest the body origin. Convex hull: the hull of the points
// (Bullet's btConvexHullComputer), its planar faces split into fans; points
// that are all collinear give no triangles. Mesh: body_mesh(shape, base_dir)
// (scene_spec.hpp), the same triangles as the Bullet world's.
// Throws xpbd::SceneError naming the field ("shape.radius: must be > 0, got
// -1") for an invalid shape, xpbd::io::ObjError for an unreadable file.
RigidMesh shape_mesh(const ShapeSpec& shape, const std::filesystem::path& base_dir,
                     const TessellationOptions& opt = {});

// `body` (body frame) moved to the pose: x_world = R(q) x_body + position.
// quat_wxyz is normalised here; throws xpbd::SceneError if it is zero or not
// finite.
RigidMesh transform_mesh(const RigidMesh& body, const xpbd::Vec3& position,
                         const std::array<xpbd::Real, 4>& quat_wxyz);

// shape_mesh + transform_mesh in one call, except for planes: their square is
// centred at the point of the (world) plane nearest the world origin, so a
// ground plane is framed around the scene whatever the body's position.
// (Reads a mesh file on every call: for many frames of a mesh body, call
// shape_mesh once and transform_mesh per frame.)
RigidMesh rigid_mesh(const ShapeSpec& shape, const xpbd::Vec3& position,
                     const std::array<xpbd::Real, 4>& quat_wxyz,
                     const std::filesystem::path& base_dir, const TessellationOptions& opt = {});

// ---------------------------------------------------------------------------
enum class ExportFormat { obj, vtk };

// "obj" or "vtk".
const char* extension(ExportFormat format);

// <out_dir>/frames/frame_00012.obj (frame numbered with at least 5 digits).
std::filesystem::path frame_file_path(const std::filesystem::path& out_dir, int frame,
                                      ExportFormat format);

// One frame as an OBJ file: object "soft" (all particles x as vertices, the
// surface `triangles` as faces, the rope `lines` as polylines, particles in
// neither as points), then one object per rigid body (named by its name or
// body_<k>, spaces replaced by '_'). Written atomically (write_text_atomically):
// the directory is created if needed and a reader never sees half a file.
// Throws std::invalid_argument for an index out of range or a non-finite
// coordinate (naming the element), std::runtime_error for I/O errors.
void write_frame_obj(const std::filesystem::path& file, std::span<const xpbd::Vec3> x,
                     const std::vector<std::array<xpbd::Index, 3>>& triangles,
                     const std::vector<std::array<xpbd::Index, 2>>& lines,
                     const std::vector<RigidMesh>& bodies);

// The same as a legacy ASCII VTK POLYDATA file: POINTS (the particles, then
// each body's vertices), VERTICES (particles in no triangle or line), LINES,
// POLYGONS, and CELL_DATA scalars "body" (0 = soft body, k + 1 = bodies[k])
// in VTK's cell order (vertices, lines, polygons) for colouring in ParaView.
// ParaView opens a numbered series frame_00000.vtk, frame_00001.vtk, ... as
// one time-dependent data set. Same atomicity and errors as write_frame_obj.
void write_frame_vtk(const std::filesystem::path& file, std::span<const xpbd::Vec3> x,
                     const std::vector<std::array<xpbd::Index, 3>>& triangles,
                     const std::vector<std::array<xpbd::Index, 2>>& lines,
                     const std::vector<RigidMesh>& bodies);

// Dispatches on `format`.
void write_frame(ExportFormat format, const std::filesystem::path& file,
                 std::span<const xpbd::Vec3> x,
                 const std::vector<std::array<xpbd::Index, 3>>& triangles,
                 const std::vector<std::array<xpbd::Index, 2>>& lines,
                 const std::vector<RigidMesh>& bodies);

}  // namespace xpbd_demos

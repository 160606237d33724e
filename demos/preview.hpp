#pragma once
// preview.png: a few frames of a run side by side, rendered headless with
// gnuplot (terminal pngcairo), so a user can look instead of read.
//
// Each panel is a 3D view of one frame: the soft body's surface triangles as
// shaded orange polygons, its rope segments as dark red lines, particles in
// neither as dots, rigid bodies as shaded blue polygons, planes grey. All
// panels share one view (from the front, +z, and above; the scene's y axis
// up) and one cube of axis ranges (equal scales on x, y and z), framed
// around the particles and the bounded rigid bodies of all frames; unbounded
// ones (planes) are clipped to that cube. Polygon edges are drawn when a
// panel has at most 4000 triangles.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "demos/frame_export.hpp"
#include "xpbd/types.hpp"

namespace xpbd_demos {

struct PreviewFrame {
  xpbd::Real time = 0;            // s, shown in the panel title
  std::vector<xpbd::Vec3> x;      // m, particle positions
  std::vector<RigidMesh> bodies;  // rigid bodies in world coordinates at this frame
};

struct PreviewInput {
  std::string title;                                  // picture title (e.g. scene and solver)
  std::vector<std::array<xpbd::Index, 3>> triangles;  // soft surface, particle indices (ExpandedSoft)
  std::vector<std::array<xpbd::Index, 2>> lines;      // rope segments, particle indices
  std::vector<PreviewFrame> frames;                   // one panel each, 1 to 8
  int panel_width = 400;                              // pixels per panel (>= 100)
  int height = 440;                                   // pixels (>= 100)
  std::string gnuplot = "gnuplot";                    // command run through the shell (sh)
};

// Renders `in` to the PNG file `png` (width = panels x panel_width, height as
// given). gnuplot writes to a temporary file next to `png`, which is then
// renamed over it (a reader never sees half a picture); the script and the
// data go through a temporary directory that is removed afterwards. Takes
// about 0.15 s per panel for a 64 x 64 cloth (gnuplot 5.4, this machine).
// Throws std::invalid_argument for bad input (no frames, an index out of
// range, a non-finite position: named), std::runtime_error naming the
// command and its exit status (and gnuplot's first error lines) if gnuplot
// is missing or fails, and std::runtime_error naming `png` if the picture
// gnuplot left is not a complete PNG (gnuplot exits 0 after a failed write,
// e.g. on a full disk): see png_complete.
void render_preview(const std::filesystem::path& png, const PreviewInput& in);

// Whether `file` is a regular file holding a whole PNG stream: the 8-byte
// signature first and the IEND chunk (with its CRC) last. If not, `why`
// (when given) says what is wrong.
bool png_complete(const std::filesystem::path& file, std::string* why = nullptr);

// Which frames to show: `panels` frame numbers spread evenly over 0 ..
// frames - 1 (rounded to the nearest), first and last included; every frame
// if there are no more than `panels`; the last one if panels is 1.
// E.g. preview_frame_numbers(180, 4) = {0, 60, 119, 179}. Throws
// std::invalid_argument if frames or panels is < 1.
std::vector<int> preview_frame_numbers(int frames, int panels = 4);

}  // namespace xpbd_demos

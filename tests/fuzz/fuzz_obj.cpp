// Fuzz target: the OBJ reader (xpbd::io::load_obj and add_obj_mesh) on a
// file with the input's bytes, both with and without triangulation. Bad
// input must be an xpbd::io::ObjError; a crash, a sanitizer report or a
// leak is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "xpbd/io/obj.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/xpbd_fuzz_obj_" + std::to_string(::getpid()) + ".obj";
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    if (size) std::fwrite(data, 1, size, f);
    std::fclose(f);
  } else {
    return 0;
  }
  for (const bool triangulate : {false, true}) {
    xpbd::io::ObjOptions opt;
    opt.triangulate = triangulate;
    try {
      (void)xpbd::io::load_obj(path, opt);
    } catch (const xpbd::io::ObjError&) {
    }
    try {
      xpbd::SceneDesc scene;
      (void)xpbd::io::add_obj_mesh(scene, path, {}, opt);
    } catch (const xpbd::io::ObjError&) {
    }
  }
  return 0;
}

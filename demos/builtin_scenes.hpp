#pragma once
// The built-in demo scenes of xpbd-demo (`xpbd-demo --list`). Each is a
// SceneSpec written in C++; `xpbd-demo --dump NAME` prints it in the scene
// file format (docs/scene-format.md), ready to edit. See docs/scenes.md for
// what each one shows and the parameters of the two ports of Bullet's
// SoftDemo.
#include <string>
#include <vector>

#include "demos/scene_spec.hpp"

namespace xpbd_demos {

// The scene README command 1 runs: XPBD inside Bullet against rigid bodies.
inline constexpr const char* kDefaultScene = "cloth_on_sphere";

// Every built-in scene, in --list order.
const std::vector<SceneSpec>& builtin_scenes();

// The scene called `name`, or nullptr.
const SceneSpec* find_builtin_scene(const std::string& name);

}  // namespace xpbd_demos

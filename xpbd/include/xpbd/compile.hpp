#pragma once
#include "xpbd/model.hpp"
#include "xpbd/scene.hpp"

namespace xpbd {

// Checks `scene` and builds the immutable Model. Throws SceneError naming the
// element, field and value of the first invalid input found.
Model compile(const SceneDesc& scene);

}  // namespace xpbd

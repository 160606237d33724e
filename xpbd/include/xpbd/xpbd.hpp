#pragma once
// Umbrella header for the xpbd solver.
#include "xpbd/builders.hpp"
#include "xpbd/compile.hpp"
#include "xpbd/constraints.hpp"
#include "xpbd/diagnostics.hpp"
#include "xpbd/error.hpp"
#include "xpbd/materials.hpp"
#include "xpbd/model.hpp"
#include "xpbd/raycast.hpp"
#include "xpbd/scene.hpp"
#include "xpbd/state.hpp"
#include "xpbd/rigid.hpp"
#include "xpbd/step.hpp"

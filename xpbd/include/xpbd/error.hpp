#pragma once
#include <stdexcept>
#include <string>

#include "xpbd/types.hpp"

namespace xpbd {

// Thrown by compile() for invalid scene input. The message names the element
// (e.g. "distances[3]"), the field and the offending value.
class SceneError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Thrown by step() for an invalid StepConfig (non-positive dt, zero substeps...).
class ConfigError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// How error messages print values: 9 significant digits ("-2.5e-07",
// "0.333333333"), and vectors as "(x, y, z)".
std::string format_value(double v);
std::string format_vec(const Vec3& v);

}  // namespace xpbd

#pragma once
#include <stdexcept>
#include <string>

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

}  // namespace xpbd

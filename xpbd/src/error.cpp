#include "xpbd/error.hpp"

#include <sstream>

namespace xpbd {

std::string format_value(double v) {
  std::ostringstream o;
  o.precision(9);
  o << v;
  return o.str();
}

// Built with a stream: GCC 12 warns falsely (-Wrestrict, GCC bug 105329) on
// "literal" + std::string&& chains.
std::string format_vec(const Vec3& v) {
  std::ostringstream o;
  o.precision(9);
  o << '(' << v.x() << ", " << v.y() << ", " << v.z() << ')';
  return o.str();
}

}  // namespace xpbd

#pragma once
// The command-line values of the squeeze programs (squeeze_campaign.cpp,
// squeeze_rest.cpp): each parser returns false, and leaves its output
// alone, on anything but a value it accepts.
#include <cstdlib>
#include <string>

#include "squeeze_app.hpp"

namespace xpbd_bullet::test::squeeze {

// A whole positive number, or 0 if `s` is not one.
inline unsigned parse_whole(const std::string& s) {
  if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos) return 0;
  return unsigned(std::stoul(s));
}

// "A-B" (1 <= A <= B) or "A": wrinkle seeds A to B.
inline bool parse_seeds(const std::string& v, unsigned& first, unsigned& last) {
  const std::size_t dash = v.find('-');
  const unsigned a = parse_whole(v.substr(0, dash));
  const unsigned b = dash == std::string::npos ? a : parse_whole(v.substr(dash + 1));
  if (a < 1 || b < a) return false;
  first = a;
  last = b;
  return true;
}

// A compliance in m/N: a number >= 0 (and below 1e6).
inline bool parse_compliance(const char* s, Real& out) {
  char* end = nullptr;
  const double c = std::strtod(s, &end);
  if (end == s || *end != '\0' || !(c >= 0) || !(c < 1e6)) return false;
  out = Real(c);
  return true;
}

// The flags both programs take: --bend C, --shear C (the cloth's
// compliances) and --seeds A-B. If argv[a] is one of them with a value,
// takes it (a moves onto the value) and returns 1, or -1 with `why` set if
// the value is bad; returns 0 for any other argument.
struct ClothAndSeeds {
  Real bend = 0, shear = 0;
  unsigned first = 1, last = 1;
};
inline int take_cloth_and_seeds(int argc, char** argv, int& a, ClothAndSeeds& out, const char*& why) {
  const std::string flag = argv[a];
  if ((flag != "--bend" && flag != "--shear" && flag != "--seeds") || a + 1 >= argc) return 0;
  const char* v = argv[++a];
  if (flag == "--seeds") {
    why = "--seeds needs A-B with 1 <= A <= B, got";
    return parse_seeds(v, out.first, out.last) ? 1 : -1;
  }
  why = flag == "--bend" ? "--bend needs a compliance >= 0 (m/N), got" : "--shear needs a compliance >= 0 (m/N), got";
  return parse_compliance(v, flag == "--bend" ? out.bend : out.shear) ? 1 : -1;
}

}  // namespace xpbd_bullet::test::squeeze

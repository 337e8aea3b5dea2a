#include "visfield/core/text.hpp"

#include <cstdio>

namespace vf {

std::string formatted(const char* pattern, double a, double b, double c, double d) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, a, b, c, d);
  return text;
}

}  // namespace vf

#include "visfield/core/text.hpp"

#include <cstdio>

namespace vf {

std::string formatted(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

}  // namespace vf

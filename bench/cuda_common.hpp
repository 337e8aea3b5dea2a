#pragma once
/// \file Small helpers the GPU bench and figures share: printf-style formatting of one to four
/// numbers, and rays over milliseconds as G rays/s.

#include <cstddef>
#include <cstdio>
#include <string>

namespace vf::bench {

/// `pattern` (printf) applied to up to four doubles.
inline std::string format(const char* pattern, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char text[160];
  std::snprintf(text, sizeof(text), pattern, a, b, c, d);
  return text;
}

/// `rays` in `ms` milliseconds as G rays per second (0 when no time was measured).
inline double grays(std::size_t rays, double ms) { return ms > 0.0 ? static_cast<double>(rays) / (ms * 1e-3) * 1e-9 : 0.0; }

}  // namespace vf::bench

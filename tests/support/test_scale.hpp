#pragma once
/// \file How many rays the heavy tests trace: all of them normally, a fraction under the sanitizer
/// run of .ci/run (VISFIELD_TEST_SCALE in (0, 1]), which keeps every code path and scene but not the
/// full count.

#include <algorithm>
#include <cstddef>
#include <cstdlib>

namespace vf::test {

/// `n` scaled by the environment's VISFIELD_TEST_SCALE (ignored unless a number in (0, 1]), at least 1.
inline std::size_t scaled_count(std::size_t n) {
  const char* text = std::getenv("VISFIELD_TEST_SCALE");
  const double scale = text ? std::atof(text) : 1.0;
  if (!(scale > 0.0 && scale <= 1.0)) return n;
  return std::max<std::size_t>(1, static_cast<std::size_t>(static_cast<double>(n) * scale));
}

}  // namespace vf::test

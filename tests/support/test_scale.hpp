#pragma once
/// \file How many rays the heavy tests trace: all of them normally, a fraction under the sanitizer
/// run of .ci/run (VISFIELD_TEST_SCALE in (0, 1]), which keeps every code path and scene but not the
/// full count.

#include <algorithm>
#include <cstddef>
#include <cstdlib>

namespace vf::test {

/// The environment's VISFIELD_TEST_SCALE when it is a number in (0, 1], else 1.
inline double test_scale() {
  const char* text = std::getenv("VISFIELD_TEST_SCALE");
  const double scale = text ? std::atof(text) : 1.0;
  return scale > 0.0 && scale <= 1.0 ? scale : 1.0;
}

/// `n` scaled by test_scale(), at least 1.
inline std::size_t scaled_count(std::size_t n) {
  return std::max<std::size_t>(1, static_cast<std::size_t>(static_cast<double>(n) * test_scale()));
}

/// Whether configuration `i` of a test's list runs: every one normally; under the scaled-down
/// sanitizer run only every `stride`-th, the first among them, for the heaviest accuracy tests, whose
/// configurations share their code paths (the full list runs in the Release stage).
inline bool sampled(std::size_t i, std::size_t stride) { return test_scale() >= 1.0 || i % stride == 0; }

}  // namespace vf::test

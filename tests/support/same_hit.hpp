#pragma once
/// \file Bitwise comparison of hits, for tests that promise bit-identical answers.

#include <bit>
#include <cstdint>

#include "visfield/core/ray.hpp"

namespace vf::test {

/// True when two answers are bit for bit the same: hit or miss, t, u, v, triangle, object, normal.
inline bool same_bits(const Hit& a, const Hit& b) {
  const auto bits = [](float x) { return std::bit_cast<std::uint32_t>(x); };
  return a.found == b.found && bits(a.t) == bits(b.t) && bits(a.u) == bits(b.u) && bits(a.v) == bits(b.v) &&
         a.prim == b.prim && a.instance == b.instance && a.has_normal == b.has_normal &&
         bits(a.normal.x) == bits(b.normal.x) && bits(a.normal.y) == bits(b.normal.y) &&
         bits(a.normal.z) == bits(b.normal.z);
}

}  // namespace vf::test

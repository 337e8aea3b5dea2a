#pragma once
/// \file The list of exact structures every differential test runs: add a new structure here (and a
/// build_for_test specialisation in harness.hpp if it needs more than Structure::build(set)).

#include <gtest/gtest.h>

#include "visfield/accel/bvh.hpp"
#include "visfield/accel/kdtree.hpp"
#include "visfield/accel/median_bsp.hpp"
#include "visfield/accel/uniform_grid.hpp"

namespace vf::test {

/// A compile-time list of structure types, usable as GoogleTest typed-test types and in loops.
template <class... Structures>
struct StructureList {
  using GTestTypes = ::testing::Types<Structures...>;
  /// Calls f.template operator()<S>() for every structure S, in order.
  template <class F>
  static void for_each(F&& f) {
    (f.template operator()<Structures>(), ...);
  }
};

/// Every exact structure.
using ExactStructures = StructureList<Bvh, UniformGrid, KdTree, MedianBsp>;

}  // namespace vf::test

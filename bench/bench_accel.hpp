#pragma once
/// \file The structures visfield-bench can run: every exact structure of accel/ plus, when this
/// build links Embree, Embree itself, all behind one variant.

#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "visfield/accel/any_accel.hpp"
#include "visfield/core/triangle_set.hpp"

#if VISFIELD_HAVE_EMBREE
#include "embree_scene.hpp"
#endif

namespace vf::bench {

/// True when this build links Embree ("embree" is a valid --accel name).
inline constexpr bool kHaveEmbree = VISFIELD_HAVE_EMBREE != 0;

/// The --accel name of Embree.
inline constexpr const char* kEmbreeName = "embree";

/// One built structure: ours (AnyAccel) or Embree's.
#if VISFIELD_HAVE_EMBREE
using BenchAccel = std::variant<AnyAccel, EmbreeScene>;
#else
using BenchAccel = std::variant<AnyAccel>;
#endif

/// Every name --accel accepts: accel_names(), then "embree" when this build links Embree.
std::vector<std::string> bench_accel_names();

/// Builds the structure `name` (one of bench_accel_names()) over `set`; `threads` is handed to
/// Embree's device (ours follow TBB's limit). Throws vf::Error on an unknown name or a failed build.
BenchAccel build_bench_accel(const std::string& name, const TriangleSet& set, int threads);

/// Calls `f` with the concrete structure `accel` holds (a type satisfying Accelerator).
template <class F>
decltype(auto) visit_accel(const BenchAccel& accel, F&& f) {
  return std::visit(
      [&](const auto& held) -> decltype(auto) {
        if constexpr (std::is_same_v<std::decay_t<decltype(held)>, AnyAccel>) {
          return std::visit(f, held);
        } else {
          return f(held);
        }
      },
      accel);
}

/// Build statistics of whichever structure `accel` holds.
AccelStats bench_accel_stats(const BenchAccel& accel);

}  // namespace vf::bench

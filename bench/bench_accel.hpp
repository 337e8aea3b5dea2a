#pragma once
/// \file The structures visfield-bench can run: every structure of the registry plus, when this
/// build links Embree, Embree itself (flattened or with its instancing), all behind one variant.

#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "visfield/registry/registry.hpp"

#if VISFIELD_HAVE_EMBREE
#include "embree_scene.hpp"
#endif

namespace vf::bench {

/// True when this build links Embree ("embree" is a valid --accel name).
inline constexpr bool kHaveEmbree = VISFIELD_HAVE_EMBREE != 0;

/// The --accel name of Embree.
inline constexpr const char* kEmbreeName = "embree";

/// One built structure: ours (AnyStructure) or Embree's.
#if VISFIELD_HAVE_EMBREE
using BenchAccel = std::variant<AnyStructure, EmbreeScene>;
#else
using BenchAccel = std::variant<AnyStructure>;
#endif

/// Every name --accel accepts: the registry's, then "embree" when this build links Embree. Ours take,
/// beside the registry's parameters, the benchmark's `call`: batch (the default: the structure's batch
/// path) or 1 (one query a ray in the same parallel loop, a row that tells the tree's quality from the
/// batch's latency hiding).
std::vector<std::string> bench_accel_names();

/// Checks a --accel spec without building (UsageError on an unknown name, a bad parameter, or
/// "embree" in a build without Embree).
void check_bench_accel(const std::string& spec);

/// One structure built for the benchmark, with the spec as resolved.
struct BuiltBenchAccel {
  BenchAccel accel;
  std::string resolved;       ///< e.g. "bvh:levels=1", "embree:levels=2,call=1,quality=medium".
  bool best_of_spec = false;  ///< One of the rows `embree:call=best` tries; the report keeps the fastest.
  bool one_ray = false;       ///< Ours with `call=1`: one intersect()/occluded() a ray, not the batch path.
};

/// Builds the structure `spec` names over `geometry`; `threads` is handed to Embree's device (ours
/// follow TBB's limit). Throws vf::Error on a failed build, and for `embree:call=best`, which only a
/// table of rows runs (build_bench_rows).
BuiltBenchAccel build_bench_accel(const std::string& spec, SceneGeometry& geometry, const BuildContext& context, int threads);

/// The rows `spec` stands for in visfield-bench's table: build_bench_accel's one, or for
/// `embree:call=best` one per call at each build quality (each quality built once).
std::vector<BuiltBenchAccel> build_bench_rows(const std::string& spec, SceneGeometry& geometry, const BuildContext& context, int threads);

/// Calls `f` with the concrete structure `accel` holds.
template <class F>
decltype(auto) visit_accel(const BenchAccel& accel, F&& f) {
  return std::visit(
      [&](const auto& held) -> decltype(auto) {
        if constexpr (std::is_same_v<std::decay_t<decltype(held)>, AnyStructure>) {
          return std::visit(f, held);
        } else {
          return f(held);
        }
      },
      accel);
}

/// Build statistics of whichever structure `accel` holds.
AccelStats bench_accel_stats(const BenchAccel& accel);

/// Whether the structure `accel` holds answers exactly (Embree does) or approximately (fields).
bool bench_accel_is_exact(const BenchAccel& accel);

}  // namespace vf::bench

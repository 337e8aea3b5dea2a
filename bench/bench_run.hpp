#pragma once
/// \file One benchmark run, from parsed options to the printed report.

#include <ostream>
#include <vector>

#include "bench_accel.hpp"
#include "bench_options.hpp"
#include "report.hpp"

namespace vf::bench {

/// The scene's camera at the requested --width / --height (a side left at 0 keeps the camera's).
Camera bench_camera(const Scene& scene, const BenchOptions& options);

/// An upper bound of the rays the options make, for the memory checks before generating them.
std::size_t estimated_ray_count(const BenchOptions& options, const Camera& camera);

/// The options' ray set over `scene` seen by `camera`. AO and shadow rays start from the primary hits
/// of the first of `built` that is ours (exact, watertight), else of Embree.
std::vector<Ray> bench_ray_set(const BenchOptions& options, const Scene& scene, const Camera& camera,
                               const std::vector<BuiltBenchAccel>& built);

/// Loads the scene, builds every requested structure, makes the ray set, times it through each
/// structure, counts mismatches against Embree (or the first structure) and returns the report.
/// Limits TBB to options.threads while it runs. Throws vf::Error on bad input (scene file, a
/// camera that sees nothing) and UsageError when the ray set would not fit in memory.
BenchReport run_bench(const BenchOptions& options);

/// Prints `report` as the table, or as JSON when `json` is set.
void print_report(std::ostream& out, const BenchReport& report, bool json);

}  // namespace vf::bench

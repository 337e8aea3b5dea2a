#pragma once
/// \file One benchmark run, from parsed options to the printed report.

#include <ostream>

#include "bench_options.hpp"
#include "report.hpp"

namespace vf::bench {

/// Loads the scene, builds every requested structure, makes the ray set, times it through each
/// structure, counts mismatches against Embree (or the first structure) and returns the report.
/// Limits TBB to options.threads while it runs. Throws vf::Error on bad input (scene file, a
/// camera that sees nothing) and UsageError when the ray set would not fit in memory.
BenchReport run_bench(const BenchOptions& options);

/// Prints `report` as the table, or as JSON when `json` is set.
void print_report(std::ostream& out, const BenchReport& report, bool json);

}  // namespace vf::bench

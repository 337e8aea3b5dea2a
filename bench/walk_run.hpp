#pragma once
/// \file visfield-bench --walk: the scene's walkthrough rendered through each --accel structure,
/// Embree included, with each frame's update and render timed (the VLF-RT paper's Figure 6).

#include <ostream>

#include "bench_options.hpp"

namespace vf::bench {

/// Renders options.walk_frames frames of the scene's animation at the bench camera's size through
/// every structure of options.accels in turn; prints a markdown table (median update and render ms
/// per frame, Mrays/s, render time against Embree's) to `out`, and writes the CSVs and the plot the
/// options ask for. Throws vf::Error on a scene without animation or a failed build or write.
void run_walk_bench(const BenchOptions& options, std::ostream& out);

}  // namespace vf::bench

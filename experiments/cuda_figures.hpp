#pragma once
/// \file The GPU fields paper's figures on the GPU (`visfield-bench --device cuda --figure ...`):
/// gpu3 (Figure 3: AO of a ground under the caster, RMS against the GPU exact reference), gpu5
/// (Figure 5: intra-object AO of the caster, 16642 x 64^2, 121 rays per pixel, 512x512, time per
/// frame) and gpu7 (Figure 7: soft shadows from three sphere lights, RMS against the GPU exact
/// reference). Only in builds with VISFIELD_CUDA=ON.

#include <ostream>

#include "bench_options.hpp"

namespace vf::bench {

/// Runs options.figure with options.scene as the caster; markdown to `out`. Throws vf::Error.
void run_cuda_figure(const BenchOptions& options, std::ostream& out);

}  // namespace vf::bench

#pragma once
/// \file The GPU fields paper's figures on the GPU (`visfield-experiments --device cuda --figure ...`):
/// gpu3 (Figure 3: AO of a ground under the caster, RMS against the GPU exact reference), gpu5
/// (Figure 5: intra-object AO of the caster, 16642 x 64^2, 121 rays per pixel, 512x512, time per
/// frame) and gpu7 (Figure 7: soft shadows from three sphere lights, RMS against the GPU exact
/// reference). Only in builds with VISFIELD_CUDA=ON.

#include <ostream>
#include <string>

namespace vf::experiments {

/// Runs GPU figure `name` with `caster_path` as the caster, precomputing fields on `threads` CPU
/// threads (0: all); markdown to `out`. Throws vf::Error (no device, a bad mesh).
void run_cuda_figure(const std::string& name, const std::string& caster_path, int threads, std::ostream& out);

}  // namespace vf::experiments

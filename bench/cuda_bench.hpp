#pragma once
/// \file `visfield-bench --device cuda`: the bench's ray set through the GPU beside the CPU, and AO
/// rays generated on the device, with G rays/s, the GPU-vs-CPU agreement and the roofline. Only in
/// builds with VISFIELD_CUDA=ON.

#include <ostream>

#include "bench_options.hpp"

namespace vf::bench {

/// Loads the scene, builds the --accel structures (CPU) and their GPU counterparts (the GPU BVH for
/// the exact ones, the packed fields for field specs), times the ray set through both (median of
/// --reps after --warmup; a GPU time is the kernel's, rays already on the device), then --ao-rays
/// device-generated AO rays per camera hit through the fields (buffer and 3D textures) and the GPU
/// BVH against the CPU on the same rays. Prints the table (or JSON) to `out`. Throws vf::Error
/// ("no CUDA device found", bad input) and UsageError as run_bench does.
void run_cuda_bench(const BenchOptions& options, std::ostream& out);

}  // namespace vf::bench

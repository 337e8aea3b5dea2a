#pragma once
// How the kernels are launched and finished (private to the cuda module): grid-stride loops of
// 256-thread blocks, errors turned into vf::Error after a synchronising wait, and the per-point
// counts added once per group of a warp's threads that share the point.

#include <cuda_runtime.h>

#include <cstddef>
#include <cstdint>

#include "visfield/cuda/device.hpp"

namespace vf::cuda::detail {

inline constexpr int kBlockThreads = 256;

/// Blocks for `n` threads, at most 2^20 (the grid-stride loop does the rest).
inline unsigned int blocks_for(std::size_t n) {
  const std::size_t blocks = (n + kBlockThreads - 1) / kBlockThreads;
  return static_cast<unsigned int>(blocks < 1 ? 1 : (blocks > (1u << 20) ? (1u << 20) : blocks));
}

/// Waits for the launched kernel and throws vf::Error naming `what` on a launch or execution failure.
inline void finish(const char* what) {
  check(cudaGetLastError(), what);
  check(cudaDeviceSynchronize(), what);
}

/// The grid-stride loop's first index and step.
__device__ inline std::size_t first_index() { return static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x; }
__device__ inline std::size_t index_step() { return static_cast<std::size_t>(gridDim.x) * blockDim.x; }

/// q = n / d and r = n − q·d, in 32 bits whenever n fits (a 64-bit division costs several times as
/// many instructions, once per ray).
__device__ inline void divide(std::size_t n, std::size_t d, std::size_t& q, std::size_t& r) {
  if (n <= 0xffffffffu) {
    const unsigned int q32 = static_cast<unsigned int>(n) / static_cast<unsigned int>(d);
    q = q32;
    r = static_cast<unsigned int>(n) - q32 * static_cast<unsigned int>(d);
  } else {
    q = n / d;
    r = n - q * d;
  }
}

/// counts[key] += 1 for every thread of the warp here with `yes` set, one atomic per group of
/// threads with the same key (consecutive rays of one point usually share a warp).
__device__ inline void add_vote(std::uint32_t* counts, unsigned long long key, bool yes) {
  const unsigned int active = __activemask();
  const unsigned int same = __match_any_sync(active, key);
  const unsigned int votes = __ballot_sync(same, yes);
  if (votes != 0 && static_cast<int>(threadIdx.x & 31u) == __ffs(same) - 1) atomicAdd(counts + key, static_cast<unsigned int>(__popc(votes)));
}

}  // namespace vf::cuda::detail

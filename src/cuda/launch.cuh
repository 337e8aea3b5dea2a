#pragma once
// How the kernels are launched and finished (private to the cuda module): grid-stride loops of
// 256-thread blocks, the traversal stack sized to the tree, the launch timed by CUDA events when
// kernel_ms() asks, errors turned into vf::Error after a synchronising wait, and the per-point
// counts added once per group of a warp's threads that share the point.

#include <cuda_runtime.h>

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "visfield/cuda/device.hpp"
#include "visfield/cuda/kernels.hpp"
#include "visfield/gpu/bvh_traversal.hpp"
#include "visfield/gpu/field_scene_view.hpp"
#include "visfield/gpu/ray_generation.hpp"

namespace vf::cuda::detail {

inline constexpr int kBlockThreads = 256;
/// Blocks an SM should hold at once: with 256 threads, 4 blocks cap a thread at 64 registers
/// (50% occupancy on sm_90) where the traversal kernels would otherwise take 66-72 and hold 3. The
/// generic field kernels spill under that cap (68 bytes a thread); built for 3 blocks (80 registers,
/// no spills) they ran 14-15% slower on an H100 (bunny: AO 23.6 against 27.3 G rays/s spilling,
/// occlusion batch 26.4 against 31.1; the spilling figures from the previous day's run on an H100),
/// so occupancy wins there and they keep 4.
inline constexpr int kMinBlocksPerSm = 4;
/// The same for the closest-hit batch kernel over `View`. Over fields, capped at 64 registers, it
/// spilled (1.4 local-memory requests a ray) and at 80 (3 blocks) ran 8-20% faster on an H100; over
/// the exact BVH it ran 3-7% slower so, and keeps 4. A measurement build may force one count for both
/// (CMake VISFIELD_CUDA_CLOSEST_BLOCKS).
#ifdef VISFIELD_CUDA_CLOSEST_BLOCKS
template <class View>
inline constexpr int kIntersectBlocks = VISFIELD_CUDA_CLOSEST_BLOCKS;
#else
template <class View>
inline constexpr int kIntersectBlocks = std::is_same_v<View, gpu::FieldSceneView> ? 3 : kMinBlocksPerSm;
#endif

/// Blocks for `n` threads, at most 2^20 (the grid-stride loop does the rest).
inline unsigned int blocks_for(std::size_t n) {
  const std::size_t blocks = (n + kBlockThreads - 1) / kBlockThreads;
  return static_cast<unsigned int>(blocks < 1 ? 1 : (blocks > (1u << 20) ? (1u << 20) : blocks));
}

/// Whether kernel_ms() is timing this thread's launches (device.cpp).
bool kernel_clock_running();
/// Adds one launch's device milliseconds to the running kernel_ms() total.
void add_kernel_ms(double ms);

/// Launches with `launch()`, waits, and throws vf::Error naming `what` on a launch or execution
/// failure; while kernel_ms() runs, CUDA events around the launch alone add its device time.
template <class Launch>
void launch_and_finish(const char* what, Launch&& launch) {
  struct Events {
    cudaEvent_t start = nullptr, stop = nullptr;
    ~Events() {
      if (start) cudaEventDestroy(start);
      if (stop) cudaEventDestroy(stop);
    }
  } events;
  const bool timed = kernel_clock_running();
  if (timed) {
    check(cudaEventCreate(&events.start), "cudaEventCreate");
    check(cudaEventCreate(&events.stop), "cudaEventCreate");
    check(cudaEventRecord(events.start), "cudaEventRecord");
  }
  launch();
  check(cudaGetLastError(), what);
  if (timed) check(cudaEventRecord(events.stop), "cudaEventRecord");
  check(cudaDeviceSynchronize(), what);
  if (timed) {
    float ms = 0.0f;
    check(cudaEventElapsedTime(&ms, events.start, events.stop), "cudaEventElapsedTime");
    add_kernel_ms(ms);
  }
}

/// The traversal stack a view's exact part needs (BvhView::stack_bound).
inline unsigned int stack_bound(const gpu::BvhView& view) { return view.stack_bound; }
inline unsigned int stack_bound(const gpu::FieldSceneView& view) { return view.exact.stack_bound; }

/// Calls run(std::integral_constant<int, C>{}) with C the smallest of gpu::kStackCapacities that
/// holds `bound` entries, so that a kernel is instantiated with the stack its tree needs.
template <class Run>
void with_stack_capacity(unsigned int bound, Run&& run) {
  static_assert(sizeof(gpu::kStackCapacities) / sizeof(int) == 4, "one case per capacity");
  switch (gpu::stack_capacity_for(bound)) {
    case gpu::kStackCapacities[0]:
      run(std::integral_constant<int, gpu::kStackCapacities[0]>{});
      break;
    case gpu::kStackCapacities[1]:
      run(std::integral_constant<int, gpu::kStackCapacities[1]>{});
      break;
    case gpu::kStackCapacities[2]:
      run(std::integral_constant<int, gpu::kStackCapacities[2]>{});
      break;
    default:
      run(std::integral_constant<int, gpu::kStackCapacities[3]>{});
  }
}

/// Calls run(std::integral_constant<gpu::FieldForm, F>{}) with F the form the kernels are compiled
/// for: the form every field of `view` has (view.form), FieldForm::any for the exact BVH (no fields).
template <class Run>
void with_field_form(const gpu::BvhView&, Run&& run) {
  run(std::integral_constant<gpu::FieldForm, gpu::FieldForm::any>{});
}
template <class Run>
void with_field_form(const gpu::FieldSceneView& view, Run&& run) {
  if (view.form == gpu::FieldForm::defaults)
    run(std::integral_constant<gpu::FieldForm, gpu::FieldForm::defaults>{});
  else
    run(std::integral_constant<gpu::FieldForm, gpu::FieldForm::any>{});
}

/// gpu::occluded and gpu::intersect through either view, the fields read as form `Form`.
template <int Capacity, gpu::FieldForm Form, class View>
__device__ inline bool occluded_in(const View& view, const Ray& ray) {
  if constexpr (std::is_same_v<View, gpu::FieldSceneView>) return gpu::occluded<Capacity, Form>(view, ray);
  else return gpu::occluded<Capacity>(view, ray);
}
template <int Capacity, gpu::FieldForm Form, class View>
__device__ inline Hit intersect_in(const View& view, const Ray& ray) {
  if constexpr (std::is_same_v<View, gpu::FieldSceneView>) return gpu::intersect<Capacity, Form>(view, ray);
  else return gpu::intersect<Capacity>(view, ray);
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

/// AO ray k of point i: continuing p.streams[i] when kStreams, else keyed by (p.seed, i, k).
template <bool kStreams>
__device__ inline Ray ao_ray_of(const gpu::SurfaceFrame* points, std::size_t i, std::size_t k, const AoParams& p) {
  if constexpr (kStreams)
    return gpu::ao_ray(points[i], p.streams[i], k, p.max_distance);
  else
    return gpu::ao_ray(points[i], p.seed, i, k, p.max_distance);
}

/// Calls run(std::bool_constant<B>{}) with B = whether `p` has streams, so that an AO kernel is
/// instantiated for its keying (a test of p.streams per ray measured 1-2% of the keyed kernel).
template <class Run>
void with_ao_keying(const AoParams& p, Run&& run) {
  if (p.streams != nullptr)
    run(std::true_type{});
  else
    run(std::false_type{});
}

/// *out = h with every byte stored, Hit's two padding bytes too: a member-wise store leaves them
/// unwritten, and copying the array back then reads memory nothing wrote (compute-sanitizer's
/// initcheck reports it).
__device__ inline void store_hit(Hit* out, const Hit& h) {
  static_assert(sizeof(Hit) % sizeof(std::uint32_t) == 0 && alignof(Hit) >= alignof(std::uint32_t), "Hit is stored in words");
  std::uint32_t words[sizeof(Hit) / sizeof(std::uint32_t)];
  memcpy(words, &h, sizeof(Hit));
  std::uint32_t* to = reinterpret_cast<std::uint32_t*>(out);
#pragma unroll
  for (std::size_t w = 0; w < sizeof(Hit) / sizeof(std::uint32_t); ++w) to[w] = words[w];
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

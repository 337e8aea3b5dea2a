#pragma once
/// \file Occlusion rays of one tile on their way to a batch query, each with the pixel sample it
/// belongs to and what it adds there when unoccluded: AO weights, soft-shadow radiance. Traced
/// kCapacity at a time through SceneQueries::occluded_block, so an occluder with a batch path (the
/// ObjectFields' SIMD kernel) runs it; the contributions are summed per sample in the order the rays
/// were added, the order a ray-by-ray loop would sum them in, so images do not depend on batching.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "visfield/accel/scene_queries.hpp"
#include "visfield/core/vec.hpp"

namespace vf::render_detail {

/// One tile's pending occlusion rays and the per-sample sums they feed. Not thread-safe (one per tile).
class OcclusionBatch {
 public:
  static constexpr std::size_t kCapacity = 4096;
  /// Sums for `samples` pixel samples, all zero, traced through `queries`.
  OcclusionBatch(const SceneQueries& queries, std::size_t samples)
      : queries_(queries), rays_(kCapacity), runs_(kCapacity), occluded_(kCapacity), sums_(samples, Vec3f{0.0f}) {}
  /// Queues `ray`; when it turns out unoccluded, `contribution` is added to sample `of_sample`.
  void add(const Ray& ray, std::size_t of_sample, const Vec3f& contribution) { append(1, of_sample, contribution)[0] = ray; }
  /// Room for `count` (<= kCapacity) rays, queued in order, each adding `contribution` to sample
  /// `of_sample` when unoccluded; the caller writes them before the next add, append or flush.
  std::span<Ray> append(std::size_t count, std::size_t of_sample, const Vec3f& contribution) {
    if (count == 0) return {};  // no run: a run has rays, so runs_ never outgrows kCapacity
    if (queued_ + count > kCapacity) flush();
    const std::span<Ray> room(rays_.data() + queued_, count);
    queued_ += count;
    runs_[run_count_++] = Run{static_cast<std::uint32_t>(queued_), static_cast<std::uint32_t>(of_sample), contribution};
    return room;
  }
  /// Queues, for each k < wi.size() (<= kCapacity) with max_component(f_cos[k]) > 0, the ray from
  /// `origin` along wi[k] over [0, tmax[k]], adding f_cos[k] · weight · scale to sample `of_sample`
  /// when unoccluded (the products in that order); returns how many it queued. One call per chunk of
  /// a light's samples: a loop of its own keeps the batch's state in registers (inside a tile's loop
  /// it lived on the stack).
  [[gnu::noinline]] std::size_t add_weighted(const Vec3f& origin, std::span<const Vec3f> wi, const float* tmax, const Vec3f* f_cos,
                                             const Vec3f& weight, float scale, std::size_t of_sample) {
    if (queued_ + wi.size() > kCapacity) flush();
    Ray* ray = rays_.data() + queued_;
    Run* run = runs_.data() + run_count_;
    const auto sample = static_cast<std::uint32_t>(of_sample);
    std::size_t added = 0;
    for (std::size_t k = 0; k < wi.size(); ++k) {
      if (!(max_component(f_cos[k]) > 0.0f)) continue;
      ray[added] = Ray{origin, wi[k], 0.0f, tmax[k]};
      run[added] = Run{static_cast<std::uint32_t>(queued_ + added + 1), sample, f_cos[k] * weight * scale};
      ++added;
    }
    queued_ += added;
    run_count_ += added;
    return added;
  }
  /// Traces the queued rays and adds their contributions.
  void flush() {
    if (queued_ == 0) return;
    queries_.occluded_block(std::span<const Ray>(rays_.data(), queued_), std::span<std::uint8_t>(occluded_.data(), queued_));
    std::size_t i = 0;
    for (std::size_t r = 0; r < run_count_;) {
      // Summed in a local across the runs of one sample (a soft shadow's rays are a run each): through
      // memory, every add would wait on the last one's store (the answers are bytes, which may alias
      // it). Same adds in the same order.
      const std::uint32_t sample = runs_[r].sample;
      Vec3f sum = sums_[sample];
      for (; r < run_count_ && runs_[r].sample == sample; ++r)
        for (; i < runs_[r].end; ++i)
          if (!occluded_[i]) sum += runs_[r].contribution;
      sums_[sample] = sum;
    }
    queued_ = 0;
    run_count_ = 0;
  }
  /// The sum of sample `s`'s unoccluded contributions (after flush()).
  const Vec3f& sum(std::size_t s) const { return sums_[s]; }

 private:
  // Consecutive queued rays that add one contribution to one sample (an AO sample's rays are one
  // run). A record of the sample and the contribution for every ray cost a store-forwarding stall a
  // ray as GCC filled it: an eighth of an AO render through fields.
  struct Run {
    std::uint32_t end;  // one past the run's last ray; it starts where the previous run ended
    std::uint32_t sample;
    Vec3f contribution;
  };
  const SceneQueries& queries_;
  std::vector<Ray> rays_;  // kCapacity, the first queued_ of them pending
  std::size_t queued_ = 0;
  std::vector<Run> runs_;  // kCapacity (a run has at least one ray), the first run_count_ of them queued
  std::size_t run_count_ = 0;
  std::vector<std::uint8_t> occluded_;
  std::vector<Vec3f> sums_;
};

}  // namespace vf::render_detail

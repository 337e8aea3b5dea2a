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
  /// Places past the queued rays that reserve_each()'s writer may fill (whole packets of lanes).
  static constexpr std::size_t kSlack = 16;
  /// Sums for `samples` pixel samples, all zero, traced through `queries`.
  OcclusionBatch(const SceneQueries& queries, std::size_t samples) : queries_(queries), sums_(samples, Vec3f{0.0f}) { grow(kCapacity); }
  /// Queues `ray`; when it turns out unoccluded, `contribution` is added to sample `of_sample`.
  void add(const Ray& ray, std::size_t of_sample, const Vec3f& contribution) { append(1, of_sample, contribution)[0] = ray; }
  /// Room for `count` (<= kCapacity) rays, queued in order, each adding `contribution` to sample
  /// `of_sample` when unoccluded; the caller writes them before the next add, append or flush.
  std::span<Ray> append(std::size_t count, std::size_t of_sample, const Vec3f& contribution) {
    if (count == 0) return {};  // no run: a run has rays, so the runs never outnumber the rays
    if (queued_ + count > capacity_) flush();
    const std::span<Ray> room(rays_.data() + queued_, count);
    queued_ += count;
    run_end_[run_count_] = static_cast<std::uint32_t>(queued_);
    run_sample_[run_count_] = static_cast<std::uint32_t>(of_sample);
    run_contribution_[run_count_++] = contribution;
    return room;
  }
  /// Where up to `count` rays go that each add a contribution of their own: rays[k] and
  /// contributions[k], k < count + kSlack, for the caller to write; commit_each() then queues the
  /// first n. Flushes first when they would not fit; grows the batch when count > kCapacity.
  struct Room {
    Ray* rays;
    Vec3f* contributions;
  };
  Room reserve_each(std::size_t count) {
    if (queued_ + count > capacity_) flush();
    if (count > capacity_) grow(count);
    return {rays_.data() + queued_, run_contribution_.data() + run_count_};
  }
  /// Queues the first n rays written to reserve_each()'s room, each adding its contribution to
  /// sample `of_sample` when unoccluded.
  void commit_each(std::size_t n, std::size_t of_sample) {
    const auto sample = static_cast<std::uint32_t>(of_sample);
    for (std::size_t k = 0; k < n; ++k) {
      run_end_[run_count_ + k] = static_cast<std::uint32_t>(queued_ + k + 1);
      run_sample_[run_count_ + k] = sample;
    }
    queued_ += n;
    run_count_ += n;
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
      const std::uint32_t sample = run_sample_[r];
      Vec3f sum = sums_[sample];
      for (; r < run_count_ && run_sample_[r] == sample; ++r)
        for (; i < run_end_[r]; ++i)
          if (!occluded_[i]) sum += run_contribution_[r];
      sums_[sample] = sum;
    }
    queued_ = 0;
    run_count_ = 0;
  }
  /// The sum of sample `s`'s unoccluded contributions (after flush()).
  const Vec3f& sum(std::size_t s) const { return sums_[s]; }

 private:
  /// Room for `capacity` queued rays (and as many runs), plus the slack.
  void grow(std::size_t capacity) {
    capacity_ = capacity;
    rays_.resize(capacity + kSlack);
    occluded_.resize(capacity + kSlack);
    run_end_.resize(capacity + kSlack);
    run_sample_.resize(capacity + kSlack);
    run_contribution_.resize(capacity + kSlack);
  }

  const SceneQueries& queries_;
  std::size_t capacity_ = 0;
  std::vector<Ray> rays_;  // the first queued_ of them pending
  std::size_t queued_ = 0;
  // Runs: consecutive queued rays that add one contribution to one sample (an AO sample's rays are
  // one run, a soft shadow's ray a run of its own), as columns: run r ends one before run_end_[r]
  // and starts where run r − 1 ended. (A record of the sample and the contribution for every ray cost
  // a store-forwarding stall a ray as GCC filled it: an eighth of an AO render through fields.)
  std::vector<std::uint32_t> run_end_, run_sample_;
  std::vector<Vec3f> run_contribution_;
  std::size_t run_count_ = 0;
  std::vector<std::uint8_t> occluded_;
  std::vector<Vec3f> sums_;
};

}  // namespace vf::render_detail

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
  OcclusionBatch(const SceneQueries& queries, std::size_t samples) : queries_(queries), sums_(samples, Vec3f{0.0f}) {}
  /// Queues `ray`; when it turns out unoccluded, `contribution` is added to sample `of_sample`.
  void add(const Ray& ray, std::size_t of_sample, const Vec3f& contribution) {
    rays_.push_back(ray);
    sample_.push_back(static_cast<std::uint32_t>(of_sample));
    contribution_.push_back(contribution);
    if (rays_.size() == kCapacity) flush();
  }
  /// Queues every ray of `rays`, each adding `contribution` to sample `of_sample` when unoccluded.
  void add(std::span<const Ray> rays, std::size_t of_sample, const Vec3f& contribution) {
    for (std::size_t first = 0; first < rays.size();) {
      const std::size_t take = std::min(rays.size() - first, kCapacity - rays_.size());
      rays_.insert(rays_.end(), rays.begin() + static_cast<std::ptrdiff_t>(first), rays.begin() + static_cast<std::ptrdiff_t>(first + take));
      sample_.insert(sample_.end(), take, static_cast<std::uint32_t>(of_sample));
      contribution_.insert(contribution_.end(), take, contribution);
      first += take;
      if (rays_.size() == kCapacity) flush();
    }
  }
  /// Traces the queued rays and adds their contributions.
  void flush() {
    occluded_.resize(rays_.size());
    queries_.occluded_block(std::span<const Ray>(rays_), std::span<std::uint8_t>(occluded_));
    for (std::size_t i = 0; i < rays_.size(); ++i)
      if (!occluded_[i]) sums_[sample_[i]] += contribution_[i];
    rays_.clear();
    sample_.clear();
    contribution_.clear();
  }
  /// The sum of sample `s`'s unoccluded contributions (after flush()).
  const Vec3f& sum(std::size_t s) const { return sums_[s]; }

 private:
  const SceneQueries& queries_;
  std::vector<Ray> rays_;
  std::vector<std::uint32_t> sample_;
  std::vector<Vec3f> contribution_;
  std::vector<std::uint8_t> occluded_;
  std::vector<Vec3f> sums_;
};

}  // namespace vf::render_detail

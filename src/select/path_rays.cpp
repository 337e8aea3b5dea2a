#include "visfield/select/path_rays.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>

#include "visfield/core/error.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/render/camera.hpp"
#include "visfield/render/sample_rays.hpp"
#include "visfield/core/parallel.hpp"

namespace vf::detail {
namespace {

constexpr int kMaxBounces = 16;

std::size_t slots_per_path(const PathRayOptions& options) { return 2 * static_cast<std::size_t>(options.max_bounces + 1); }

}  // namespace

std::size_t path_chunk_size(std::size_t missing) { return std::clamp<std::size_t>(missing / 2, 256, 65536); }

PathChunk::PathChunk(const Scene& scene, const PathRayOptions& options, std::size_t first_path, std::size_t path_count)
    : scene_(scene), spawner_(scene), options_(options), first_path_(first_path) {
  if (options.max_bounces < 0 || options.max_bounces > kMaxBounces)
    throw Error("path rays: max_bounces must be in 0.." + std::to_string(kMaxBounces) + ", got " +
                std::to_string(options.max_bounces));
  if (scene.bounds().empty()) throw Error("path rays: the scene has no geometry");
  const PinholeCamera camera(scene.camera_or_default(0, 0));
  const std::size_t slots = slots_per_path(options);
  slots_.resize(path_count * slots);
  used_.assign(path_count * slots, 0);
  pending_.resize(path_count);
  pending_path_.resize(path_count);
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, path_count, 1024), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t p = range.begin(); p != range.end(); ++p) {
      Rng rng(options.seed, first_path + p, 0);
      const float x = rng.uniform() * static_cast<float>(camera.width());
      const float y = rng.uniform() * static_cast<float>(camera.height());
      pending_[p] = camera.generate(x, y);
      pending_path_[p] = p;
      slots_[p * slots] = pending_[p];
      used_[p * slots] = 1;
    }
  });
}

void PathChunk::advance(std::span<const Hit> hits) {
  if (hits.size() != pending_.size())
    throw Error("path rays: " + std::to_string(hits.size()) + " hits for " + std::to_string(pending_.size()) + " rays");
  const std::size_t slots = slots_per_path(options_);
  const bool bounce = depth_ < options_.max_bounces;
  const LightTargets lights(scene_);
  // Each hit may continue its path; gather the continuing ones in pending order (deterministic).
  std::vector<Ray> next(pending_.size());
  std::vector<std::uint8_t> continues(pending_.size(), 0);
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, pending_.size(), 1024), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (!hits[i]) continue;
      const std::size_t path = pending_path_[i];
      Rng rng(options_.seed, first_path_ + path, static_cast<std::uint64_t>(depth_) + 1);
      const SurfacePoint point = spawner_.surface_point(pending_[i], hits[i]);
      const std::size_t shadow_slot = path * slots + 2 * static_cast<std::size_t>(depth_) + 1;
      slots_[shadow_slot] = shadow_ray(point, lights.sample(point.position, rng));
      used_[shadow_slot] = 1;
      if (!bounce) continue;
      next[i] = ao_ray(point, rng, std::numeric_limits<float>::infinity());
      slots_[shadow_slot + 1] = next[i];
      used_[shadow_slot + 1] = 1;
      continues[i] = 1;
    }
  });
  std::vector<Ray> pending;
  std::vector<std::size_t> pending_path;
  for (std::size_t i = 0; i < next.size(); ++i) {
    if (!continues[i]) continue;
    pending.push_back(next[i]);
    pending_path.push_back(pending_path_[i]);
  }
  pending_ = std::move(pending);
  pending_path_ = std::move(pending_path);
  ++depth_;
}

void PathChunk::append_to(QuerySet& out, std::size_t limit) const {
  for (std::size_t slot = 0; slot < slots_.size() && out.size() < limit; ++slot) {
    if (!used_[slot]) continue;
    // Even slots are closest-hit rays (camera ray or bounce), odd slots the shadow ray of that hit.
    (slot % 2 == 0 ? out.closest : out.shadow).push_back(slots_[slot]);
  }
}

}  // namespace vf::detail

#include "visfield/accel/brute_force.hpp"

#include <cstdint>
#include <vector>

#include "simd/watertight_block.hpp"
#include "visfield/accel/aligned_vector.hpp"
#include "visfield/core/stopwatch.hpp"

namespace vf {
namespace brute {

constexpr int kWidth = simd::kNativeWidth;
using Block = simd::TriangleBlock<kWidth>;
using Lanes = simd::Lanes<kWidth>;

/// The triangles in SIMD blocks, in TriangleSet order (triangle i in block i / kWidth, lane i % kWidth).
struct BruteLayout {
  AlignedVector<Block> blocks;
  std::vector<std::uint32_t> prim;
  std::vector<ObjectId> instance;
  AccelStats stats;
};

}  // namespace brute

BruteForce::BruteForce(std::unique_ptr<const brute::BruteLayout> layout) : layout_(std::move(layout)) {}
BruteForce::BruteForce(BruteForce&&) noexcept = default;
BruteForce& BruteForce::operator=(BruteForce&&) noexcept = default;
BruteForce::~BruteForce() = default;

BruteForce BruteForce::build(const TriangleSet& set) {
  using brute::kWidth;
  const Stopwatch watch;
  auto layout = std::make_unique<brute::BruteLayout>();
  layout->blocks.resize((set.size() + kWidth - 1) / kWidth);
  for (std::size_t b = 0; b < layout->blocks.size(); ++b) {
    for (int lane = 0; lane < kWidth; ++lane) {
      const std::size_t i = b * kWidth + static_cast<std::size_t>(lane);
      if (i < set.size())
        layout->blocks[b].set(lane, set.triangles[i][0], set.triangles[i][1], set.triangles[i][2]);
      else
        layout->blocks[b].clear(lane);
    }
  }
  layout->prim = set.prim;
  layout->instance = set.instance;
  AccelStats& s = layout->stats;
  s.memory_bytes = layout->blocks.capacity() * sizeof(brute::Block) +
                   (layout->prim.capacity() + layout->instance.capacity()) * sizeof(std::uint32_t);
  s.leaf_count = layout->blocks.size();
  s.reference_count = set.size();
  s.build_ms = watch.elapsed_ms();
  return BruteForce(std::move(layout));
}

Hit BruteForce::intersect(const Ray& ray) const {
  using namespace brute;
  const simd::BlockRay<kWidth> block_ray{WatertightRay(ray)};
  const Lanes tmin = Lanes::broadcast(ray.tmin);
  Lanes tmax = Lanes::broadcast(ray.tmax);
  simd::BlockHits<kWidth> hits;
  float best_t = ray.tmax, best_u = 0.0f, best_v = 0.0f;
  std::size_t best = 0;
  bool found = false;
  for (std::size_t b = 0; b < layout_->blocks.size(); ++b) {
    simd::LaneBits lanes = simd::intersect_block<kWidth, true>(layout_->blocks[b], block_ray, tmin, tmax, &hits);
    if (lanes == 0) continue;
    // Lanes in increasing triangle order; a strictly smaller t is needed to replace a hit.
    for (; lanes != 0; lanes &= lanes - 1) {
      const int l = simd::first_lane(lanes);
      if (found && !(hits.t[l] < best_t)) continue;
      found = true;
      best = b * kWidth + static_cast<std::size_t>(l);
      best_t = hits.t[l];
      best_u = hits.u[l];
      best_v = hits.v[l];
    }
    tmax = Lanes::broadcast(best_t);
  }
  if (!found) return Hit{};
  return Hit::triangle(best_t, best_u, best_v, layout_->prim[best], layout_->instance[best],
                       layout_->blocks[best / kWidth].normal(static_cast<int>(best % kWidth)));
}

bool BruteForce::occluded(const Ray& ray) const {
  using namespace brute;
  const simd::BlockRay<kWidth> block_ray{WatertightRay(ray)};
  const Lanes tmin = Lanes::broadcast(ray.tmin), tmax = Lanes::broadcast(ray.tmax);
  for (const Block& block : layout_->blocks)
    if (simd::intersect_block<kWidth, false>(block, block_ray, tmin, tmax, nullptr) != 0) return true;
  return false;
}

const AccelStats& BruteForce::stats() const { return layout_->stats; }

}  // namespace vf

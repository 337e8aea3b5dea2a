#include "visfield/accel/brute_force.hpp"

#include <chrono>
#include <cstdint>
#include <vector>

#include "simd/watertight_block.hpp"
#include "visfield/accel/aligned_vector.hpp"

namespace vf {
namespace {

constexpr int kWidth = simd::kNativeWidth;
using Block = simd::TriangleBlock<kWidth>;
using Lanes = simd::Lanes<kWidth>;

}  // namespace

/// The triangles in SIMD blocks, in TriangleSet order (triangle i in block i / kWidth, lane i % kWidth).
struct BruteForce::Impl {
  AlignedVector<Block> blocks;
  std::vector<std::uint32_t> prim, instance;
  AccelStats stats;
};

BruteForce::BruteForce(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
BruteForce::BruteForce(BruteForce&&) noexcept = default;
BruteForce& BruteForce::operator=(BruteForce&&) noexcept = default;
BruteForce::~BruteForce() = default;

BruteForce BruteForce::build(const TriangleSet& set) {
  const auto start = std::chrono::steady_clock::now();
  auto impl = std::make_unique<Impl>();
  impl->blocks.resize((set.size() + kWidth - 1) / kWidth);
  for (std::size_t b = 0; b < impl->blocks.size(); ++b) {
    for (int lane = 0; lane < kWidth; ++lane) {
      const std::size_t i = b * kWidth + static_cast<std::size_t>(lane);
      if (i < set.size())
        impl->blocks[b].set(lane, set.triangles[i][0], set.triangles[i][1], set.triangles[i][2]);
      else
        impl->blocks[b].clear(lane);
    }
  }
  impl->prim = set.prim;
  impl->instance = set.instance;
  AccelStats& s = impl->stats;
  s.memory_bytes = impl->blocks.capacity() * sizeof(Block) +
                   (impl->prim.capacity() + impl->instance.capacity()) * sizeof(std::uint32_t);
  s.leaf_count = impl->blocks.size();
  s.reference_count = set.size();
  s.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return BruteForce(std::move(impl));
}

std::optional<Hit> BruteForce::intersect(const Ray& ray) const {
  const simd::BlockRay<kWidth> block_ray{WatertightRay(ray)};
  const Lanes tmin = Lanes::broadcast(ray.tmin);
  Lanes tmax = Lanes::broadcast(ray.tmax);
  simd::BlockHits<kWidth> hits;
  Hit best;
  bool found = false;
  const std::vector<std::uint32_t>& prim = impl_->prim;
  const std::vector<std::uint32_t>& instance = impl_->instance;
  for (std::size_t b = 0; b < impl_->blocks.size(); ++b) {
    simd::LaneBits lanes = simd::intersect_block<kWidth, true>(impl_->blocks[b], block_ray, tmin, tmax, &hits);
    if (lanes == 0) continue;
    // Lanes in increasing triangle order; a strictly smaller t is needed to replace a hit.
    for (; lanes != 0; lanes &= lanes - 1) {
      const int l = simd::first_lane(lanes);
      if (found && !(hits.t[l] < best.t)) continue;
      found = true;
      const std::size_t index = b * kWidth + static_cast<std::size_t>(l);
      best = Hit{hits.t[l], hits.u[l], hits.v[l], prim[index], instance[index]};
    }
    tmax = Lanes::broadcast(best.t);
  }
  if (!found) return std::nullopt;
  return best;
}

bool BruteForce::occluded(const Ray& ray) const {
  const simd::BlockRay<kWidth> block_ray{WatertightRay(ray)};
  const Lanes tmin = Lanes::broadcast(ray.tmin), tmax = Lanes::broadcast(ray.tmax);
  for (const Block& block : impl_->blocks)
    if (simd::intersect_block<kWidth, false>(block, block_ray, tmin, tmax, nullptr) != 0) return true;
  return false;
}

const AccelStats& BruteForce::stats() const { return impl_->stats; }

}  // namespace vf

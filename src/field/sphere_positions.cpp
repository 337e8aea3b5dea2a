#include "visfield/field/sphere_positions.hpp"

#include <string>

#include "visfield/core/error.hpp"

namespace vf::field {

std::size_t SpherePositions::count(int level) { return static_cast<std::size_t>(position_count(1 << level)); }

SpherePositions::SpherePositions(int level) : level_(level) {
  if (level < kMinLevel || level > kMaxLevel)
    throw Error("position level " + std::to_string(level) + ": expected " + std::to_string(kMinLevel) + ".." +
                std::to_string(kMaxLevel) + " (" + std::to_string(count(kMinLevel)) + " to " +
                std::to_string(count(kMaxLevel)) + " samples)");
  n_ = 1 << level;
  upper_.resize(static_cast<std::size_t>(octa::point_count(n_)));
  upper_float_.resize(upper_.size());
  for (int i = -n_; i <= n_; ++i) {
    const int span = n_ - (i < 0 ? -i : i);
    for (int j = -span; j <= span; ++j) {
      const auto index = static_cast<std::size_t>(octa::point_index(i, j, n_));
      upper_[index] = octa::point_direction<double>(i, j, n_);
      // Float directions are computed in float (not rounded from double), as the SIMD lookup computes them.
      upper_float_[index] = octa::point_direction<float>(i, j, n_);
    }
  }
}

hd::Vec3<double> SpherePositions::direction(std::size_t index) const {
  if (index < upper_.size()) return upper_[index];
  const hd::Vec3<double>& w = upper_[index - upper_.size()];
  return {w.x, w.y, -w.z};
}

}  // namespace vf::field

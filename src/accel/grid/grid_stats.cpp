#include "visfield/accel/grid_stats.hpp"

#include <algorithm>
#include <cmath>

namespace vf {

GridStatistics compute_grid_statistics(std::span<const std::uint32_t> cell_starts) {
  GridStatistics s;
  if (cell_starts.size() < 2) return s;
  const std::size_t t = cell_starts.size() - 1;
  const auto count = [&](std::size_t i) { return cell_starts[i + 1] - cell_starts[i]; };
  s.cell_count = t;
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < t; ++i) {
    const std::uint32_t n = count(i);
    sum += n;
    s.empty_cells += n == 0 ? 1 : 0;
    s.max_refs = std::max(s.max_refs, n);
  }
  const double cells = static_cast<double>(t);
  s.sparseness = static_cast<double>(s.empty_cells) / cells;
  s.mean = static_cast<double>(sum) / cells;
  // Central moments in a second pass (stable; the order of the sums is fixed, so deterministic).
  double m2 = 0.0, m3 = 0.0, m4 = 0.0;
  for (std::size_t i = 0; i < t; ++i) {
    const double d = static_cast<double>(count(i)) - s.mean;
    const double d2 = d * d;
    m2 += d2;
    m3 += d2 * d;
    m4 += d2 * d2;
  }
  s.variance = t > 1 ? m2 / (cells - 1.0) : 0.0;
  s.std_dev = std::sqrt(s.variance);
  if (s.std_dev > 0.0) {
    const double sigma2 = s.variance, sigma3 = sigma2 * s.std_dev;
    s.skewness = m3 / cells / sigma3;
    s.kurtosis = m4 / cells / (sigma2 * sigma2) - 3.0;
  }
  return s;
}

GridStatistics compute_grid_statistics(const UniformGrid& grid) { return compute_grid_statistics(grid.cell_starts()); }

}  // namespace vf

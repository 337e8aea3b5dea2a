#pragma once
// Synthetic scene measurements with known answers, for the arithmetic of calibration and estimation.

#include <cmath>
#include <string>
#include <vector>

#include "visfield/select/calibration.hpp"

namespace vf::test {

// A measurement that follows the cost model exactly: T_B^H = cb N log2 N, t_R^H = cr log2 N (both kinds),
// with the given grid numbers (sample time = full time).
inline SceneMeasurement model_scene(const std::string& name, std::uint64_t n, double cb, double cr_random, double cr_path,
                                    double grid_build_ms, double grid_random_us, double grid_path_us) {
  SceneMeasurement m;
  m.name = name;
  m.triangles = n;
  m.grid_resolution = {4, 5, 6};
  m.grid_memory_bytes = 1000 + n;
  m.grid_statistics.cell_count = 120;
  m.grid_statistics.empty_cells = 30;
  m.grid_statistics.sparseness = 0.25;
  m.grid_statistics.max_refs = 17;
  m.grid_statistics.mean = 2.5;
  m.grid_statistics.variance = 6.25;
  m.grid_statistics.std_dev = 2.5;
  m.grid_statistics.skewness = -0.5;
  m.grid_statistics.kurtosis = 1.75;
  m.grid_build_ms = grid_build_ms;
  const double log_n = std::log2(static_cast<double>(n));
  m.tree_build_ms = cb * static_cast<double>(n) * log_n;
  m.tree_memory_bytes = 2000 + n;
  m.rays[calibrated_kind_index(RayKind::random)] = {10000, grid_random_us, cr_random * log_n, 500, grid_random_us};
  m.rays[calibrated_kind_index(RayKind::path)] = {10000, grid_path_us, cr_path * log_n, 500, grid_path_us};
  return m;
}

}  // namespace vf::test

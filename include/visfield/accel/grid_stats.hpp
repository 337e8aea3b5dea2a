#pragma once
/// \file Statistics of a uniform grid's per-cell reference counts N_i over its t cells, with the
/// formulas of the grids-vs-hierarchies paper (Havran et al., eqs. 1-6), used to judge whether a
/// scene suits a grid.

#include <cstddef>
#include <cstdint>
#include <span>

#include "visfield/accel/uniform_grid.hpp"

namespace vf {

/// The paper's scene statistics. Plain value.
struct GridStatistics {
  std::size_t cell_count = 0;   ///< t, the number of cells.
  std::size_t empty_cells = 0;  ///< Cells with N_i = 0.
  double sparseness = 0.0;      ///< Eq. 1: empty cells / all cells, in [0, 1].
  std::uint32_t max_refs = 0;   ///< Eq. 2: max N_i.
  double mean = 0.0;            ///< Eq. 3: (1/t) sum N_i.
  double variance = 0.0;        ///< Eq. 4: 1/(t-1) sum (N_i - mean)^2 (the paper divides by t-1); 0 when t = 1.
  double std_dev = 0.0;         ///< sigma = sqrt(variance).
  double skewness = 0.0;        ///< Eq. 5: (1/t) sum ((N_i - mean)/sigma)^3; 0 when sigma = 0.
  double kurtosis = 0.0;        ///< Eq. 6: (1/t) sum ((N_i - mean)/sigma)^4 - 3 (excess kurtosis); 0 when sigma = 0.

  /// Field-by-field equality (exact, doubles included).
  bool operator==(const GridStatistics&) const = default;
};

/// Statistics of the counts N_i = cell_starts[i+1] - cell_starts[i] (t = cell_starts.size() - 1
/// cells). O(t), serial, deterministic. All zero for t = 0.
GridStatistics compute_grid_statistics(std::span<const std::uint32_t> cell_starts);

/// Statistics of `grid`'s cells; see the overload above.
GridStatistics compute_grid_statistics(const UniformGrid& grid);

}  // namespace vf

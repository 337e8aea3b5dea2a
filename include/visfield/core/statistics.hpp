#pragma once
/// \file Summary statistics of measured values.

#include <vector>

namespace vf {

/// Median of `values` (mean of the two middle ones for an even count); 0 for none. O(n log n).
double median(std::vector<double> values);

}  // namespace vf

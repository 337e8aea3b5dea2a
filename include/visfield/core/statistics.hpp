#pragma once
/// \file Summary statistics of measured values.

#include <vector>

namespace vf {

/// Median of `values` (mean of the two middle ones for an even count); 0 for none. O(n log n).
double median(std::vector<double> values);

/// Root mean square of a[i] - b[i] over the first a.size() values (b at least as long); 0 for none. O(n).
double rms_difference(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace vf

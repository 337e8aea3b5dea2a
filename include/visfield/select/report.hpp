#pragma once
/// \file The markdown report of the grids-vs-hierarchies evaluation: the paper's Table 1 for every
/// measured scene, the leave-k-out experiment and the decision accuracy for several workload sizes.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "visfield/select/calibration.hpp"
#include "visfield/select/critical_rays.hpp"

namespace vf {

/// What the report computes from the measurements.
struct ReportOptions {
  std::vector<double> decision_rays{1e4, 1e5, 1e6, 1e7};  ///< Workload sizes R of the decision table.
  std::size_t splits = 20;                                ///< Random splits per k in leave-k-out (>= 1).
  std::uint64_t seed = 1;                                 ///< Seed of the splits.
  double epsilon = kCriticalEpsilon;                      ///< The paper's epsilon.
  std::string command;                                    ///< Command line quoted in the report (empty: none).
};

/// The report as markdown, from measurements of at least two scenes (throws vf::Error otherwise).
/// Pure arithmetic on `measured`; no timing.
std::string report_markdown(const Calibration& measured, const ReportOptions& options);

}  // namespace vf

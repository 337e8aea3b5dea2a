#pragma once
/// \file How much memory this machine has, for refusing oversized requests before allocating.

#include <cstddef>

namespace vf {

/// Physical memory of this machine in bytes; 0 when the system does not say. O(1), thread-safe.
std::size_t physical_memory_bytes();

/// The most bytes one structure or ray set may take: half of physical memory (+infinity when the
/// system does not say). Requests above it are refused with a vf::Error quoting the estimate.
double allocation_budget_bytes();

}  // namespace vf

#pragma once
/// \file How much memory this machine has, for refusing oversized requests before allocating, and
/// how sizes are written in messages.

#include <cstddef>
#include <string>

namespace vf {

/// Physical memory of this machine in bytes; 0 when the system does not say. O(1), thread-safe.
std::size_t physical_memory_bytes();

/// The most bytes one structure or ray set may take: half of physical memory (+infinity when the
/// system does not say).
double allocation_budget_bytes();

/// Refuses, before allocating, a request for more than allocation_budget_bytes(): throws vf::Error
/// "<what> would need <bytes>, more than half of this machine's <memory>". Thread-safe.
void require_memory(double bytes, const std::string& what);

/// A size for people: "950 B", "12.3 KiB", "4.40 MiB", "2.50 GiB".
std::string format_bytes(double bytes);

}  // namespace vf

#include "visfield/core/memory.hpp"

#include <unistd.h>

#include <cstdio>
#include <limits>

#include "visfield/core/error.hpp"

namespace vf {

std::size_t physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return 0;
  return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page_size);
}

double allocation_budget_bytes() {
  const std::size_t bytes = physical_memory_bytes();
  return bytes == 0 ? std::numeric_limits<double>::infinity() : 0.5 * static_cast<double>(bytes);
}

void require_memory(double bytes, const std::string& what) {
  const double budget = allocation_budget_bytes();
  if (!(bytes <= budget))
    throw Error(what + " would need " + format_bytes(bytes) + ", more than half of this machine's " +
                format_bytes(2.0 * budget));
}

std::string format_bytes(double bytes) {
  constexpr double kKiB = 1024.0, kMiB = kKiB * 1024.0, kGiB = kMiB * 1024.0;
  char text[64];
  if (bytes >= kGiB) std::snprintf(text, sizeof text, "%.2f GiB", bytes / kGiB);
  else if (bytes >= kMiB) std::snprintf(text, sizeof text, "%.2f MiB", bytes / kMiB);
  else if (bytes >= kKiB) std::snprintf(text, sizeof text, "%.1f KiB", bytes / kKiB);
  else std::snprintf(text, sizeof text, "%.0f B", bytes);
  return text;
}

}  // namespace vf

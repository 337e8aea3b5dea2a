#include "visfield/core/memory.hpp"

#include <unistd.h>

#include <limits>

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

}  // namespace vf

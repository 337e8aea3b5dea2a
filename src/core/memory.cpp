#include "visfield/core/memory.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <mutex>
#include <new>
#include <sstream>

#include "visfield/core/error.hpp"

namespace vf {
namespace {

std::mutex limit_mutex;
std::optional<MemoryLimit> set_limit;

}  // namespace

std::size_t physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return 0;
  return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page_size);
}

std::size_t available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  std::size_t kib = 0;
  std::string unit;
  while (meminfo >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  return physical_memory_bytes();
}

MemoryLimit memory_limit() {
  {
    const std::lock_guard lock(limit_mutex);
    if (set_limit) return *set_limit;
  }
  const std::size_t available = available_memory_bytes();
  if (available == 0) return {std::numeric_limits<double>::infinity(), "the available memory (unknown)"};
  const auto bytes = static_cast<double>(available);
  return {bytes, "the available memory (" + format_bytes(bytes) + ")"};
}

void set_memory_limit(double bytes, const std::string& source) {
  const std::lock_guard lock(limit_mutex);
  set_limit = MemoryLimit{bytes, source};
}

void clear_memory_limit() {
  const std::lock_guard lock(limit_mutex);
  set_limit.reset();
}

void require_memory(double bytes, const std::string& what) {
  const MemoryLimit limit = memory_limit();
  if (!(bytes <= limit.bytes)) throw MemoryRefused(what + " would need about " + format_bytes(bytes) + ", more than " + limit.source);
}

std::string format_bytes(double bytes) {
  constexpr double kKiB = 1024.0, kMiB = kKiB * 1024.0, kGiB = kMiB * 1024.0, kTiB = kGiB * 1024.0;
  char text[64];
  if (bytes >= kTiB) std::snprintf(text, sizeof text, "%.2f TiB", bytes / kTiB);
  else if (bytes >= kGiB) std::snprintf(text, sizeof text, "%.2f GiB", bytes / kGiB);
  else if (bytes >= kMiB) std::snprintf(text, sizeof text, "%.2f MiB", bytes / kMiB);
  else if (bytes >= kKiB) std::snprintf(text, sizeof text, "%.1f KiB", bytes / kKiB);
  else std::snprintf(text, sizeof text, "%.0f B", bytes);
  return text;
}

std::optional<double> parse_byte_size(std::string_view text) {
  double number = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), number);
  if (ec != std::errc() || end == text.data()) return std::nullopt;
  std::string unit;
  for (const char* c = end; c != text.data() + text.size(); ++c)
    if (!std::isspace(static_cast<unsigned char>(*c))) unit += static_cast<char>(std::toupper(static_cast<unsigned char>(*c)));
  if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();                    // "GB", "GIB", "KB"
  if (unit.size() == 2 && unit.back() == 'I') unit.pop_back();                   // "GI" (from "GiB")
  double scale = 1.0;
  if (unit == "K") scale = 1024.0;
  else if (unit == "M") scale = 1024.0 * 1024.0;
  else if (unit == "G") scale = 1024.0 * 1024.0 * 1024.0;
  else if (unit == "T") scale = 1024.0 * 1024.0 * 1024.0 * 1024.0;
  else if (!unit.empty() && unit != "B") return std::nullopt;
  const double bytes = number * scale;
  if (!std::isfinite(bytes) || !(bytes > 0.0)) return std::nullopt;
  return bytes;
}

void* allocate_aligned(std::size_t bytes, std::size_t alignment) {
  if (bytes < kHugePageBytes) return ::operator new(bytes, std::align_val_t{alignment});
  // Whole huge pages, advised before anything touches them, so that the first writes fault them in.
  const std::size_t whole = (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
  void* storage = ::operator new(whole, std::align_val_t{std::max(alignment, kHugePageBytes)});
#if defined(MADV_HUGEPAGE)
  (void)madvise(storage, whole, MADV_HUGEPAGE);  // advice only: without it the pages are 4 KiB ones
#endif
  return storage;
}

void free_aligned(void* storage, std::size_t bytes, std::size_t alignment) noexcept {
  if (bytes < kHugePageBytes)
    ::operator delete(storage, std::align_val_t{alignment});
  else
    ::operator delete(storage, std::align_val_t{std::max(alignment, kHugePageBytes)});
}

}  // namespace vf

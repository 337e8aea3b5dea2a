#pragma once
/// \file The memory limit builds and ray sets are checked against before they allocate (--max-memory,
/// by default the memory available now), and how sizes are written and read.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "visfield/core/error.hpp"

namespace vf {

/// Physical memory of this machine in bytes; 0 when the system does not say. O(1), thread-safe.
std::size_t physical_memory_bytes();

/// Memory the system can give this process now without swapping (MemAvailable of /proc/meminfo),
/// else physical memory; 0 when neither is known. Reads /proc; thread-safe.
std::size_t available_memory_bytes();

/// A memory limit and the words that name it in messages ("--max-memory 4.00 GiB").
struct MemoryLimit {
  double bytes = 0.0;  ///< +infinity when nothing is known.
  std::string source;  ///< "--max-memory 4.00 GiB" or "the available memory (20.10 GiB)".
};

/// The limit in force: the last set_memory_limit(), else the available memory at the time of the
/// call. Thread-safe.
MemoryLimit memory_limit();

/// Sets the process-wide limit (the CLI's --max-memory). Thread-safe; meant for program start.
void set_memory_limit(double bytes, const std::string& source);

/// Forgets set_memory_limit(): back to the available memory (for tests).
void clear_memory_limit();

/// What require_memory() throws: a vf::Error that callers may tell apart (the C API's VF_ERROR_OUT_OF_MEMORY).
class MemoryRefused : public Error {
 public:
  explicit MemoryRefused(const std::string& message) : Error(message) {}
};

/// Refuses, before allocating, a request beyond memory_limit(): throws vf::MemoryRefused "<what> would need
/// about <bytes>, more than <source>". Thread-safe.
void require_memory(double bytes, const std::string& what);

/// A size for people: "950 B", "12.3 KiB", "4.40 MiB", "2.50 GiB".
std::string format_bytes(double bytes);

/// A size as people write it: a number with an optional unit K, M, G or T (powers of 1024; "KiB",
/// "KB", "k" and a trailing "B" all accepted), or bytes without one: "4G", "512MiB", "1.5 GB",
/// "1e9". Nothing for anything else, or for a size that is not finite and > 0.
std::optional<double> parse_byte_size(std::string_view text);

/// Arrays from this size on are placed on 2 MiB boundaries and advised to the kernel as huge pages.
inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

/// Uninitialised storage of `bytes` aligned to `alignment` (a power of two); from kHugePageBytes on,
/// aligned to kHugePageBytes and advised as transparent huge pages (Linux, where the kernel allows:
/// random reads into tables of many MiB then miss the TLB far less). Throws std::bad_alloc.
void* allocate_aligned(std::size_t bytes, std::size_t alignment);

/// Releases storage from allocate_aligned() of the same `bytes` and `alignment`.
void free_aligned(void* storage, std::size_t bytes, std::size_t alignment) noexcept;

/// How parse_byte_size's input is described in messages.
inline constexpr std::string_view kByteSizeSyntax = "a size such as 4G, 512MiB or 1e9 (bytes)";

}  // namespace vf

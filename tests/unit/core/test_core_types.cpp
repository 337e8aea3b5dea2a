#include <gtest/gtest.h>

#include <cmath>

#include "visfield/core/memory.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {
namespace {

TEST(Transform, RotationScaleTranslationRoundTrip) {
  Transform t;
  t.rotation = Mat3::euler_xyz({30.0f, -45.0f, 60.0f});
  t.translation = {1, 2, 3};
  t.scale = 2.5f;
  const Vec3f p{0.3f, -0.7f, 1.1f};
  const Vec3f back = t.inverse_point(t.apply_point(p));
  EXPECT_NEAR(back.x, p.x, 1e-5f);
  EXPECT_NEAR(back.y, p.y, 1e-5f);
  EXPECT_NEAR(back.z, p.z, 1e-5f);
  EXPECT_NEAR(length(t.apply_vector({1, 0, 0})), 2.5f, 1e-5f);
  const Vec3f z = Mat3::rotation({0, 0, 1}, 90.0f) * Vec3f{1, 0, 0};
  EXPECT_NEAR(z.y, 1.0f, 1e-6f);
}

TEST(TriangleSet, FlattenAppliesInstancesAndDropsDegenerates) {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 1, 3}, {1, 1, 2}};  // the last two have zero area
  Scene scene = scene_from_mesh(mesh);
  Instance moved;
  moved.transform.translation = {0, 0, 5};
  scene.instances.push_back(moved);
  const TriangleSet set = flatten(scene);
  ASSERT_EQ(set.size(), 2u);
  EXPECT_EQ(set.degenerate_count, 4u);
  EXPECT_EQ(set.prim[1], 0u);
  EXPECT_EQ(set.instance[1], 1u);
  EXPECT_FLOAT_EQ(set.triangles[1][0].z, 5.0f);
  EXPECT_FLOAT_EQ(set.bounds.hi.z, 5.0f);
}

TEST(Rng, SameKeysSameNumbersDifferentKeysDiffer) {
  Rng a(42, 7, 3), b(42, 7, 3), c(42, 7, 4);
  bool differs = false;
  for (int i = 0; i < 16; ++i) {
    const float x = a.uniform();
    EXPECT_EQ(x, b.uniform());
    differs |= x != c.uniform();
    EXPECT_GE(x, 0.0f);
    EXPECT_LT(x, 1.0f);
  }
  EXPECT_TRUE(differs);
}

TEST(Sampling, CosineHemisphereHasMeanCosineTwoThirds) {
  Rng rng(1);
  double sum = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const Vec3f d = cosine_hemisphere(rng.uniform(), rng.uniform());
    ASSERT_NEAR(length(d), 1.0f, 1e-4f);
    ASSERT_GE(d.z, 0.0f);
    sum += d.z;
  }
  EXPECT_NEAR(sum / n, 2.0 / 3.0, 0.005);
}

TEST(Memory, BudgetIsHalfOfPhysicalMemory) {
  const std::size_t physical = physical_memory_bytes();
  ASSERT_GT(physical, std::size_t{1} << 26);  // any machine that builds visfield has more than 64 MiB
  EXPECT_DOUBLE_EQ(allocation_budget_bytes(), 0.5 * static_cast<double>(physical));
}

}  // namespace
}  // namespace vf

#include <gtest/gtest.h>

#include "differential/test_scenes.hpp"
#include "visfield/accel/any_accel.hpp"
#include "visfield/accel/batch.hpp"
#include "visfield/core/error.hpp"

namespace vf {
namespace {

TEST(AnyAccel, NamesAndDispatch) {
  EXPECT_EQ(accel_names(), (std::vector<std::string>{"bvh", "grid", "kdtree", "median-bsp", "brute"}));
  const TriangleSet set = test::set_from_triangles(test::random_soup(31, 500, 0.05f, 0.1f));
  for (const std::string& name : accel_names()) {
    const AnyAccel accel = build_accel(name, set);
    const AccelStats s = accel_stats(accel);
    EXPECT_GE(s.reference_count, set.size()) << name;  // spatial subdivisions reference a triangle once per cell
    EXPECT_GT(s.memory_bytes, 0u) << name;
    EXPECT_GE(s.build_ms, 0.0) << name;
    const std::string held = std::visit([](const auto& a) { return a.name(); }, accel);
    EXPECT_EQ(held, name);
  }
}

TEST(AnyAccel, UnknownNameListsTheValidOnes) {
  try {
    build_accel("octree", TriangleSet{});
    FAIL() << "expected vf::Error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("octree"), std::string::npos);
    EXPECT_NE(what.find("bvh"), std::string::npos);
    EXPECT_NE(what.find("brute"), std::string::npos);
  }
}

TEST(AnyAccel, BatchQueriesMatchSingleQueries) {
  const TriangleSet set = test::set_from_triangles(test::random_soup(32, 2000, 0.02f, 0.1f));
  std::vector<Ray> rays;
  for (int i = 0; i < 1000; ++i) {
    const float s = static_cast<float>(i) / 1000.0f;
    rays.push_back(Ray{{s, 0.5f, -1.0f}, {0.0f, 0.1f * s, 1.0f}, 0.0f, i % 3 == 0 ? 1.2f : INFINITY});
  }
  for (const std::string& name : accel_names()) {
    const AnyAccel accel = build_accel(name, set);
    std::visit(
        [&](const auto& a) {
          std::vector<Hit> hits(rays.size());
          std::vector<std::uint8_t> occluded(rays.size());
          intersect_batch(a, std::span<const Ray>(rays), std::span<Hit>(hits));
          occluded_batch(a, std::span<const Ray>(rays), std::span<std::uint8_t>(occluded));
          std::size_t hit_count = 0;
          for (std::size_t i = 0; i < rays.size(); ++i) {
            const std::optional<Hit> single = a.intersect(rays[i]);
            ASSERT_EQ(hits[i].prim != kInvalidId, single.has_value()) << name << " ray " << i;
            if (single) {
              EXPECT_EQ(hits[i].t, single->t);
            }
            EXPECT_EQ(occluded[i] != 0, a.occluded(rays[i]));
            hit_count += single.has_value();
          }
          EXPECT_GT(hit_count, 100u) << name;
        },
        accel);
  }
}

}  // namespace
}  // namespace vf

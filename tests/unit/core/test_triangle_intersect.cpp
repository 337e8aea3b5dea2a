#include <gtest/gtest.h>

#include <cmath>

#include "visfield/core/rng.hpp"
#include "visfield/core/triangle_intersect.hpp"

namespace vf {
namespace {

bool hit(const Ray& ray, const Vec3f& a, const Vec3f& b, const Vec3f& c, TriangleHit* out = nullptr) {
  TriangleHit h{};
  const bool ok = intersect_triangle(WatertightRay(ray), a, b, c, ray.tmin, ray.tmax, h);
  if (out) *out = h;
  return ok;
}

TEST(TriangleIntersect, HitsInteriorWithCorrectTAndBarycentrics) {
  TriangleHit h{};
  ASSERT_TRUE(hit(Ray{{0.25f, 0.25f, -1.0f}, {0, 0, 1}}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, &h));
  EXPECT_FLOAT_EQ(h.t, 1.0f);
  EXPECT_FLOAT_EQ(h.u, 0.25f);
  EXPECT_FLOAT_EQ(h.v, 0.25f);
}

TEST(TriangleIntersect, MissesOutsideAndRespectsTRange) {
  EXPECT_FALSE(hit(Ray{{0.75f, 0.75f, -1.0f}, {0, 0, 1}}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  EXPECT_FALSE(hit(Ray{{0.25f, 0.25f, -1.0f}, {0, 0, 1}, 0.0f, 0.5f}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  EXPECT_FALSE(hit(Ray{{0.25f, 0.25f, -1.0f}, {0, 0, -1}}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  // The range is (tmin, tmax]: tmax exactly at the hit keeps it, tmin exactly at the hit drops it.
  EXPECT_TRUE(hit(Ray{{0.25f, 0.25f, -1.0f}, {0, 0, 1}, 0.0f, 1.0f}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  EXPECT_TRUE(hit(Ray{{0.25f, 0.25f, -1.0f}, {0, 0, 1}, std::nextafter(1.0f, 0.0f), 1.0f}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  EXPECT_FALSE(hit(Ray{{0.25f, 0.25f, -1.0f}, {0, 0, 1}, 1.0f, 2.0f}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  // A ray that starts on the triangle (tmin = 0) does not hit it, whichever way it leaves.
  EXPECT_FALSE(hit(Ray{{0.25f, 0.25f, 0.0f}, {0, 0, 1}}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  EXPECT_FALSE(hit(Ray{{0.25f, 0.25f, 0.0f}, {0.3f, 0.1f, -1}}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
}

TEST(TriangleIntersect, BackFacesHitToo) {
  EXPECT_TRUE(hit(Ray{{0.25f, 0.25f, -1.0f}, {0, 0, 1}}, {0, 0, 0}, {0, 1, 0}, {1, 0, 0}));
}

TEST(TriangleIntersect, SharedEdgeIsNeverMissedByBothTriangles) {
  // A quad split along its diagonal; rays aimed exactly at points on the diagonal.
  const Vec3f a{0, 0, 0}, b{1, 0, 0}, c{1, 1, 0}, d{0, 1, 0};
  Rng rng(7);
  int misses = 0;
  for (int i = 0; i < 20000; ++i) {
    const float s = rng.uniform();
    const Vec3f target{s, s, 0.0f};
    const Vec3f org{rng.uniform() * 4 - 2, rng.uniform() * 4 - 2, -1.0f - rng.uniform()};
    const Ray ray{org, target - org};
    if (!hit(ray, a, b, c) && !hit(ray, a, c, d)) ++misses;
  }
  EXPECT_EQ(misses, 0);
}

TEST(TriangleIntersect, AxisParallelAndZeroComponentDirections) {
  for (int axis = 0; axis < 3; ++axis) {
    Vec3f dir{0.0f};
    dir[axis] = 1.0f;
    Vec3f p0{0.0f}, p1{0.0f}, p2{0.0f};
    p1[(axis + 1) % 3] = 1.0f;
    p2[(axis + 2) % 3] = 1.0f;
    Vec3f org{0.2f};
    org[axis] = -3.0f;
    TriangleHit h{};
    ASSERT_TRUE(hit(Ray{org, dir}, p0, p1, p2, &h)) << "axis " << axis;
    EXPECT_FLOAT_EQ(h.t, 3.0f);
  }
}

}  // namespace
}  // namespace vf

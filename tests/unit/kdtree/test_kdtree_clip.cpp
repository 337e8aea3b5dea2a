// Perfect-split clipping: the bounds of (triangle ∩ box) against analytic values and an independent
// reference (the extreme points of a convex intersection are triangle corners in the box, triangle
// edges meeting box faces, and box edges meeting the triangle).

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "kdtree/clip.hpp"
#include "visfield/core/rng.hpp"

namespace vf {
namespace {

using Triangle = std::array<Vec3f, 3>;

struct LongPoint {
  long double p[3];
};

bool inside_box(const LongPoint& q, const Bounds3f& box, long double eps) {
  for (int a = 0; a < 3; ++a)
    if (q.p[a] < box.lo[a] - eps || q.p[a] > box.hi[a] + eps) return false;
  return true;
}

/// Exact-to-long-double bounds of triangle ∩ box from its candidate extreme points; empty bounds
/// (lo > hi) when there are none.
std::array<std::array<long double, 3>, 2> reference_bounds(const Triangle& t, const Bounds3f& box) {
  const long double eps = 1e-12L;
  std::vector<LongPoint> points;
  const auto lp = [](const Vec3f& v) { return LongPoint{{v.x, v.y, v.z}}; };
  for (const Vec3f& c : t)
    if (inside_box(lp(c), box, 0)) points.push_back(lp(c));
  // Triangle edges against the six face planes.
  for (int e = 0; e < 3; ++e) {
    const LongPoint a = lp(t[e]), b = lp(t[(e + 1) % 3]);
    for (int axis = 0; axis < 3; ++axis)
      for (const float s : {box.lo[axis], box.hi[axis]}) {
        const long double d = b.p[axis] - a.p[axis];
        if (d == 0) continue;
        const long double u = (s - a.p[axis]) / d;
        if (u < 0 || u > 1) continue;
        LongPoint q;
        for (int k = 0; k < 3; ++k) q.p[k] = a.p[k] + u * (b.p[k] - a.p[k]);
        q.p[axis] = s;
        if (inside_box(q, box, eps)) points.push_back(q);
      }
  }
  // The twelve box edges against the triangle (Möller–Trumbore in long double).
  const LongPoint p0 = lp(t[0]), p1 = lp(t[1]), p2 = lp(t[2]);
  long double e1[3], e2[3];
  for (int k = 0; k < 3; ++k) e1[k] = p1.p[k] - p0.p[k], e2[k] = p2.p[k] - p0.p[k];
  for (int axis = 0; axis < 3; ++axis)
    for (const float y : {box.lo[(axis + 1) % 3], box.hi[(axis + 1) % 3]})
      for (const float z : {box.lo[(axis + 2) % 3], box.hi[(axis + 2) % 3]}) {
        long double o[3], d[3] = {0, 0, 0};
        o[axis] = box.lo[axis];
        o[(axis + 1) % 3] = y;
        o[(axis + 2) % 3] = z;
        d[axis] = static_cast<long double>(box.hi[axis]) - box.lo[axis];
        const long double pv[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
        const long double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
        if (std::fabs(det) < 1e-30L) continue;
        const long double tv[3] = {o[0] - p0.p[0], o[1] - p0.p[1], o[2] - p0.p[2]};
        const long double u = (tv[0] * pv[0] + tv[1] * pv[1] + tv[2] * pv[2]) / det;
        const long double qv[3] = {tv[1] * e1[2] - tv[2] * e1[1], tv[2] * e1[0] - tv[0] * e1[2], tv[0] * e1[1] - tv[1] * e1[0]};
        const long double v = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) / det;
        const long double s = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det;
        if (u < 0 || v < 0 || u + v > 1 || s < 0 || s > 1) continue;
        LongPoint q;
        for (int k = 0; k < 3; ++k) q.p[k] = o[k] + s * d[k];
        points.push_back(q);
      }
  std::array<std::array<long double, 3>, 2> r;
  for (int k = 0; k < 3; ++k) r[0][k] = std::numeric_limits<long double>::infinity(), r[1][k] = -r[0][k];
  for (const LongPoint& q : points)
    for (int k = 0; k < 3; ++k) r[0][k] = std::min(r[0][k], q.p[k]), r[1][k] = std::max(r[1][k], q.p[k]);
  return r;
}

TEST(KdTreeClip, AnalyticCases) {
  // x, y >= 1 and x + y <= 4 inside [1, 3]^2: the clipped triangle spans [1, 3] x [1, 3] in z = 0.
  // Corner coordinates and clip planes are exact; interpolated ones at most one float ulp outside.
  const Triangle t{Vec3f{0, 0, 0}, Vec3f{4, 0, 0}, Vec3f{0, 4, 0}};
  const Bounds3f b = kd::clipped_triangle_bounds(t, Bounds3f{{1, 1, -1}, {3, 3, 1}});
  EXPECT_EQ(b.lo, (Vec3f{1, 1, 0}));
  EXPECT_EQ(b.hi.z, 0.0f);
  EXPECT_GE(b.hi.x, 3.0f);
  EXPECT_LE(b.hi.x, std::nextafter(3.0f, 4.0f));
  EXPECT_GE(b.hi.y, 3.0f);
  EXPECT_LE(b.hi.y, std::nextafter(3.0f, 4.0f));

  // A box cutting a sloped triangle: z = x / 2 over x in [0, 2]; clipped to x <= 1 gives z <= 0.5.
  const Triangle slope{Vec3f{0, 0, 0}, Vec3f{2, 0, 1}, Vec3f{0, 2, 0}};
  const Bounds3f s = kd::clipped_triangle_bounds(slope, Bounds3f{{-5, -5, -5}, {1, 5, 5}});
  EXPECT_EQ(s.lo, (Vec3f{0, 0, 0}));
  EXPECT_EQ(s.hi.x, 1.0f);
  EXPECT_GE(s.hi.y, 2.0f);  // the corner (0, 2, 0) is inside
  EXPECT_EQ(s.hi.y, 2.0f);
  EXPECT_GE(s.hi.z, 0.5f);
  EXPECT_LE(s.hi.z, std::nextafter(0.5f, 1.0f));

  // Inside: the triangle's own bounds. Outside: empty. Lying in a face: flat bounds in the face.
  const Bounds3f whole = kd::clipped_triangle_bounds(t, Bounds3f{{-1, -1, -1}, {5, 5, 5}});
  EXPECT_EQ(whole.lo, (Vec3f{0, 0, 0}));
  EXPECT_EQ(whole.hi, (Vec3f{4, 4, 0}));
  EXPECT_TRUE(kd::clipped_triangle_bounds(t, Bounds3f{{3, 3, -1}, {5, 5, 1}}).empty());
  EXPECT_TRUE(kd::clipped_triangle_bounds(t, Bounds3f{{0, 0, 0.5f}, {4, 4, 1}}).empty());
  const Bounds3f face = kd::clipped_triangle_bounds(t, Bounds3f{{0, 0, 0}, {1, 1, 1}});
  EXPECT_EQ(face.lo, (Vec3f{0, 0, 0}));
  EXPECT_EQ(face.hi, (Vec3f{1, 1, 0}));
  // Touching the box in one corner point only.
  const Bounds3f touch = kd::clipped_triangle_bounds(t, Bounds3f{{4, 0, 0}, {5, 1, 1}});
  EXPECT_EQ(touch.lo, (Vec3f{4, 0, 0}));
  EXPECT_EQ(touch.hi, (Vec3f{4, 0, 0}));
}

TEST(KdTreeClip, RandomTrianglesMatchTheReference) {
  Rng rng(31, 0xc1u);
  int non_empty = 0;
  for (int i = 0; i < 5000; ++i) {
    Triangle t;
    for (Vec3f& p : t) p = {4 * rng.uniform() - 2, 4 * rng.uniform() - 2, 4 * rng.uniform() - 2};
    Bounds3f box;
    box.extend(Vec3f{2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1});
    box.extend(Vec3f{2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1});
    const Bounds3f got = kd::clipped_triangle_bounds(t, box);
    const auto expected = reference_bounds(t, box);
    const bool expected_empty = expected[0][0] > expected[1][0];
    ASSERT_EQ(got.empty(), expected_empty) << "case " << i;
    if (expected_empty) continue;
    ++non_empty;
    for (int k = 0; k < 3; ++k) {
      // Conservative (contains the exact bounds, to the reference's own rounding) and tight: within
      // one float ulp plus the documented interpolation margin (2^-40 of the coordinate scale).
      const long double slack = 0x1p-22L + 0x1p-38L;  // a float ulp at |x| <= 2, plus the margin
      EXPECT_LE(got.lo[k], expected[0][k] + 1e-15L) << "case " << i << " axis " << k;
      EXPECT_GE(got.hi[k], expected[1][k] - 1e-15L) << "case " << i << " axis " << k;
      EXPECT_GE(got.lo[k], expected[0][k] - slack) << "case " << i << " axis " << k;
      EXPECT_LE(got.hi[k], expected[1][k] + slack) << "case " << i << " axis " << k;
      EXPECT_GE(got.lo[k], box.lo[k]);
      EXPECT_LE(got.hi[k], box.hi[k]);
    }
  }
  EXPECT_GT(non_empty, 1000);
}

}  // namespace
}  // namespace vf

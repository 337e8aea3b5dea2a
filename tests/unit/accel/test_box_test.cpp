// The BVH's ray-box test: conservative (never culls a box the ray meets), exact for rays with
// zero direction components lying in a box's plane, and empty slots never hit.

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "bvh/box_test.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"

namespace vf::bvh {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

BoxRay box_ray(const Ray& ray) {
  const float inv[3] = {1.0f / ray.dir.x, 1.0f / ray.dir.y, 1.0f / ray.dir.z};
  BoxRay r;
  r.set(ray, inv);
  return r;
}

simd::LaneBits hits(const Node8& node, const Ray& ray) {
  V8 t_near;
  return test_children(node, box_ray(ray), V8::broadcast(widen_down(ray.tmin)), V8::broadcast(widen_up(ray.tmax)),
                       t_near);
}

// Exact slab test in double precision (the reference the float test must never undercut).
bool meets_exactly(const Bounds3f& b, const Ray& ray) {
  double t0 = ray.tmin, t1 = ray.tmax;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.org[a], d = ray.dir[a], lo = b.lo[a], hi = b.hi[a];
    if (d == 0.0) {
      if (o < lo || o > hi) return false;
      continue;
    }
    double n = (lo - o) / d, f = (hi - o) / d;
    if (n > f) std::swap(n, f);
    t0 = std::max(t0, n);
    t1 = std::min(t1, f);
  }
  return t0 <= t1;
}

TEST(BoxTest, RaysInABoxPlaneWithZeroDirectionComponentEnter) {
  Node8 node = Node8::empty();
  node.set_bounds(0, Bounds3f{{0, 0, 5}, {1, 1, 6}});
  for (const float zero : {0.0f, -0.0f}) {
    // In the planes x = 0 and x = 1 (faces of the box), moving along +z: the ray runs on a face.
    EXPECT_EQ(hits(node, Ray{{0, 0.5f, 0}, {zero, 0, 1}}), 1u) << "zero " << zero;
    EXPECT_EQ(hits(node, Ray{{1, 0.5f, 0}, {zero, 0, 1}}), 1u) << "zero " << zero;
    // Along an edge of the box (two zero components).
    EXPECT_EQ(hits(node, Ray{{1, 1, 0}, {zero, zero, 1}}), 1u) << "zero " << zero;
    // Just outside the face: misses.
    EXPECT_EQ(hits(node, Ray{{std::nextafter(1.0f, 2.0f), 0.5f, 0}, {zero, 0, 1}}), 0u) << "zero " << zero;
    EXPECT_EQ(hits(node, Ray{{std::nextafter(0.0f, -1.0f), 0.5f, 0}, {zero, 0, 1}}), 0u) << "zero " << zero;
    // Moving away from the box.
    EXPECT_EQ(hits(node, Ray{{0, 0.5f, 0}, {zero, 0, -1}}), 0u) << "zero " << zero;
  }
}

TEST(BoxTest, OriginOnTheFarFaceStillEntersAtZero) {
  Node8 node = Node8::empty();
  node.set_bounds(0, Bounds3f{{0, 0, 0}, {1, 1, 1}});
  EXPECT_EQ(hits(node, Ray{{0.5f, 0.5f, 1.0f}, {0.3f, -0.2f, 1.0f}}), 1u);
  EXPECT_EQ(hits(node, Ray{{0.5f, 0.5f, 1.0f}, {0.3f, -0.2f, 1.0f}, 1e-3f}), 0u);
  // tmax exactly at the entry distance: inclusive.
  EXPECT_EQ(hits(node, Ray{{0.5f, 0.5f, -2.0f}, {0, 0, 1}, 0.0f, 2.0f}), 1u);
}

TEST(BoxTest, EmptySlotsNeverHit) {
  const Node8 node = Node8::empty();
  for (const Vec3f& dir : {Vec3f{1, 0, 0}, Vec3f{0, -1, 0}, Vec3f{0, 0, 0.5f}, Vec3f{1, 2, 3}})
    EXPECT_EQ(hits(node, Ray{{0, 0, 0}, dir}), 0u);
}

TEST(BoxTest, NeverCullsABoxTheRayMeetsExactly) {
  // Random boxes (tiny to large, near and far) and rays aimed at points on or near them; whenever
  // the exact test says the ray meets the box, the float test must report it.
  Rng rng(99);
  int exact_hits = 0;
  for (int iter = 0; iter < 20000; ++iter) {
    Node8 node = Node8::empty();
    Bounds3f boxes[8];
    const float offset = std::pow(10.0f, -2.0f + 5.0f * rng.uniform());
    for (int slot = 0; slot < 8; ++slot) {
      const float size = std::pow(10.0f, -6.0f + 7.0f * rng.uniform());
      const Vec3f c = Vec3f{rng.uniform(), rng.uniform(), rng.uniform()} * offset;
      Vec3f e{size * rng.uniform(), size * rng.uniform(), size * rng.uniform()};
      if (slot % 4 == 0) e[slot % 3] = 0.0f;  // flat boxes (axis-aligned triangles)
      boxes[slot] = Bounds3f{c - e, c + e};
      node.set_bounds(slot, boxes[slot]);
    }
    const Bounds3f& target = boxes[rng.next_u32() % 8];
    // A point on the target's boundary or inside it.
    Vec3f p;
    for (int a = 0; a < 3; ++a) {
      const float u = rng.uniform();
      p[a] = u < 0.25f ? target.lo[a] : (u < 0.5f ? target.hi[a] : target.lo[a] + (target.hi[a] - target.lo[a]) * u);
    }
    Vec3f dir = uniform_sphere(rng.uniform(), rng.uniform());
    if (iter % 7 == 0) dir[static_cast<int>(rng.next_u32() % 3)] = 0.0f;
    const float back = offset * (0.5f + rng.uniform());
    Ray ray{p - dir * back, dir};
    if (iter % 3 == 0) ray.tmax = back;  // ends exactly at the point
    const simd::LaneBits got = hits(node, ray);
    for (int slot = 0; slot < 8; ++slot) {
      if (!meets_exactly(boxes[slot], ray)) continue;
      ++exact_hits;
      ASSERT_TRUE((got >> slot) & 1u) << "iteration " << iter << " slot " << slot;
    }
  }
  EXPECT_GT(exact_hits, 20000);
}

#if defined(__AVX512F__) && defined(__AVX512DQ__)
TEST(BoxTest, NeverCullsABoxBehindTheOriginThatAnIntervalReachingBackMeets) {
  // Far distances below zero: scaled up by 1 + 2^-16 they would move down, culling flat boxes wholly
  // behind the origin (a unit cube's face, met at t = -5 from x = 5 along +x).
  Node8 face = Node8::empty();
  face.set_bounds(0, Bounds3f{{0, 0, 0}, {0, 1, 1}});
  Ray along{{5, 0.5f, 0.5f}, {1, 0, 0}};
  along.tmin = -100.0f;
  EXPECT_EQ(hits(face, along), 1u);
  // Random boxes, flat ones among them, and rays that passed a point of one before their origin.
  Rng rng(7);
  int exact_hits = 0;
  for (int iter = 0; iter < 20000; ++iter) {
    Node8 node = Node8::empty();
    Bounds3f boxes[8];
    for (int slot = 0; slot < 8; ++slot) {
      const float size = std::pow(10.0f, -4.0f + 4.0f * rng.uniform());
      const Vec3f c{rng.uniform(), rng.uniform(), rng.uniform()};
      Vec3f e{size * rng.uniform(), size * rng.uniform(), size * rng.uniform()};
      if (slot % 2 == 0) e[slot % 3] = 0.0f;
      boxes[slot] = Bounds3f{c - e, c + e};
      node.set_bounds(slot, boxes[slot]);
    }
    const Bounds3f& target = boxes[rng.next_u32() % 8];
    Vec3f p;
    for (int a = 0; a < 3; ++a) p[a] = rng.uniform() < 0.5f ? target.lo[a] : target.hi[a];
    Vec3f dir = uniform_sphere(rng.uniform(), rng.uniform());
    if (iter % 2 == 0) dir = Vec3f{0, 0, 0}, dir[static_cast<int>(rng.next_u32() % 3)] = rng.uniform() < 0.5f ? -1.0f : 1.0f;
    const float ahead = 2.0f + rng.uniform();
    Ray ray{p + dir * ahead, dir};
    ray.tmin = -ahead * (iter % 3 == 0 ? 1.0f : 1.5f);  // from the point exactly, or from farther back
    ray.tmax = iter % 5 == 0 ? -0.5f : kInf;
    const simd::LaneBits got = hits(node, ray);
    for (int slot = 0; slot < 8; ++slot) {
      if (!meets_exactly(boxes[slot], ray)) continue;
      ++exact_hits;
      ASSERT_TRUE((got >> slot) & 1u) << "iteration " << iter << " slot " << slot;
    }
  }
  EXPECT_GT(exact_hits, 20000);
}

TEST(BoxTest, ADirectionComponentWhoseReciprocalOverflowsRestrictsNothing) {
  // From y = -1e-45 at 1e-45 a unit the ray reaches y = 0 at t = 1; 1 / 1e-45 overflows to inf, which
  // would put that plane at t = inf. box_reciprocal() makes it NaN: the axis does not restrict.
  EXPECT_TRUE(std::isnan(box_reciprocal(1e-45f)));
  EXPECT_TRUE(std::signbit(box_reciprocal(-1e-45f)));
  EXPECT_EQ(box_reciprocal(0.0f), kInf);
  EXPECT_EQ(box_reciprocal(-0.0f), -kInf);
  EXPECT_EQ(box_reciprocal(4.0f), 0.25f);
  Node8 node = Node8::empty();
  node.set_bounds(0, Bounds3f{{0, 0, 0}, {1, 1, 1}});
  EXPECT_EQ(hits(node, Ray{{2, -1e-45f, 0.5f}, {-1, 1e-45f, 0}}), 1u);
}

TEST(BoxTest, SixteenRaysAgainstOneBoxDecideAsOneRayAgainstEight) {
  // rays_meet_child() must give each ray test_children()'s bit, edge cases included: rays that meet
  // a box at their origin alone (t_near == t_far == 0), rays ending exactly on it, rays in a
  // face's plane with a zero (or negative zero) direction component, flat and empty boxes.
  Rng rng(5);
  int hits_seen = 0, touching = 0;
  for (int iter = 0; iter < 4000; ++iter) {
    Node8 node = Node8::empty();
    Bounds3f boxes[8];
    for (int slot = 0; slot < 7; ++slot) {  // slot 7 stays empty
      const Vec3f c{rng.uniform() * 4 - 2, rng.uniform() * 4 - 2, rng.uniform() * 4 - 2};
      Vec3f e{rng.uniform(), rng.uniform(), rng.uniform()};
      if (slot == 3) e[iter % 3] = 0.0f;
      boxes[slot] = Bounds3f{c - e, c + e};
      node.set_bounds(slot, boxes[slot]);
    }
    alignas(64) float columns[8][16];
    Ray rays[16];
    for (int lane = 0; lane < 16; ++lane) {
      const Bounds3f& b = boxes[rng.next_u32() % 7];
      Ray ray{{rng.uniform() * 6 - 3, rng.uniform() * 6 - 3, rng.uniform() * 6 - 3}, uniform_sphere(rng.uniform(), rng.uniform())};
      const int axis = static_cast<int>(rng.next_u32() % 3);
      switch (lane % 4) {
        case 1: {  // from a point of a face, leaving the box: it meets it at t = 0 alone
          for (int a = 0; a < 3; ++a) ray.org[a] = b.lo[a] + (b.hi[a] - b.lo[a]) * rng.uniform();
          const bool high = rng.uniform() < 0.5f;
          ray.org[axis] = high ? b.hi[axis] : b.lo[axis];
          ray.dir[axis] = high ? std::fabs(ray.dir[axis]) + 0.1f : -std::fabs(ray.dir[axis]) - 0.1f;
          break;
        }
        case 2:  // in a face's plane, a zero direction component
          ray.org[axis] = rng.uniform() < 0.5f ? b.lo[axis] : b.hi[axis];
          ray.dir[axis] = rng.uniform() < 0.5f ? 0.0f : -0.0f;
          break;
        case 3:  // ending where it enters
          ray.tmax = 0.5f * rng.uniform();
          break;
        default:
          break;
      }
      rays[lane] = ray;
      for (int a = 0; a < 3; ++a) {
        columns[a][lane] = ray.org[a];
        columns[3 + a][lane] = ray.dir[a];
      }
      columns[6][lane] = ray.tmin;  // widened by the load
      columns[7][lane] = ray.tmax;
    }
    const float* const column[8] = {columns[0], columns[1], columns[2], columns[3], columns[4], columns[5], columns[6], columns[7]};
    BoxRays16 packet;
    packet.load(column, 0);
    for (int slot = 0; slot < 8; ++slot) {
      const __mmask16 lanes = rays_meet_child(node, slot, packet);
      for (int lane = 0; lane < 16; ++lane) {
        const bool one = (hits(node, rays[lane]) >> slot) & 1u;
        ASSERT_EQ(((lanes >> lane) & 1u) != 0, one) << "iteration " << iter << " slot " << slot << " lane " << lane;
        hits_seen += one ? 1 : 0;
      }
    }
    // The origin-on-a-face rays: at least some meet their box at t = 0 exactly, where <= and < differ.
    for (int lane = 1; lane < 16; lane += 4)
      for (int slot = 0; slot < 7; ++slot) {
        const Ray& ray = rays[lane];
        bool on_face = true;
        for (int a = 0; a < 3; ++a) on_face = on_face && ray.org[a] >= boxes[slot].lo[a] && ray.org[a] <= boxes[slot].hi[a];
        touching += on_face && ((hits(node, ray) >> slot) & 1u) ? 1 : 0;
      }
  }
  EXPECT_GT(hits_seen, 20000);
  EXPECT_GT(touching, 10000);
}
#endif

}  // namespace
}  // namespace vf::bvh

// The SIMD block test is bit-identical to the scalar intersect_triangle(), lane by lane, at every width.

#include <bit>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "simd/watertight_block.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"

namespace vf {
namespace {

using Triangle = std::array<Vec3f, 3>;

struct Case {
  Ray ray;
  Triangle triangle;
};

Vec3f random_in(Rng& rng, float scale) {
  return Vec3f{rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f} * scale;
}

// Random and adversarial (ray, triangle) pairs: random, rays through corners and edge points (many
// exact zero edge values, the double fallback), axis-parallel and zero-component directions,
// grazing rays, tmin/tmax exactly at the hit, tiny and huge triangles.
std::vector<Case> make_cases(std::uint64_t seed, std::size_t n) {
  Rng rng(seed);
  std::vector<Case> cases;
  while (cases.size() < n) {
    const float scale = std::pow(10.0f, -4.0f + 7.0f * rng.uniform());
    Triangle t{random_in(rng, scale), random_in(rng, scale), random_in(rng, scale)};
    const Vec3f target_vertex = t[rng.next_u32() % 3];
    const Vec3f target_edge = t[0] + (t[1] - t[0]) * rng.uniform();
    const Vec3f target_inside = t[0] + (t[1] - t[0]) * 0.3f + (t[2] - t[0]) * 0.3f;
    const Vec3f org = random_in(rng, 4 * scale);
    Vec3f axis_dir{0.0f};
    axis_dir[static_cast<int>(rng.next_u32() % 3)] = rng.uniform() < 0.5f ? -1.0f : 1.0f;
    Vec3f axis_org = target_vertex - axis_dir * scale;
    switch (cases.size() % 10) {
      case 9: {  // huge coordinates: edge products overflow to inf (NaN edge values), often with exact zeros
        const float huge = std::ldexp(1.0f, 60 + static_cast<int>(rng.next_u32() % 10));
        Triangle g{Vec3f{0, 0, 0}, Vec3f{huge, 0, 0}, Vec3f{0, huge, 0}};
        if (rng.uniform() < 0.5f) g[2].z = huge * rng.uniform();
        const Vec3f through = g[rng.next_u32() % 3];
        cases.push_back({Ray{through - Vec3f{0.25f, 0.5f, 1.0f} * huge, Vec3f{0.25f, 0.5f, 1.0f}}, g});
        break;
      }
      case 0: cases.push_back({Ray{org, uniform_sphere(rng.uniform(), rng.uniform())}, t}); break;
      case 1: cases.push_back({Ray{org, target_vertex - org}, t}); break;
      case 2: cases.push_back({Ray{org, target_edge - org}, t}); break;
      case 3: cases.push_back({Ray{axis_org, axis_dir}, t}); break;
      case 4: {  // zero component direction, org through an inner point
        Vec3f dir = uniform_sphere(rng.uniform(), rng.uniform());
        dir[static_cast<int>(rng.next_u32() % 3)] = 0.0f;
        cases.push_back({Ray{target_inside - dir * scale, dir}, t});
        break;
      }
      case 5: cases.push_back({Ray{t[0] - (t[1] - t[0]) * 0.5f, t[1] - t[0]}, t}); break;  // along an edge line
      case 6: {  // integer grid: exact zero edge values are common
        Triangle g{Vec3f{0, 0, 0}, Vec3f{float(rng.next_u32() % 4), 1, 0}, Vec3f{0, float(1 + rng.next_u32() % 3), 1}};
        cases.push_back({Ray{Vec3f{float(rng.next_u32() % 3), float(rng.next_u32() % 3), -2}, Vec3f{0, 0, 1}}, g});
        break;
      }
      default: {  // tmin or tmax exactly at the scalar hit
        Ray r{org, target_inside - org};
        TriangleHit h{};
        if (intersect_triangle(WatertightRay(r), t[0], t[1], t[2], r.tmin, r.tmax, h)) {
          if (cases.size() % 2) r.tmax = h.t; else r.tmin = h.t;
        }
        cases.push_back({r, t});
      }
    }
  }
  return cases;
}

template <int W>
void expect_bit_identical(std::uint64_t seed, std::size_t n, std::size_t* hits_seen) {
  // Each case's ray is tested against a block holding its triangle in a rotating lane, the other
  // lanes filled with triangles of neighbouring cases (and one empty lane now and then).
  const std::vector<Case> cases = make_cases(seed, n);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Ray& ray = cases[i].ray;
    simd::TriangleBlock<W> block;
    for (int lane = 0; lane < W; ++lane) {
      const Triangle& t = cases[(i + static_cast<std::size_t>(lane)) % cases.size()].triangle;
      if (lane == W - 1 && i % 5 == 0) block.clear(lane); else block.set(lane, t[0], t[1], t[2]);
    }
    const WatertightRay wr(ray);
    const simd::BlockRay<W> block_ray(wr);
    const auto tmin = simd::Lanes<W>::broadcast(ray.tmin), tmax = simd::Lanes<W>::broadcast(ray.tmax);
    simd::BlockHits<W> hits;
    const simd::LaneBits mask = simd::intersect_block<W, true>(block, block_ray, tmin, tmax, &hits);
    const simd::LaneBits mask_only = simd::intersect_block<W, false>(block, block_ray, tmin, tmax, nullptr);
    ASSERT_EQ(mask, mask_only);
    for (int lane = 0; lane < W; ++lane) {
      const bool empty = lane == W - 1 && i % 5 == 0;
      const Triangle& t = cases[(i + static_cast<std::size_t>(lane)) % cases.size()].triangle;
      TriangleHit expected{};
      const bool scalar_hit = !empty && intersect_triangle(wr, t[0], t[1], t[2], ray.tmin, ray.tmax, expected);
      ASSERT_EQ(((mask >> lane) & 1u) != 0, scalar_hit) << "W=" << W << " case " << i << " lane " << lane;
      if (!scalar_hit) continue;
      ++*hits_seen;
      EXPECT_EQ(std::bit_cast<std::uint32_t>(hits.t[lane]), std::bit_cast<std::uint32_t>(expected.t));
      EXPECT_EQ(std::bit_cast<std::uint32_t>(hits.u[lane]), std::bit_cast<std::uint32_t>(expected.u));
      EXPECT_EQ(std::bit_cast<std::uint32_t>(hits.v[lane]), std::bit_cast<std::uint32_t>(expected.v));
    }
  }
}

TEST(WatertightBlock, BitIdenticalToScalarAtEveryWidth) {
  std::size_t hits = 0;
  expect_bit_identical<2>(1, 20000, &hits);   // portable lanes
  expect_bit_identical<4>(2, 20000, &hits);   // SSE
  expect_bit_identical<8>(3, 20000, &hits);   // AVX
  expect_bit_identical<16>(4, 20000, &hits);  // AVX-512
  EXPECT_GT(hits, 20000u);  // the comparison covered many hits, not just misses
}

TEST(WatertightBlock, DoubleFallbackLanesMatchScalar) {
  // Rays exactly through a corner or along an edge of integer triangles make float edge values
  // exactly zero, which sends those lanes through the double-precision fallback.
  std::size_t hits = 0;
  simd::TriangleBlock<8> block;
  const Triangle tris[8] = {
      {Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}}, {Vec3f{1, 0, 0}, Vec3f{1, 1, 0}, Vec3f{0, 1, 0}},
      {Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, Vec3f{-1, 0, 0}}, {Vec3f{0, 0, 0}, Vec3f{-1, 0, 0}, Vec3f{0, -1, 0}},
      {Vec3f{0, 0, 0}, Vec3f{0, -1, 0}, Vec3f{1, 0, 0}}, {Vec3f{0, 0, 1}, Vec3f{1, 0, 1}, Vec3f{0, 1, 1}},
      {Vec3f{2, 2, 0}, Vec3f{3, 2, 0}, Vec3f{2, 3, 0}},  {Vec3f{0, 0, 0}, Vec3f{2, 2, 0}, Vec3f{0, 2, 0}}};
  for (int lane = 0; lane < 8; ++lane) block.set(lane, tris[lane][0], tris[lane][1], tris[lane][2]);
  const Vec3f targets[] = {Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0.5f, 0.5f, 0}, Vec3f{0, 0.5f, 0}, Vec3f{1, 1, 0}};
  for (const Vec3f& target : targets) {
    for (const Vec3f& dir : {Vec3f{0, 0, 1}, Vec3f{0, 0, -1}, Vec3f{1, 1, 4}, Vec3f{0, 1, 2}}) {
      const Ray ray{target - dir * 3.0f, dir};
      const WatertightRay wr(ray);
      simd::BlockHits<8> out;
      const simd::LaneBits mask = simd::intersect_block<8, true>(
          block, simd::BlockRay<8>(wr), simd::Lanes<8>::broadcast(0.0f), simd::Lanes<8>::broadcast(INFINITY), &out);
      for (int lane = 0; lane < 8; ++lane) {
        TriangleHit h{};
        const bool scalar_hit = intersect_triangle(wr, tris[lane][0], tris[lane][1], tris[lane][2], 0.0f, INFINITY, h);
        ASSERT_EQ(((mask >> lane) & 1u) != 0, scalar_hit);
        if (!scalar_hit) continue;
        ++hits;
        EXPECT_EQ(std::bit_cast<std::uint32_t>(out.t[lane]), std::bit_cast<std::uint32_t>(h.t));
        EXPECT_EQ(std::bit_cast<std::uint32_t>(out.u[lane]), std::bit_cast<std::uint32_t>(h.u));
        EXPECT_EQ(std::bit_cast<std::uint32_t>(out.v[lane]), std::bit_cast<std::uint32_t>(h.v));
      }
    }
  }
  // Every ray passes through a shared corner or edge: at least one triangle must report it.
  EXPECT_GE(hits, 20u);
}

TEST(WatertightBlock, OverflowingEdgeValueRecoveredByTheDoubleFallback) {
  // A thin triangle with corners near 2^65: in float one edge product overflows (inf - inf = NaN)
  // while the ray through corner 0 makes the other two edge values exactly zero. The scalar test
  // recomputes all three in double, where they are finite, and reports a hit at corner 0; the
  // block test must do the same rather than drop the NaN lane.
  const float h = 0x1p65f;
  const Triangle thin{Vec3f{0, 0, 0}, Vec3f{h, h, 0}, Vec3f{h, h * (1.0f + 0x1p-20f), 0}};
  const Ray ray{{0, 0, -1}, {0, 0, 1}};
  const WatertightRay wr(ray);
  TriangleHit expected{};
  ASSERT_TRUE(intersect_triangle(wr, thin[0], thin[1], thin[2], ray.tmin, ray.tmax, expected));
  simd::TriangleBlock<8> block;
  for (int lane = 0; lane < 8; ++lane) block.set(lane, thin[0], thin[1], thin[2]);
  block.clear(7);
  simd::BlockHits<8> out;
  const simd::LaneBits mask = simd::intersect_block<8, true>(
      block, simd::BlockRay<8>(wr), simd::Lanes<8>::broadcast(0.0f), simd::Lanes<8>::broadcast(INFINITY), &out);
  EXPECT_EQ(mask, 0x7fu);
  EXPECT_EQ(std::bit_cast<std::uint32_t>(out.t[0]), std::bit_cast<std::uint32_t>(expected.t));
}

}  // namespace
}  // namespace vf

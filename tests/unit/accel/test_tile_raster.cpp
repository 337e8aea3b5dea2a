// BeamField's conservative rasterisation against an exact, independently formulated overlap test
// (a vertex of either shape inside the other, or two edges crossing), on random triangles, slivers,
// triangles seen edge-on, points, corners and edges exactly on tile borders, and triangles reaching
// outside the grid. Coordinates are multiples of 1/256 in a small range, so every product is exact
// in double and "touches" has one answer.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "beam_field/tile_raster.hpp"
#include "visfield/core/rng.hpp"

namespace vf::beam {
namespace {

double orient(Point2 o, Point2 p, Point2 q) { return (p.s - o.s) * (q.t - o.t) - (p.t - o.t) * (q.s - o.s); }

bool on_segment(Point2 p, Point2 q, Point2 x) {
  return orient(p, q, x) == 0.0 && std::min(p.s, q.s) <= x.s && x.s <= std::max(p.s, q.s) && std::min(p.t, q.t) <= x.t &&
         x.t <= std::max(p.t, q.t);
}

bool segments_meet(Point2 a, Point2 b, Point2 c, Point2 d) {
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return true;
  return on_segment(a, b, c) || on_segment(a, b, d) || on_segment(c, d, a) || on_segment(c, d, b);
}

bool in_triangle(Point2 a, Point2 b, Point2 c, Point2 p) {
  if (orient(a, b, c) == 0.0) return on_segment(a, b, p) || on_segment(b, c, p) || on_segment(c, a, p);
  const double o1 = orient(a, b, p), o2 = orient(b, c, p), o3 = orient(c, a, p);
  return (o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0);
}

// The closed triangle and the closed square [s0, s1] × [t0, t1] share a point.
bool overlaps(Point2 a, Point2 b, Point2 c, double s0, double t0, double s1, double t1) {
  const Point2 tri[3] = {a, b, c};
  const Point2 sq[4] = {{s0, t0}, {s1, t0}, {s1, t1}, {s0, t1}};
  for (const Point2& p : tri)
    if (s0 <= p.s && p.s <= s1 && t0 <= p.t && p.t <= t1) return true;
  for (const Point2& p : sq)
    if (in_triangle(a, b, c, p)) return true;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      if (segments_meet(tri[i], tri[(i + 1) % 3], sq[j], sq[(j + 1) % 4])) return true;
  return false;
}

std::vector<std::uint32_t> exact_tiles(const TileGrid& g, Point2 a, Point2 b, Point2 c) {
  std::vector<std::uint32_t> out;
  for (int y = 0; y < g.n; ++y)
    for (int x = 0; x < g.n; ++x) {
      const double s0 = g.lo_s + x * g.size, t0 = g.lo_t + y * g.size;
      if (overlaps(a, b, c, s0, t0, s0 + g.size, t0 + g.size)) out.push_back(static_cast<std::uint32_t>(y * g.n + x));
    }
  return out;
}

constexpr TileGrid kGrid{-2.0, -1.5, 0.5, 16};  // [-2, 6) × [-1.5, 6.5)

// A multiple of 1/256 in [lo, hi].
double dyadic(Rng& rng, double lo, double hi) {
  const auto steps = static_cast<std::uint32_t>((hi - lo) * 256.0);
  return lo + static_cast<double>(rng.next_u32() % (steps + 1)) / 256.0;
}

void expect_exact(Point2 a, Point2 b, Point2 c, const char* kind, int& failures) {
  std::vector<std::uint32_t> got;
  rasterize_triangle(kGrid, a, b, c, 0.0, got);
  const std::vector<std::uint32_t> expected = exact_tiles(kGrid, a, b, c);
  if (got != expected && ++failures <= 5) {
    std::vector<std::uint32_t> missed;
    std::set_difference(expected.begin(), expected.end(), got.begin(), got.end(), std::back_inserter(missed));
    ADD_FAILURE() << kind << " triangle (" << a.s << ", " << a.t << ") (" << b.s << ", " << b.t << ") (" << c.s << ", "
                  << c.t << "): " << got.size() << " tiles, exact " << expected.size() << ", missed " << missed.size();
  }
}

TEST(TileRaster, EqualsTheExactOverlapOnRandomAndAdversarialTriangles) {
  Rng rng(5, 8);
  int failures = 0;
  const auto point = [&](double lo, double hi) { return Point2{dyadic(rng, lo, hi), dyadic(rng, lo, hi)}; };
  const auto corner = [&] { return Point2{-2.0 + 0.5 * (rng.next_u32() % 17), -1.5 + 0.5 * (rng.next_u32() % 17)}; };
  for (int q = 0; q < 3000; ++q) {
    expect_exact(point(-1, 5), point(-1, 5), point(-1, 5), "random", failures);
    expect_exact(point(-4, 8), point(-4, 8), point(-4, 8), "partly outside", failures);
    const Point2 a = point(-1, 5);
    expect_exact(a, Point2{a.s + dyadic(rng, -0.5, 0.5), a.t + dyadic(rng, -0.5, 0.5)},
                 Point2{a.s + dyadic(rng, -0.5, 0.5), a.t + dyadic(rng, -0.5, 0.5)}, "small", failures);
    // Corners on tile corners, and edges along tile borders.
    expect_exact(corner(), corner(), corner(), "tile corners", failures);
    const Point2 p = corner();
    expect_exact(p, Point2{p.s + 0.5 * (rng.next_u32() % 6), p.t}, Point2{p.s, p.t + dyadic(rng, -2, 2)}, "on borders", failures);
    // Slivers: the third corner 1/256 off the line through the other two, or on it (seen edge-on).
    const Point2 u = point(-1, 5), v = point(-1, 5);
    const double k = dyadic(rng, -1, 2);
    const Point2 on_line{u.s + k * (v.s - u.s), u.t + k * (v.t - u.t)};
    expect_exact(u, v, Point2{on_line.s + 1.0 / 256.0, on_line.t}, "sliver", failures);
    expect_exact(u, v, on_line, "edge-on", failures);
    expect_exact(u, u, u, "point", failures);
  }
  expect_exact({-100, -100}, {100, -100}, {0, 100}, "covering", failures);
  EXPECT_EQ(failures, 0);
}

TEST(TileRaster, SlackAddsOnlyNearbyTilesAndKeepsTheTouchedOnes) {
  Rng rng(9, 4);
  for (int q = 0; q < 2000; ++q) {
    const Point2 a{dyadic(rng, -1, 5), dyadic(rng, -1, 5)}, b{dyadic(rng, -1, 5), dyadic(rng, -1, 5)},
        c{dyadic(rng, -1, 5), dyadic(rng, -1, 5)};
    std::vector<std::uint32_t> exact, loose;
    rasterize_triangle(kGrid, a, b, c, 0.0, exact);
    rasterize_triangle(kGrid, a, b, c, 0.25, loose);
    ASSERT_TRUE(std::includes(loose.begin(), loose.end(), exact.begin(), exact.end()));
    // Every added tile touches the triangle grown by the slack: its square grown by 0.25 overlaps it.
    for (std::uint32_t tile : loose) {
      const double s0 = kGrid.lo_s + (tile % 16) * kGrid.size - 0.25, t0 = kGrid.lo_t + (tile / 16) * kGrid.size - 0.25;
      EXPECT_TRUE(overlaps(a, b, c, s0, t0, s0 + kGrid.size + 0.5, t0 + kGrid.size + 0.5)) << tile;
    }
  }
}

TEST(TileRaster, TrianglesOutsideTheGridTouchNothing) {
  std::vector<std::uint32_t> tiles;
  rasterize_triangle(kGrid, {-10, -10}, {-9, -10}, {-10, -9}, 0.0, tiles);
  rasterize_triangle(kGrid, {6.5, 0}, {7, 0}, {6.5, 1}, 0.0, tiles);
  EXPECT_TRUE(tiles.empty());
  rasterize_triangle(kGrid, {6, 0}, {7, 0}, {6, 1}, 0.0, tiles);  // touches the grid's last column's right border
  EXPECT_EQ(tiles, (std::vector<std::uint32_t>{2 * 16 + 15, 3 * 16 + 15, 4 * 16 + 15, 5 * 16 + 15}));  // t in [0, 1]: rows 2..5
}

}  // namespace
}  // namespace vf::beam

// Which cells reference which triangles: complete (no cell a triangle meets is missed), exact (no
// cell it does not meet, with exact_overlap), sorted and independent of the thread count.

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "unit/grid/grid_test_support.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/rng.hpp"

namespace vf {
namespace {

using test::set_from_triangles;
using test::Triangle;
using D3 = std::array<double, 3>;

/// Triangle–box overlap by the separating axis theorem (Akenine-Möller 2001), in double: an
/// independent reference for the build's clipping.
bool triangle_meets_box(const Triangle& tri, const D3& lo, const D3& hi) {
  D3 c, h, v[3];
  for (int a = 0; a < 3; ++a) {
    c[a] = 0.5 * (lo[a] + hi[a]);
    h[a] = 0.5 * (hi[a] - lo[a]);
  }
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) v[k][a] = static_cast<double>(tri[k][a]) - c[a];
  const auto dot = [](const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  const auto separated = [&](const D3& axis) {
    const double p0 = dot(axis, v[0]), p1 = dot(axis, v[1]), p2 = dot(axis, v[2]);
    const double r = h[0] * std::fabs(axis[0]) + h[1] * std::fabs(axis[1]) + h[2] * std::fabs(axis[2]);
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
  };
  D3 e[3];
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) e[k][a] = v[(k + 1) % 3][a] - v[k][a];
  for (int a = 0; a < 3; ++a) {
    D3 unit{0, 0, 0};
    unit[a] = 1;
    if (separated(unit)) return false;
    for (const D3& edge : e) {
      const D3 axis{unit[1] * edge[2] - unit[2] * edge[1], unit[2] * edge[0] - unit[0] * edge[2],
                    unit[0] * edge[1] - unit[1] * edge[0]};
      if (separated(axis)) return false;
    }
  }
  const D3 normal{e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
                  e[0][0] * e[1][1] - e[0][1] * e[1][0]};
  return !separated(normal);
}

/// Box of cell `cell` grown by `grow` on every side.
void cell_box(const GridGeometry& g, std::size_t cell, double grow, D3& lo, D3& hi) {
  std::size_t rest = cell;
  for (int a = 0; a < 3; ++a) {
    const int i = static_cast<int>(rest % static_cast<std::size_t>(g.resolution[a]));
    rest /= static_cast<std::size_t>(g.resolution[a]);
    lo[a] = g.plane(a, i) - grow;
    hi[a] = g.plane(a, i + 1) + grow;
  }
}

/// Cell holding point p (clamped to the grid).
std::size_t cell_of(const GridGeometry& g, const Vec3f& p) {
  int i[3];
  for (int a = 0; a < 3; ++a)
    i[a] = std::clamp(static_cast<int>(std::floor((p[a] - g.origin[a]) / g.cell_size[a])), 0, g.resolution[a] - 1);
  return g.cell_index(i[0], i[1], i[2]);
}

bool references(const UniformGrid& g, std::size_t cell, std::uint32_t triangle) {
  const auto refs = g.cell_references(cell);
  return std::binary_search(refs.begin(), refs.end(), triangle);
}

/// Soup of small, medium and large triangles, so that many span several cells in every direction.
TriangleSet mixed_soup(std::uint64_t seed, std::size_t n) { return set_from_triangles(test::random_soup(seed, n, 0.002f, 0.4f)); }

TEST(GridCells, ReferencesAreSortedAndUnique) {
  const TriangleSet set = mixed_soup(1, 4000);
  const UniformGrid g = UniformGrid::build(set);
  for (std::size_t c = 0; c < g.geometry().cell_count(); ++c) {
    const auto refs = g.cell_references(c);
    ASSERT_TRUE(std::adjacent_find(refs.begin(), refs.end(), std::greater_equal<>()) == refs.end()) << "cell " << c;
    for (std::uint32_t t : refs) ASSERT_LT(t, set.size());
  }
}

TEST(GridCells, EveryPointOfATriangleIsInACellThatReferencesIt) {
  for (bool exact : {true, false}) {
    const TriangleSet set = mixed_soup(2, 3000);
    const UniformGrid g = UniformGrid::build(set, {.density = 4.0f, .exact_overlap = exact});
    Rng rng(5, 1);
    for (std::uint32_t i = 0; i < set.size(); ++i) {
      const Triangle& t = set.triangles[i];
      for (int k = 0; k < 3; ++k) ASSERT_TRUE(references(g, cell_of(g.geometry(), t[k]), i)) << "corner of " << i;
      for (int s = 0; s < 20; ++s) {
        const float u = rng.uniform(), v = rng.uniform() * (1.0f - u);
        const Vec3f p = t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * v;
        ASSERT_TRUE(references(g, cell_of(g.geometry(), p), i)) << "triangle " << i << " exact " << exact;
      }
    }
  }
}

TEST(GridCells, ExactOverlapReferencesOnlyCellsTheTriangleMeets) {
  const TriangleSet set = mixed_soup(3, 2000);
  const UniformGrid exact = UniformGrid::build(set, {.density = 4.0f, .exact_overlap = true});
  const UniformGrid boxes = UniformGrid::build(set, {.density = 4.0f, .exact_overlap = false});
  ASSERT_EQ(exact.resolution(), boxes.resolution());
  const double tolerance = 1e-5 * (2.0 + length(set.bounds.extent()));  // above the build's margin
  std::size_t checked = 0;
  for (std::size_t c = 0; c < exact.geometry().cell_count(); ++c) {
    D3 lo, hi;
    cell_box(exact.geometry(), c, tolerance, lo, hi);
    for (std::uint32_t t : exact.cell_references(c)) {
      ASSERT_TRUE(triangle_meets_box(set.triangles[t], lo, hi)) << "cell " << c << " triangle " << t;
      ASSERT_TRUE(references(boxes, c, t)) << "exact references must be a subset of the bounding-box ones";
      ++checked;
    }
    // And the other way: every cell the SAT sees a triangle meet (with a shrunk box) is referenced.
    cell_box(exact.geometry(), c, -tolerance, lo, hi);
    for (std::uint32_t t : boxes.cell_references(c)) {
      if (triangle_meets_box(set.triangles[t], lo, hi)) {
        ASSERT_TRUE(references(exact, c, t)) << "cell " << c << " triangle " << t;
      }
    }
  }
  EXPECT_EQ(checked, exact.stats().reference_count);
  EXPECT_LT(exact.stats().reference_count, boxes.stats().reference_count * 9 / 10);
}

TEST(GridCells, TrianglesInCellsAndOnCellBoundariesOfAForcedGrid) {
  // Cells of unit_cells(4) are unit cubes [x, x+1] x [y, y+1] x [z, z+1].
  const std::vector<Triangle> triangles{
      test::small_triangle({1.5f, 2.5f, 3.5f}),                                    // 0: inside cell (1, 2, 3)
      {Vec3f{2, 0.2f, 0.2f}, Vec3f{2, 0.8f, 0.2f}, Vec3f{2, 0.2f, 0.8f}},          // 1: in the plane x = 2
      {Vec3f{0.2f, 0.2f, 3.9f}, Vec3f{3.8f, 0.2f, 3.9f}, Vec3f{0.2f, 3.8f, 3.9f}}, // 2: big, in cells z = 3
      {Vec3f{0.5f, 0.5f, 0.5f}, Vec3f{3.5f, 3.5f, 0.5f}, Vec3f{3.5f, 3.5f, 3.5f}}, // 3: diagonal
  };
  const TriangleSet set = set_from_triangles(triangles);
  const UniformGrid g = UniformGrid::build(set, test::unit_cells(4));
  const GridGeometry& L = g.geometry();
  const auto cells_of = [&](std::uint32_t t) {
    std::set<std::array<int, 3>> out;
    for (int z = 0; z < 4; ++z)
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
          if (references(g, L.cell_index(x, y, z), t)) out.insert({x, y, z});
    return out;
  };
  EXPECT_EQ(cells_of(0), (std::set<std::array<int, 3>>{{1, 2, 3}}));
  EXPECT_EQ(cells_of(1), (std::set<std::array<int, 3>>{{1, 0, 0}, {2, 0, 0}}));
  // Triangle 2 meets the cells (x, y, 3) with x + y <= 4: those with x + y = 4 touch its
  // hypotenuse x + y = 4 at their lower corner (cells are closed).
  std::set<std::array<int, 3>> expected2;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      if (x + y <= 4) expected2.insert({x, y, 3});
  EXPECT_EQ(cells_of(2), expected2);
  // Triangle 3 lies in the plane x = y: it meets the diagonal cells (i, i, z) with z <= i and, at
  // their shared edges, the cells (i, i+1, z), (i+1, i, z) only where the plane touches them
  // (their edge x = y = i+1, which is in the triangle for z <= i+1).
  for (const auto& c : cells_of(3)) EXPECT_LE(std::abs(c[0] - c[1]), 1) << c[0] << c[1] << c[2];
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(cells_of(3).count({i, i, 0})) << i;
  EXPECT_FALSE(cells_of(3).count({0, 0, 3}));
}

TEST(GridCells, BuildDoesNotDependOnThreadCount) {
  const TriangleSet set = mixed_soup(6, 30000);
  const auto build_with = [&](int threads) {
    const ThreadLimit limit(threads);
    return UniformGrid::build(set);
  };
  const UniformGrid one = build_with(1), two = build_with(2), three = build_with(3);
  for (const UniformGrid* other : {&two, &three}) {
    ASSERT_EQ(one.resolution(), other->resolution());
    ASSERT_TRUE(std::ranges::equal(one.cell_starts(), other->cell_starts()));
    for (std::size_t c = 0; c < one.geometry().cell_count(); ++c)
      ASSERT_TRUE(std::ranges::equal(one.cell_references(c), other->cell_references(c))) << "cell " << c;
    EXPECT_EQ(one.stats().leaf_count, other->stats().leaf_count);
    EXPECT_EQ(one.stats().memory_bytes, other->stats().memory_bytes);
  }
}

}  // namespace
}  // namespace vf

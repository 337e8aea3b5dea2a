// Grid resolution, box, config validation and build statistics.

#include <cmath>

#include <gtest/gtest.h>

#include "unit/grid/grid_test_support.hpp"
#include "visfield/core/error.hpp"

namespace vf {
namespace {

using test::set_from_triangles;
using test::Triangle;

static_assert(Accelerator<UniformGrid>);

double cell_count(const UniformGrid& g) { return static_cast<double>(g.geometry().cell_count()); }

TEST(GridGeometry, CellCountFollowsTheDensityOnACubicScene) {
  const TriangleSet set = set_from_triangles(test::random_soup(1, 5000, 0.005f, 0.02f));
  for (float density : {1.0f, 2.0f, 4.0f, 8.0f}) {
    const UniformGrid g = UniformGrid::build(set, {.density = density});
    const double target = density * 5000.0;
    EXPECT_GT(cell_count(g), 0.7 * target) << density;
    EXPECT_LT(cell_count(g), 1.4 * target) << density;
    // Cells are about cubical: the resolutions follow the box's extents.
    const Vec3f e = set.bounds.extent();
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(g.geometry().cell_size[a], e[a] / std::cbrt(target / (e.x * e.y * e.z)), 0.2 * g.geometry().cell_size[a]);
  }
}

TEST(GridGeometry, ResolutionFollowsTheExtentsAsInClearyWyvill) {
  // A 4 x 2 x 1 slab of triangles: n_a = extent_a * cbrt(density * N / volume).
  std::vector<Triangle> triangles = test::random_soup(2, 4000, 0.002f, 0.01f);
  for (Triangle& t : triangles)
    for (Vec3f& p : t) p = p * Vec3f{4.0f, 2.0f, 1.0f};
  const TriangleSet set = set_from_triangles(triangles);
  const UniformGrid g = UniformGrid::build(set, {.density = 2.0f});
  const Vec3f e = set.bounds.extent();
  const double k = std::cbrt(2.0 * 4000 / (static_cast<double>(e.x) * e.y * e.z));
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(g.resolution()[a], std::round(e[a] * k), 1.0) << "axis " << a;
}

TEST(GridGeometry, FlatSceneGetsOneCellAcrossAndATwoDimensionalResolution) {
  const TriangleSet set = set_from_triangles(test::coplanar_soup(3, 3000, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  ASSERT_EQ(set.bounds.extent().z, 0.0f);
  const UniformGrid g = UniformGrid::build(set, {.density = 4.0f});
  EXPECT_EQ(g.resolution()[2], 1);
  const double in_plane = static_cast<double>(g.resolution()[0]) * g.resolution()[1];
  EXPECT_GT(in_plane, 0.7 * 4 * 3000);
  EXPECT_LT(in_plane, 1.4 * 4 * 3000);
  EXPECT_GT(g.geometry().cell_size[2], 0.0);
}

TEST(GridGeometry, ThinSceneGetsARowOfCells) {
  // Triangles strung along x, much thinner than a cell across: all cells go to x.
  std::vector<Triangle> triangles;
  for (int i = 0; i < 1000; ++i) {
    const float x = static_cast<float>(i);
    triangles.push_back({Vec3f{x, 0, 0}, Vec3f{x + 0.5f, 0.01f, 0}, Vec3f{x, 0, 0.01f}});
  }
  const UniformGrid g = UniformGrid::build(set_from_triangles(triangles), {.density = 2.0f});
  EXPECT_EQ(g.resolution()[1], 1);
  EXPECT_EQ(g.resolution()[2], 1);
  EXPECT_EQ(g.resolution()[0], 2000);
}

TEST(GridGeometry, ForcedResolutionAndBoxAreUsedAsGiven) {
  const TriangleSet set = set_from_triangles({test::small_triangle({0.5f, 0.5f, 0.5f})});
  const UniformGrid g = UniformGrid::build(set, test::unit_cells(4));
  EXPECT_EQ(g.resolution(), (std::array<int, 3>{4, 4, 4}));
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(g.geometry().origin[a], 0.0);
    EXPECT_EQ(g.geometry().cell_size[a], 1.0);
  }
  EXPECT_EQ(g.geometry().cell_index(1, 2, 3), 1u + 4u * (2u + 4u * 3u));
  EXPECT_EQ(g.geometry().plane(1, 3), 3.0);
}

TEST(GridGeometry, RejectsBadConfig) {
  const TriangleSet set = set_from_triangles({test::small_triangle({0.5f, 0.5f, 0.5f})});
  EXPECT_THROW(UniformGrid::build(set, {.density = 0.0f}), Error);
  EXPECT_THROW(UniformGrid::build(set, {.density = -1.0f}), Error);
  EXPECT_THROW(UniformGrid::build(set, {.density = std::nanf("")}), Error);
  EXPECT_THROW(UniformGrid::build(set, {.density = 1000.0f}), Error);
  EXPECT_THROW(UniformGrid::build(set, {.resolution = {4, 0, 4}}), Error);
  EXPECT_THROW(UniformGrid::build(set, {.resolution = {4, 4, 1 << 20}}), Error);
  EXPECT_THROW(UniformGrid::build(set, {.resolution = {1 << 16, 1 << 16, 1}}), Error);  // too many cells
  UniformGridConfig small_box = test::unit_cells(2);
  small_box.box.hi = Vec3f{0.5f};
  EXPECT_THROW(UniformGrid::build(set, small_box), Error);
  try {
    UniformGrid::build(set, {.density = 0.0f});
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("density"), std::string::npos) << e.what();
  }
}

TEST(GridGeometry, StatsDescribeTheGrid) {
  const TriangleSet set = set_from_triangles(test::random_soup(4, 3000, 0.01f, 0.1f));
  const UniformGrid g = UniformGrid::build(set);
  const AccelStats& s = g.stats();
  EXPECT_EQ(UniformGrid::name(), "grid");
  EXPECT_EQ(s.node_count, g.geometry().cell_count());
  EXPECT_EQ(s.max_depth, 0);
  std::size_t non_empty = 0, references = 0;
  for (std::size_t c = 0; c < g.geometry().cell_count(); ++c) {
    non_empty += g.cell_references(c).empty() ? 0 : 1;
    references += g.cell_references(c).size();
  }
  EXPECT_EQ(s.leaf_count, non_empty);
  EXPECT_EQ(s.reference_count, references);
  EXPECT_GE(s.reference_count, set.size());
  // Triangles, their (prim, instance) ids, cell offsets and references.
  EXPECT_GE(s.memory_bytes, set.size() * (9 * sizeof(float) + 2 * sizeof(std::uint32_t)) +
                                (s.node_count + 1 + s.reference_count) * sizeof(std::uint32_t));
  EXPECT_GT(s.build_ms, 0.0);
}

TEST(GridGeometry, EmptySetBuildsAnEmptyGrid) {
  const UniformGrid g = UniformGrid::build(TriangleSet{});
  EXPECT_EQ(g.geometry().cell_count(), 0u);
  EXPECT_EQ(g.stats().reference_count, 0u);
  EXPECT_FALSE(g.intersect(Ray{{0, 0, 0}, {0, 0, 1}}).found);
  EXPECT_FALSE(g.occluded(Ray{{0, 0, 0}, {0, 0, 1}}));
}

}  // namespace
}  // namespace vf

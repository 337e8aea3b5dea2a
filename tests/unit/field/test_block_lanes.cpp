// A FieldScene block's sphere pass on lanes: the rows it appends for several objects in one pass
// are, bit for bit, what may_meet_sphere() and InverseTransform::apply() give ray by ray, in order,
// settled rays left out; on counts that leave a partial packet for the scalar tail; into rows of
// their own or shared; from rays as Rays or as columns. And a few exact triangles' closest hits on
// lanes: the brute-force oracle's, bit for bit. And the grid that routes a block's rays to lists of
// objects: never a box left out.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "block_lanes.hpp"
#include "visfield/accel/brute_force.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/field/sphere_cull.hpp"

namespace vf::field {
namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }

/// Rays from a box around three spheres toward points near them, some already settled.
std::vector<Ray> rays_around(std::size_t n, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Ray> rays(n);
  for (Ray& r : rays) {
    const Vec3f org{8.0f * rng.uniform() - 4.0f, 8.0f * rng.uniform() - 4.0f, 8.0f * rng.uniform() - 4.0f};
    const Vec3f to{3.0f * rng.uniform() - 1.5f, 3.0f * rng.uniform() - 1.5f, 3.0f * rng.uniform() - 1.5f};
    // Short rays, long ones and unlimited ones: the interval decides some lanes.
    const float tmax = rng.uniform() < 0.3f ? 0.4f * rng.uniform() : (rng.uniform() < 0.5f ? 1e30f : 2.0f);
    r = Ray{org, to - org, 1e-3f, tmax};
  }
  return rays;
}

/// Three objects' maps, centres and radii: one turned, scaled and moved, one moved and shrunk, one as is.
struct ThreeObjects {
  InverseTransform maps[3];
  Vec3f centres[3] = {{1.0f, -0.5f, 0.25f}, {-1.0f, 0.5f, 0.0f}, {0.0f, 0.0f, 1.0f}};
  float radii[3] = {0.9f, 0.5f, 0.7f};

  ThreeObjects() {
    Transform a, b;
    a.rotation = Mat3::rotation(normalize(Vec3f{1.0f, 2.0f, -0.5f}), 37.0f);
    a.translation = {1.0f, -0.5f, 0.25f};
    a.scale = 1.7f;
    b.translation = {-1.0f, 0.5f, 0.0f};
    b.scale = 0.6f;
    maps[0] = a.inverse(), maps[1] = b.inverse(), maps[2] = Transform{}.inverse();
  }
};

/// Row k of `rows` as its id and 8 floats' bits.
std::array<std::uint32_t, 9> row_bits(const RayRows& rows, std::size_t k) {
  std::array<std::uint32_t, 9> bits{rows.id[k]};
  for (int c = 0; c < 8; ++c) std::memcpy(&bits[1 + static_cast<std::size_t>(c)], &rows.row[static_cast<std::size_t>(c)][k], sizeof(float));
  return bits;
}

/// Expects each of three objects' rows `got` to be `want`'s bit for bit (`n` rays traced); returns
/// how many rows they hold.
std::size_t expect_same_rows(const RayRows (&got)[3], const RayRows (&want)[3], std::size_t n) {
  std::size_t met = 0;
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(got[k].count, want[k].count) << "object " << k << ", " << n << " rays";
    for (std::size_t r = 0; r < std::min(got[k].count, want[k].count); ++r)
      EXPECT_EQ(row_bits(got[k], r), row_bits(want[k], r)) << "object " << k << " row " << r << ", " << n << " rays";
    met += want[k].count;
  }
  return met;
}

TEST(BlockLanes, TargetsSharingTheirRowsGetTheRowsOfTheirOwn) {
  const ThreeObjects objects;
  for (const std::size_t n : {std::size_t{5003}, std::size_t{5}}) {
    const std::vector<Ray> rays = rays_around(n, 29 + n);
    std::vector<std::uint32_t> ids(n);
    for (std::size_t i = 0; i < n; ++i) ids[i] = static_cast<std::uint32_t>(7 * i);
    RayRows own[3], shared;
    std::vector<SphereTarget> targets, into_shared;
    for (int k = 0; k < 3; ++k) {
      targets.push_back({objects.centres[k], objects.radii[k], &objects.maps[k], &own[k]});
      into_shared.push_back({objects.centres[k], objects.radii[k], &objects.maps[k], &shared});
    }
    append_meeting_spheres(targets, rays, ids.data());
    append_meeting_spheres(into_shared, rays, ids.data());
    // The same rows, each packet's for one object after another's (and room made for all of them).
    std::vector<std::array<std::uint32_t, 9>> expected, got;
    for (int k = 0; k < 3; ++k)
      for (std::size_t r = 0; r < own[k].count; ++r) expected.push_back(row_bits(own[k], r));
    for (std::size_t r = 0; r < shared.count; ++r) got.push_back(row_bits(shared, r));
    std::sort(expected.begin(), expected.end());
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected) << n << " rays";
    if (n > 1000) {
      EXPECT_GT(expected.size(), n / 4);  // the spheres do meet a share of the rays
    }
  }
}

TEST(BlockLanes, OnePassForSeveralSpheresAppendsTheRowsOfTheScalarTests) {
  const ThreeObjects objects;
  const auto& maps = objects.maps;
  const auto& centres = objects.centres;
  const auto& radii = objects.radii;
  for (const std::size_t n : {std::size_t{4001}, std::size_t{16}, std::size_t{7}}) {
    const std::vector<Ray> rays = rays_around(n, 11 + n);
    std::vector<std::uint8_t> skip(n);
    std::vector<std::uint32_t> ids(n);
    for (std::size_t i = 0; i < n; ++i) {
      skip[i] = i % 5 == 2 ? 1 : 0;
      ids[i] = static_cast<std::uint32_t>(3 * i + 1);
    }
    RayRows rows[3];
    std::vector<SphereTarget> targets;
    for (int k = 0; k < 3; ++k) targets.push_back({centres[k], radii[k], &maps[k], &rows[k]});
    append_meeting_spheres(targets, rays, ids.data(), skip.data());
    std::size_t met = 0;
    for (int k = 0; k < 3; ++k) {
      std::size_t at = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (skip[i] || !may_meet_sphere(centres[k], radii[k], rays[i])) continue;
        ASSERT_LT(at, rows[k].count) << "object " << k << ", " << n << " rays";
        const Ray r = maps[k].apply(rays[i]);
        const float want[8] = {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax};
        for (int c = 0; c < 8; ++c) EXPECT_TRUE(same_bits(rows[k].row[c][at], want[c])) << "object " << k << " ray " << i << " column " << c;
        EXPECT_EQ(rows[k].id[at], ids[i]);
        ++at;
      }
      EXPECT_EQ(at, rows[k].count) << "object " << k << ", " << n << " rays";
      met += at;
    }
    if (n > 1000) {
      EXPECT_GT(met, n / 4);  // the spheres do meet a share of the rays
    }
  }
}

TEST(BlockLanes, RaysAsColumnsGetTheRowsOfRaysAsRays) {
  const ThreeObjects objects;
  for (const std::size_t n : {std::size_t{4001}, std::size_t{16}, std::size_t{7}}) {
    const std::vector<Ray> rays = rays_around(n, 41 + n);
    // The ids index a settled array of their own (as a tree leaf's rays index their block's).
    std::vector<std::uint32_t> ids(n + kColumnsSlack, 0);
    std::vector<std::uint8_t> settled(3 * n + 2, 0), skip(n);
    for (std::size_t i = 0; i < n; ++i) {
      ids[i] = static_cast<std::uint32_t>(3 * i + 1);
      settled[ids[i]] = i % 7 == 3 ? 1 : 0;
      skip[i] = settled[ids[i]];
    }
    // Past the count: values that would meet every sphere, ids of rays not settled.
    std::array<std::vector<float>, 8> columns;
    for (auto& column : columns) column.assign(n + kColumnsSlack, 0.0f);
    for (std::size_t i = 0; i < n; ++i) {
      const float values[8] = {rays[i].org.x, rays[i].org.y, rays[i].org.z, rays[i].dir.x, rays[i].dir.y, rays[i].dir.z, rays[i].tmin, rays[i].tmax};
      for (int c = 0; c < 8; ++c) columns[static_cast<std::size_t>(c)][i] = values[c];
    }
    for (std::size_t i = n; i < n + kColumnsSlack; ++i) {
      columns[3][i] = 1.0f;
      columns[7][i] = 1e30f;
    }
    const float* column[8];
    for (int c = 0; c < 8; ++c) column[c] = columns[static_cast<std::size_t>(c)].data();
    RayRows as_rays[3], as_columns[3];
    std::vector<SphereTarget> from_rays, from_columns;
    for (int k = 0; k < 3; ++k) {
      from_rays.push_back({objects.centres[k], objects.radii[k], &objects.maps[k], &as_rays[k]});
      from_columns.push_back({objects.centres[k], objects.radii[k], &objects.maps[k], &as_columns[k]});
    }
    append_meeting_spheres(from_rays, rays, ids.data(), skip.data());
    append_meeting_spheres(from_columns, column, n, ids.data(), settled.data());
    EXPECT_GT(expect_same_rows(as_columns, as_rays, n), n / 4);  // the spheres do meet a share of the rays
  }
}

TEST(BlockLanes, RaysByIndexGetTheRowsOfRaysAsRays) {
  const ThreeObjects objects;
  const std::vector<Ray> rays = rays_around(3000, 43);
  for (const std::size_t n : {std::size_t{1234}, std::size_t{16}, std::size_t{5}}) {
    // Every other ray from the end back: ids in no order, the gathered rays as a block of their own.
    std::vector<std::uint32_t> ids(n + kColumnsSlack, 0), own(n);
    std::vector<Ray> gathered(n);
    for (std::size_t k = 0; k < n; ++k) {
      ids[k] = static_cast<std::uint32_t>(rays.size() - 1 - 2 * k);
      own[k] = ids[k];
      gathered[k] = rays[ids[k]];
    }
    RayRows by_index[3], as_rays[3];
    std::vector<SphereTarget> from_index, from_rays;
    for (int k = 0; k < 3; ++k) {
      from_index.push_back({objects.centres[k], objects.radii[k], &objects.maps[k], &by_index[k]});
      from_rays.push_back({objects.centres[k], objects.radii[k], &objects.maps[k], &as_rays[k]});
    }
    append_meeting_spheres(from_index, rays.data(), ids.data(), n);
    append_meeting_spheres(from_rays, gathered, own.data());
    EXPECT_GT(expect_same_rows(by_index, as_rays, n), n / 4);
  }
}

/// Whether the segment of `ray` meets `box` (closed), in double: the exact answer to rounding far
/// below a grid's margin.
bool segment_meets(const Ray& ray, const Bounds3f& box) {
  double t0 = ray.tmin, t1 = ray.tmax;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.org[a], d = ray.dir[a];
    if (d == 0.0) {
      if (o < box.lo[a] || o > box.hi[a]) return false;
      continue;
    }
    const double near = (box.lo[a] - o) / d, far = (box.hi[a] - o) / d;
    t0 = std::max(t0, std::min(near, far));
    t1 = std::min(t1, std::max(near, far));
  }
  return t0 <= t1;
}

/// 30 x 30 boxes on a jittered lattice in the xz plane, each about `width` times its spacing (0.25;
/// below 1 some touching, some apart; above, each reaching into its neighbours as the busts' spheres
/// do in docs/objectfield-measurements.md), and a few scattered just above them.
std::vector<Bounds3f> boxes_in_rows(Rng& rng, float width) {
  std::vector<Bounds3f> boxes;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) {
      const Vec3f centre{0.25f * static_cast<float>(i) + 0.01f * rng.uniform(), 0.1f, 0.25f * static_cast<float>(j)};
      const float r = width * (0.1f + 0.03f * rng.uniform());
      boxes.push_back({centre - Vec3f(r), centre + Vec3f(r)});
    }
  for (int k = 0; k < 20; ++k) {
    const Vec3f centre{7.5f * rng.uniform(), 0.25f + 0.2f * rng.uniform(), 7.5f * rng.uniform()};
    boxes.push_back({centre - Vec3f(0.05f), centre + Vec3f(0.05f)});
  }
  return boxes;
}

/// The median of the boxes' sides along x (the grid's unit).
float median_side(const std::vector<Bounds3f>& boxes) {
  std::vector<float> sides;
  for (const Bounds3f& b : boxes) sides.push_back(b.hi.x - b.lo.x);
  std::nth_element(sides.begin(), sides.begin() + static_cast<std::ptrdiff_t>(sides.size() / 2), sides.end());
  return sides[sides.size() / 2];
}

/// The grid over `boxes` routes a ray to a list of cells only when every box its segment meets is on
/// that list, and says "no box" only when it meets none: on rays leaving the boxes' surfaces (AO rays,
/// unlimited), long rays across the rows, rays from afar, along an axis, with tiny or NaN components;
/// lanes and one ray at a time give the same cells. Most surface rays are routed (or the test could
/// not fail). `grid`: the grid built.
void expect_lists_hold_every_box_met(const std::vector<Bounds3f>& boxes, Rng& rng, CellGrid& grid) {
  const ObjectField* fields[2] = {nullptr, reinterpret_cast<const ObjectField*>(&fields)};  // two tags, never read
  std::vector<const ObjectField*> field_of;
  for (std::size_t k = 0; k < boxes.size(); ++k) field_of.push_back(fields[k % 2]);
  std::vector<std::uint32_t> first, items;
  grid = cell_grid_over(boxes, field_of, first, items);
  ASSERT_GT(grid.count(), 100u);
  ASSERT_EQ(first.size(), kCellShapes * grid.count() + 1);
  for (std::size_t list = 0; list + 1 < first.size(); ++list)
    for (std::uint32_t k = first[list]; k + 1 < first[list + 1]; ++k) {
      const std::uint32_t a = items[k], b = items[k + 1];
      ASSERT_TRUE(field_of[a] < field_of[b] || (field_of[a] == field_of[b] && a < b)) << "list " << list;
    }
  std::vector<Ray> rays;
  std::size_t surface = 0;
  for (int k = 0; k < 20000; ++k) {
    const Bounds3f& box = boxes[rng.next_u32() % boxes.size()];
    const Vec3f on{box.lo.x + (box.hi.x - box.lo.x) * rng.uniform(), box.hi.y, box.lo.z + (box.hi.z - box.lo.z) * rng.uniform()};
    const Vec3f dir{rng.uniform() - 0.5f, 0.3f + rng.uniform(), rng.uniform() - 0.5f};
    rays.push_back(Ray{on, dir, 1e-4f, k % 3 == 0 ? 0.3f : INFINITY});
  }
  surface = rays.size();
  for (int k = 0; k < 3000; ++k) {
    const Vec3f from{10.0f * rng.uniform() - 1.0f, 2.0f * rng.uniform() - 0.5f, 10.0f * rng.uniform() - 1.0f};
    const Vec3f to{8.0f * rng.uniform(), 0.2f * rng.uniform(), 8.0f * rng.uniform()};
    rays.push_back(Ray{from, to - from, 0.0f, rng.uniform() < 0.5f ? 1.0f : 1e30f});
    rays.push_back(Ray{from * 100.0f, to - from * 100.0f, 0.0f, 1.0f});  // from afar: left to the walk
    Vec3f along{0.0f, 0.0f, 0.0f};
    along[static_cast<int>(rng.next_u32() % 3)] = rng.uniform() < 0.5f ? -1.0f : 1.0f;
    rays.push_back(Ray{to, along, 0.0f, 0.6f * rng.uniform()});
    rays.push_back(Ray{to, Vec3f{1e-31f, 1.0f, rng.uniform() - 0.5f}, 0.0f, 1.0f});
    rays.push_back(Ray{to + Vec3f{0.0f, 3.0f, 0.0f}, Vec3f{rng.uniform() - 0.5f, 1.0f, rng.uniform() - 0.5f}, 0.0f, INFINITY});  // away: no box
  }
  rays.push_back(Ray{{NAN, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, 0.0f, 1.0f});
  rays.push_back(Ray{{1.0f, 0.1f, 1.0f}, {1.0f, 0.0f, NAN}, 0.0f, 1.0f});
  rays.push_back(Ray{{1.0f, 0.1f, 1.0f}, {1.0f, 0.2f, 0.3f}, NAN, 1.0f});
  rays.push_back(Ray{{1.0f, 0.1f, 1.0f}, {1.0f, 0.2f, 0.3f}, 0.0f, NAN});
  std::vector<std::uint8_t> skip(rays.size(), 0);
  for (std::size_t i = 0; i < rays.size(); i += 11) skip[i] = 1;
  std::vector<std::int32_t> cell(rays.size());
  std::vector<std::uint32_t> in_cells(rays.size() + kColumnsSlack);
  const std::size_t placed = cells_of_rays(grid, rays, skip.data(), cell.data(), in_cells.data());
  std::size_t routed_surface = 0, given = 0, none = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    std::int32_t one;
    std::uint32_t unused[kColumnsSlack];
    cells_of_rays(grid, std::span<const Ray>(&rays[i], 1), &skip[i], &one, unused);
    ASSERT_EQ(one, cell[i]) << "ray " << i << ": lanes and one ray at a time";
    if (skip[i]) {
      ASSERT_EQ(cell[i], kManyCells) << "ray " << i;
      continue;
    }
    if (cell[i] == kManyCells) continue;
    routed_surface += i < surface ? 1 : 0;
    if (cell[i] == kNoCell) {
      ++none;
      for (std::size_t k = 0; k < boxes.size(); ++k) ASSERT_FALSE(segment_meets(rays[i], boxes[k])) << "ray " << i << " box " << k;
      continue;
    }
    ASSERT_LT(given, placed);
    ASSERT_EQ(in_cells[given++], i);
    const auto list = static_cast<std::size_t>(cell[i]);
    ASSERT_LT(list + 1, first.size());
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      if (!segment_meets(rays[i], boxes[k])) continue;
      ASSERT_TRUE(std::find(items.begin() + first[list], items.begin() + first[list + 1], k) != items.begin() + first[list + 1])
          << "ray " << i << " meets box " << k << ", not on its list " << list;
    }
  }
  EXPECT_EQ(given, placed);
  EXPECT_GT(routed_surface, surface / 2) << "of " << surface << " surface rays";
  EXPECT_GT(none, 100u);
}

TEST(BlockLanes, CellsOfRaysNeverLeaveOutABoxTheRayMeets) {
  Rng rng(51);
  const std::vector<Bounds3f> rows = boxes_in_rows(rng, 1.0f);
  CellGrid grid, narrow;
  ASSERT_NO_FATAL_FAILURE(expect_lists_hold_every_box_met(rows, rng, grid));
  EXPECT_GE(grid.edge[0], 1.75f * median_side(rows)) << "cells of two median boxes: their pairs' lists are short";
  // Boxes about 1.6 times as wide as their spacing: at cells of two boxes the pairs' lists would hold
  // more than 16 boxes, so the grid's cells narrow until those are used.
  const std::vector<Bounds3f> wide = boxes_in_rows(rng, 1.6f);
  ASSERT_NO_FATAL_FAILURE(expect_lists_hold_every_box_met(wide, rng, narrow));
  EXPECT_LT(narrow.edge[0], 1.75f * median_side(wide));
  // A scene far from the world's origin, where float rounding would outgrow the margin: no grid.
  std::vector<Bounds3f> far = rows;
  for (Bounds3f& b : far) b = {b.lo + Vec3f(1e6f), b.hi + Vec3f(1e6f)};
  std::vector<const ObjectField*> field_of(far.size(), nullptr);
  std::vector<std::uint32_t> first, items;
  EXPECT_EQ(cell_grid_over(far, field_of, first, items).count(), 0u);
}

TEST(BlockLanes, ClosestHitsOfAFewTrianglesAreTheOraclesBitForBit) {
  // 40 triangles in a box; triangle 5 again at 20 (equal hits: the lower index stays) and two that
  // share an edge (rays through it fall back to double, and to the scalar test).
  Rng rng(17);
  TriangleSet set;
  const auto corner = [&] { return Vec3f{4.0f * rng.uniform() - 2.0f, 4.0f * rng.uniform() - 2.0f, 4.0f * rng.uniform() - 2.0f}; };
  for (int k = 0; k < 40; ++k) set.triangles.push_back({corner(), corner(), corner()});
  set.triangles[20] = set.triangles[5];
  set.triangles[31] = {set.triangles[30][1], set.triangles[30][0], corner()};
  for (std::size_t k = 0; k < set.triangles.size(); ++k) {
    set.prim.push_back(static_cast<std::uint32_t>(100 + k));
    set.instance.push_back(static_cast<ObjectId>(7 + k % 3));
  }
  std::vector<Ray> rays = rays_around(4001, 19);
  for (int k = 0; k < 2000; ++k) {  // at the duplicated triangle, the shared edge, and corners
    const std::array<Vec3f, 3>& t = set.triangles[k % 3 == 0 ? 5 : 30];
    const float a = rng.uniform();
    const Vec3f to = k % 3 == 1 ? t[0] * a + t[1] * (1.0f - a) : k % 3 == 2 ? t[k % 2] : (t[0] + t[1] + t[2]) * (1.0f / 3.0f);
    const Vec3f from = corner() * 3.0f;
    rays.push_back(Ray{from, to - from, 0.0f, k % 5 == 0 ? 1.0f : 1e30f});
  }
  std::vector<Hit> got(rays.size());
  closest_by_small_exact(set, Bvh::build(set), rays, got.data());
  const BruteForce oracle = BruteForce::build(set);
  std::size_t hits = 0, at_five = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit want = oracle.intersect(rays[i]);
    ASSERT_EQ(got[i].found, want.found) << "ray " << i;
    if (!want.found) continue;
    ++hits;
    at_five += want.prim == 105 ? 1 : 0;
    ASSERT_TRUE(same_bits(got[i].t, want.t) && same_bits(got[i].u, want.u) && same_bits(got[i].v, want.v)) << "ray " << i;
    ASSERT_EQ(got[i].prim, want.prim) << "ray " << i;
    ASSERT_EQ(got[i].instance, want.instance) << "ray " << i;
    ASSERT_TRUE(got[i].has_normal && same_bits(got[i].normal.x, want.normal.x) && same_bits(got[i].normal.y, want.normal.y) &&
                same_bits(got[i].normal.z, want.normal.z))
        << "ray " << i;
  }
  EXPECT_GT(hits, rays.size() / 3);
  EXPECT_GT(at_five, 40u);  // the duplicate's equal hits
}

// Occlusion by a few triangles on lanes is the brute-force oracle's, bit for bit, including the rays
// the lanes settle before any triangle (origin beyond the triangles' box along the ray's major axis,
// moving away): from just above, on and just below a ground, up, down and sideways, with tmin 0, -0,
// negative and positive; then with triangles above the ground too.
TEST(BlockLanes, OcclusionByAFewTrianglesIsTheOraclesBitForBit) {
  Rng rng(23);
  TriangleSet ground;
  ground.triangles = {{Vec3f{-6.0f, 0.0f, -6.0f}, Vec3f{6.0f, 0.0f, 6.0f}, Vec3f{6.0f, 0.0f, -6.0f}},
                      {Vec3f{-6.0f, 0.0f, -6.0f}, Vec3f{-6.0f, 0.0f, 6.0f}, Vec3f{6.0f, 0.0f, 6.0f}}};
  TriangleSet with_more = ground;
  for (int k = 0; k < 10; ++k) {
    const Vec3f c{8.0f * rng.uniform() - 4.0f, 3.0f * rng.uniform(), 8.0f * rng.uniform() - 4.0f};
    with_more.triangles.push_back({c, c + Vec3f{rng.uniform(), rng.uniform(), 0.0f}, c + Vec3f{0.0f, rng.uniform(), rng.uniform()}});
  }
  for (TriangleSet* set : {&ground, &with_more})
    for (std::size_t k = 0; k < set->triangles.size(); ++k) {
      set->prim.push_back(static_cast<std::uint32_t>(k));
      set->instance.push_back(0);
    }
  std::vector<Ray> rays = rays_around(1001, 31);
  const float heights[] = {0.0f, -0.0f, std::nextafter(0.0f, 1.0f), std::nextafter(0.0f, -1.0f), 1e-7f, -1e-7f, 1e-3f, -1e-3f, 2.0f, -2.0f};
  const float tmins[] = {0.0f, -0.0f, -1.0f, 1e-4f};
  // Runs of 16 alike (whole packets of lanes settled at once, or not), then the next kind.
  for (int k = 0; k < 8000; ++k) {
    const int kind = k / 16;
    const Vec3f from{12.0f * rng.uniform() - 6.0f, heights[kind % 10], 12.0f * rng.uniform() - 6.0f};
    // Steep (y the major axis), shallow (x or z the major axis), up and down.
    const float up = (kind / 10) % 2 == 0 ? 1.0f : -1.0f, slope = (kind / 20) % 3 == 0 ? 4.0f : ((kind / 20) % 3 == 1 ? 0.9f : 0.2f);
    const Vec3f dir{2.0f * rng.uniform() - 1.0f, up * slope * (0.5f + rng.uniform()), 2.0f * rng.uniform() - 1.0f};
    rays.push_back(Ray{from, dir, tmins[(kind / 60) % 4], (kind / 240) % 2 == 0 ? 1e30f : 3.0f});
  }
  for (const TriangleSet* set : {&ground, &with_more}) {
    std::vector<std::uint8_t> got(rays.size(), 7);
    occluded_by_small_exact(set->triangles, rays, got.data());
    const BruteForce oracle = BruteForce::build(*set);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const bool want = oracle.occluded(rays[i]);
      ASSERT_EQ(got[i], want ? 1 : 0) << set->triangles.size() << " triangles, ray " << i;
      hits += want ? 1 : 0;
    }
    EXPECT_GT(hits, rays.size() / 5);
    EXPECT_LT(hits, rays.size() * 4 / 5);
  }
}

}  // namespace
}  // namespace vf::field

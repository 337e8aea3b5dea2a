#pragma once
/// \file Exact uniform grid (Fujimoto 1986; resolution after Cleary & Wyvill 1988): about
/// density * N cells over the scene box, an O(N) parallel build into a compact cell -> triangle
/// reference array, and 3D-DDA traversal (Amanatides & Woo 1987) with the watertight triangle test.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "visfield/accel/query.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {

/// Build parameters of the uniform grid.
struct UniformGridConfig {
  /// Target cells per triangle, lambda: the grid has about density * N cells, in (0, 64]. The
  /// default is the fastest of {1, 2, 4, 8} over AO and random rays on the shared models and the
  /// built-in scenes (figures in src/accel/grid/geometry.cpp).
  float density = 2.0f;
  /// Cells per axis when all three are > 0 (tests, experiments); {0, 0, 0} = from `density`.
  std::array<int, 3> resolution{0, 0, 0};
  /// The grid box when non-empty; it must contain every triangle. Empty = the triangles' bounds.
  Bounds3f box = {};
  /// Reference a triangle only from the cells its surface meets (exact clipping), not from every
  /// cell of its bounding box: 12-70% fewer references and 4-125% faster queries on the shared
  /// models, for up to 1.8x the build time (figures in src/accel/grid/cell_overlap.hpp).
  bool exact_overlap = true;
};

/// Where the cells lie: cell (x, y, z) spans origin + (x, y, z) * cell_size to origin + (x+1, y+1,
/// z+1) * cell_size, in double precision. Plain value.
struct GridGeometry {
  std::array<double, 3> origin{};         ///< Lower corner of the grid box.
  std::array<double, 3> cell_size{};      ///< Cell edge lengths, > 0 on every axis.
  std::array<int, 3> resolution{0, 0, 0}; ///< Cells per axis; all 0 for an empty grid.

  /// Number of cells, nx * ny * nz.
  std::size_t cell_count() const {
    return static_cast<std::size_t>(resolution[0]) * static_cast<std::size_t>(resolution[1]) *
           static_cast<std::size_t>(resolution[2]);
  }
  /// Linear index of cell (x, y, z); x varies fastest. No bounds check.
  std::size_t cell_index(int x, int y, int z) const {
    return static_cast<std::size_t>(x) +
           static_cast<std::size_t>(resolution[0]) *
               (static_cast<std::size_t>(y) + static_cast<std::size_t>(resolution[1]) * static_cast<std::size_t>(z));
  }
  /// Coordinate of the plane between cells i - 1 and i on `axis` (i in 0..resolution[axis]).
  double plane(int axis, int i) const { return origin[axis] + static_cast<double>(i) * cell_size[axis]; }
};

namespace grid {
struct GridLayout;
}

/// An immutable uniform grid over a TriangleSet. Queries are const and thread-safe; results are
/// those of BruteForce (same t, u, v and triangle; ties in t go to the lowest triangle index). Build
/// and queries do not depend on the thread count. Move-only.
class UniformGrid {
 public:
  /// Builds over `set` (triangles copied); O(N + cells + references), parallel over TBB's threads.
  /// Throws vf::Error on a bad config, or before allocating a grid that would exceed 32-bit
  /// reference offsets or the memory limit (memory_limit(), counted exactly in its first pass).
  static UniformGrid build(const TriangleSet& set, const UniformGridConfig& config = {});
  /// Peak bytes build() takes for `triangles` triangles with 4 references each: 80 per triangle,
  /// 4 per cell and 16 per reference (measured 74 per triangle on Armadillo at density 2). More
  /// references (large triangles: 53 per triangle on a soup) are counted before they are stored.
  static double estimate_build_bytes(std::size_t triangles, const UniformGridConfig& config = {});
  UniformGrid(UniformGrid&&) noexcept;
  UniformGrid& operator=(UniformGrid&&) noexcept;
  ~UniformGrid();

  /// Closest hit in (tmin, tmax]; a zero direction never hits.
  Hit intersect(const Ray& ray) const;
  /// True when any triangle is hit in (tmin, tmax]; stops at the first.
  bool occluded(const Ray& ray) const;
  /// Build statistics: node_count = cells, leaf_count = non-empty cells, reference_count, bytes, ms.
  const AccelStats& stats() const;
  /// The registry name, "grid".
  static std::string name() { return "grid"; }
  static constexpr Exactness exactness = Exactness::exact;

  /// Cell geometry and resolution (nx, ny, nz).
  const GridGeometry& geometry() const;
  /// Cells per axis (nx, ny, nz).
  const std::array<int, 3>& resolution() const { return geometry().resolution; }
  /// cells + 1 offsets into the reference array: cell c holds cell_starts()[c+1] - cell_starts()[c]
  /// references (listed by cell_references(c)); the last entry is the reference count.
  std::span<const std::uint32_t> cell_starts() const;
  /// TriangleSet indices of the triangles meeting cell `cell`, in increasing order.
  std::span<const std::uint32_t> cell_references(std::size_t cell) const;

 private:
  explicit UniformGrid(std::unique_ptr<const grid::GridLayout> layout);
  std::unique_ptr<const grid::GridLayout> layout_;
};

}  // namespace vf

#pragma once
// Private to accel (BeamField, issue 8): conservative rasterisation of a triangle projected along a
// beam direction into the n×n tiles of that direction's parallel subfield: the paper's edge walk
// with interior fill (VLF-RT Figure 1), done a row of tiles at a time.

#include <cstdint>
#include <vector>

namespace vf::beam {

/// A point in PSF coordinates (s, t): the plane perpendicular to a line's direction.
struct Point2 {
  double s = 0.0, t = 0.0;
};

/// n×n square tiles covering [lo_s, lo_s + n·size) × [lo_t, lo_t + n·size); tile (x, y) has index
/// y·n + x. Tiles are closed squares: a point on a shared border touches both.
struct TileGrid {
  double lo_s = 0.0, lo_t = 0.0;
  double size = 1.0;  ///< Side of a tile, > 0.
  int n = 1;          ///< Tiles per side, >= 1.
};

/// Appends to `tiles`, in increasing index order, every tile of `grid` that the closed triangle
/// (a, b, c) comes within `slack` of in s and in t (slack = 0: every tile it touches, borders and
/// corners included; degenerate triangles are their segments or their point). Parts outside the
/// grid are ignored. Conservative: no touched tile is left out, whatever the triangle's shape.
/// O(rows + tiles). Thread-safe (no state).
void rasterize_triangle(const TileGrid& grid, Point2 a, Point2 b, Point2 c, double slack, std::vector<std::uint32_t>& tiles);

}  // namespace vf::beam

#pragma once
/// \file Choosing the grid box and resolution (private to the accel module).

#include <array>
#include <cstddef>
#include <string>

#include "visfield/accel/uniform_grid.hpp"

namespace vf::grid {

/// Largest cell count a grid may have (cell offsets and indices stay within 32 bits).
inline constexpr std::size_t kMaxCells = std::size_t{1} << 31;
/// Largest resolution on one axis.
inline constexpr int kMaxAxisCells = 1 << 16;
/// Largest accepted density (cells per triangle).
inline constexpr float kMaxDensity = 64.0f;

/// Cells per axis giving about `target_cells` cubical-as-possible cells over a box with these edge
/// lengths (Cleary & Wyvill: n_a = extent_a * cbrt(target / volume)). Axes whose share would be
/// under one cell (flat or thin boxes) get one cell and the remaining axes share the target, so a
/// flat scene gets sqrt-shaped 2D resolutions. Each axis is clamped to [1, kMaxAxisCells].
std::array<int, 3> resolution_for(const std::array<double, 3>& extent, double target_cells);

/// The grid box and resolution for `set` under `config` (validated; throws vf::Error naming the
/// bad field). Axes of zero (or negligible) extent are thickened so every cell has a volume. An
/// empty set gives resolution {0, 0, 0}.
GridGeometry make_geometry(const TriangleSet& set, const UniformGridConfig& config);

/// Coordinate scale of the grid: largest coordinate magnitude of its box plus its largest extent.
/// Float rounding of points in or near the grid is a small multiple of 2^-24 times this.
double coordinate_scale(const GridGeometry& geometry);

/// Cells are enlarged by this distance when triangles are assigned to them, so that points the
/// watertight test counts as on a triangle (which may lie a few ulps outside it) are in a cell that
/// references the triangle. 2^-18 of the scale: 64 ulps, and far below a cell.
inline double overlap_margin(const GridGeometry& geometry) { return 0x1p-18 * coordinate_scale(geometry); }

/// Spatial part of the traversal slack: a hit whose t lies within this distance (in t units: divided
/// by the largest |dir| component) of a cell's exit is also looked for in the next cell. Covers the
/// t error of the watertight test; 2^-16 of the scale.
inline double traversal_slack(const GridGeometry& geometry) { return 0x1p-16 * coordinate_scale(geometry); }

}  // namespace vf::grid

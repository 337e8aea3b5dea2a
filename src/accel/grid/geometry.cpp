#include "grid/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"

namespace vf::grid {
namespace {

// An axis shorter than this fraction of the longest one is flat: it gets one cell and, when its
// extent is tiny or zero, is thickened to kFlatThickness of the longest axis so cells have volume.
constexpr double kFlatFraction = 0x1p-20;
constexpr double kFlatThickness = 0x1p-10;

// The default density (UniformGridConfig::density = 2) was measured with the SIMD cell test of
// traversal.cpp, exact overlap, one thread; Mrays per CPU-second, AO rays (4 per pixel of a
// 320 x 240 view, max distance a quarter of the scene diagonal, occlusion queries) and Havran's
// random rays (100k segments between points of the bounding sphere, closest hit):
//   scene                 AO, lambda = 1 / 2 / 4 / 8              random, lambda = 1 / 2 / 4 / 8
//   conference             5.88 /  5.71 /  5.29 /  4.90     7.78 /  8.82 /  8.98 /  8.38
//   sponza                14.22 / 15.85 / 15.34 / 16.26    13.72 / 14.22 / 13.16 / 13.20
//   bun_zipper             1.80 /  1.99 /  1.98 /  1.86     2.80 /  2.73 /  2.47 /  1.93
//   Armadillo              0.81 /  0.87 /  0.84 /  0.70     0.88 /  0.91 /  0.79 /  0.62
//   dragon_vrip_res2       1.13 /  1.17 /  1.09 /  0.94     1.33 /  1.35 /  1.21 /  0.95
//   lucy                   1.36 /  1.41 /  1.32 /  1.19     2.41 /  2.17 /  2.03 /  1.55
//   teapot                 3.22 /  3.42 /  3.43 /  3.28     5.66 /  5.65 /  5.42 /  4.95
//   cow                    3.42 /  3.64 /  3.69 /  3.52     6.42 /  6.24 /  6.11 /  5.65
//   igea-triangles         1.41 /  1.53 /  1.54 /  1.41     1.19 /  1.11 /  1.07 /  0.96
//   CornellBox-Original    8.65 /  8.39 /  8.35 /  7.95    11.00 / 11.32 / 11.83 / 12.22
//   builtin:soup           4.40 /  4.36 /  4.00 /  3.75     1.72 /  1.69 /  1.54 /  1.72
//   builtin:stadium        0.02 /  0.02 /  0.03 /  0.05     7.31 /  8.11 /  7.16 /  6.49
//   builtin:sphere         1.22 /  1.60 /  1.92 /  2.21    14.93 / 14.31 / 13.16 / 11.90
//   builtin:boxes          4.10 /  5.96 /  6.25 /  6.46    19.51 / 19.80 / 19.27 / 18.54
//   builtin:cornell        4.30 /  4.32 /  4.19 /  3.85    10.42 / 10.70 / 10.65 / 10.37
// Geometric means relative to lambda = 2 (stadium left out: its AO rays start in the dense knot,
// where any lambda is hopeless): AO 0.92 / 1 / 0.99 / 0.94, random 1.00 / 1 / 0.95 / 0.86. Lambda 2
// is best or within 1% on both, with half the cells of lambda 4. Build of conference (331k
// triangles, two threads): 6.2 / 7.8 / 8.9 / 11.3 ms.

std::string resolution_text(const std::array<int, 3>& r) {
  return std::to_string(r[0]) + " x " + std::to_string(r[1]) + " x " + std::to_string(r[2]);
}

void validate(const UniformGridConfig& c, const TriangleSet& set) {
  if (!(c.density > 0.0f && c.density <= kMaxDensity)) {
    char text[96];
    std::snprintf(text, sizeof text, "grid: density must be in (0, %g], got %g", static_cast<double>(kMaxDensity),
                  static_cast<double>(c.density));
    throw Error(text);
  }
  const bool forced = c.resolution[0] > 0 || c.resolution[1] > 0 || c.resolution[2] > 0;
  if (forced) {
    for (int n : c.resolution)
      if (n < 1 || n > kMaxAxisCells)
        throw Error("grid: resolution must be 0 0 0 or three values in [1, " + std::to_string(kMaxAxisCells) +
                    "], got " + resolution_text(c.resolution));
  }
  if (!c.box.empty()) {
    if (!is_finite(c.box.lo) || !is_finite(c.box.hi)) throw Error("grid: box must be finite");
    if (set.size() > 0 && !(c.box.contains(set.bounds.lo) && c.box.contains(set.bounds.hi)))
      throw Error("grid: box does not contain every triangle");
  }
  if (set.size() >= kMaxCells) throw Error("grid: " + std::to_string(set.size()) + " triangles exceed the limit");
}

}  // namespace

std::array<int, 3> resolution_for(const std::array<double, 3>& extent, double target_cells) {
  std::array<int, 3> n{1, 1, 1};
  std::array<bool, 3> active{};
  for (int a = 0; a < 3; ++a) active[a] = extent[a] > 0.0;
  // Drop axes whose share is below one cell, then spread the target over the rest.
  for (;;) {
    int dims = 0;
    double volume = 1.0;
    for (int a = 0; a < 3; ++a)
      if (active[a]) {
        ++dims;
        volume *= extent[a];
      }
    if (dims == 0) return n;
    const double cells_per_unit = std::pow(std::max(target_cells, 1.0) / volume, 1.0 / dims);
    bool dropped = false;
    for (int a = 0; a < 3; ++a)
      if (active[a] && extent[a] * cells_per_unit < 1.0) {
        active[a] = false;
        dropped = true;
      }
    if (dropped) continue;
    for (int a = 0; a < 3; ++a)
      if (active[a]) {
        const double cells = std::floor(extent[a] * cells_per_unit + 0.5);
        n[a] = static_cast<int>(std::clamp(cells, 1.0, static_cast<double>(kMaxAxisCells)));
      }
    return n;
  }
}

GridGeometry make_geometry(const TriangleSet& set, const UniformGridConfig& config) {
  validate(config, set);
  GridGeometry geometry;
  if (set.size() == 0) return geometry;
  const Bounds3f& box = config.box.empty() ? set.bounds : config.box;
  std::array<double, 3> lo{}, extent{};
  double longest = 0.0;
  for (int a = 0; a < 3; ++a) {
    lo[a] = box.lo[a];
    extent[a] = static_cast<double>(box.hi[a]) - box.lo[a];
    longest = std::max(longest, extent[a]);
  }
  if (!(longest > 0.0)) longest = 1.0;  // unreachable for non-degenerate triangles; keeps cells finite
  std::array<double, 3> sized = extent;
  for (int a = 0; a < 3; ++a) {
    if (extent[a] > kFlatFraction * longest) continue;
    sized[a] = 0.0;  // flat: one cell, no share of the density target
    const double thickness = kFlatThickness * longest;
    if (extent[a] < thickness) {
      lo[a] -= 0.5 * (thickness - extent[a]);
      extent[a] = thickness;
    }
  }
  const bool forced = config.resolution[0] > 0;
  geometry.resolution = forced ? config.resolution
                             : resolution_for(sized, static_cast<double>(config.density) * static_cast<double>(set.size()));
  if (geometry.cell_count() > kMaxCells)
    throw Error("grid: resolution " + resolution_text(geometry.resolution) + " has more than " +
                std::to_string(kMaxCells) + " cells");
  require_memory(4.0 * static_cast<double>(geometry.cell_count()),
                 "grid: the cell offsets of resolution " + resolution_text(geometry.resolution));
  for (int a = 0; a < 3; ++a) {
    geometry.origin[a] = lo[a];
    geometry.cell_size[a] = extent[a] / geometry.resolution[a];
  }
  return geometry;
}

double coordinate_scale(const GridGeometry& geometry) {
  double magnitude = 0.0, longest = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double hi = geometry.plane(a, geometry.resolution[a]);
    magnitude = std::max({magnitude, std::fabs(geometry.origin[a]), std::fabs(hi)});
    longest = std::max(longest, hi - geometry.origin[a]);
  }
  return magnitude + longest;
}

}  // namespace vf::grid

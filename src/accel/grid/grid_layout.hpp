#pragma once
/// \file Memory layout of the built UniformGrid (private to the accel module).

#include <array>
#include <cstdint>
#include <vector>

#include "visfield/accel/uniform_grid.hpp"

namespace vf::grid {

/// The cells, their triangle references and a copy of the triangles.
struct GridLayout {
  GridGeometry geometry;
  std::vector<std::array<Vec3f, 3>> triangles;  ///< Copy of the TriangleSet's corners, same order.
  std::vector<std::uint32_t> prim;              ///< Copy of the TriangleSet's triangle ids.
  std::vector<ObjectId> instance;               ///< Copy of the TriangleSet's object ids.
  std::vector<std::uint32_t> cell_start;        ///< cells + 1 offsets into refs.
  std::vector<std::uint32_t> refs;              ///< Triangle indices, grouped by cell.
  double slack_distance = 0.0;                  ///< Traversal slack in distance units (see traversal.cpp).
  AccelStats stats;
};

}  // namespace vf::grid

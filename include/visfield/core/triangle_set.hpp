#pragma once
/// \file The flat world-space triangle list every acceleration structure is built from.

#include <array>
#include <cstdint>
#include <vector>

#include "visfield/core/bounds.hpp"
#include "visfield/core/scene.hpp"

namespace vf {

/// World-space triangles of a scene (instances applied, degenerate triangles removed), with the
/// (instance, prim) each came from. Immutable after flatten(); safe to share between threads.
struct TriangleSet {
  std::vector<std::array<Vec3f, 3>> triangles;   ///< World-space corners.
  std::vector<std::uint32_t> prim;               ///< Triangle index in its mesh.
  std::vector<std::uint32_t> instance;           ///< Instance index in the scene.
  std::size_t degenerate_count = 0;              ///< Zero-area triangles left out.
  Bounds3f bounds;                               ///< Bounds of all kept triangles.

  /// Number of kept triangles.
  std::size_t size() const { return triangles.size(); }
  /// Bytes held by the arrays.
  std::size_t memory_bytes() const;
};

/// Applies every instance transform and drops zero-area triangles (counted in degenerate_count).
/// O(total triangles), parallel.
TriangleSet flatten(const Scene& scene);

}  // namespace vf

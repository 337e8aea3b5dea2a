#pragma once
/// \file The flat triangle list every single-level acceleration structure is built from.

#include <array>
#include <cstdint>
#include <vector>

#include "visfield/core/bounds.hpp"
#include "visfield/core/scene.hpp"

namespace vf {

/// Triangles (degenerate ones removed) with the (object, triangle) each came from. Built by
/// flatten() in world space, or by mesh_triangles() in a mesh's object space for the per-mesh
/// structures of the instance layer. Immutable once built; safe to share between threads.
struct TriangleSet {
  std::vector<std::array<Vec3f, 3>> triangles;   ///< Corners.
  std::vector<std::uint32_t> prim;               ///< Triangle index in its mesh.
  std::vector<ObjectId> instance;                ///< Object id (kInvalidId in an object-space set).
  std::size_t degenerate_count = 0;              ///< Zero-area triangles left out.
  Bounds3f bounds;                               ///< Bounds of all kept triangles.

  /// Number of kept triangles.
  std::size_t size() const { return triangles.size(); }
  /// Bytes held by the arrays.
  std::size_t memory_bytes() const;
};

/// World-space triangles of every object of `scene`, objects in id order and triangles in mesh
/// order, with zero-area triangles (in world space) dropped and counted. O(total triangles), parallel.
TriangleSet flatten(const Scene& scene);

/// World-space triangles of one object: `mesh` placed by `transform`, tagged with `id`, exactly as
/// flatten() makes that object's part (same corners, same zero-area triangles dropped). O(triangles).
TriangleSet object_triangles(const TriangleMesh& mesh, const Transform& transform, ObjectId id);

/// Object-space triangles of `mesh` (zero-area ones dropped and counted), with instance = kInvalidId:
/// what a per-mesh structure shared by all objects of the mesh is built from. O(triangles), parallel.
TriangleSet mesh_triangles(const TriangleMesh& mesh);

}  // namespace vf

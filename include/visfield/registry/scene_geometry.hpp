#pragma once
/// \file A scene as the structures are built from it: the objects, and their world-space triangles
/// flattened on first use only (a scene of many instances may never need them).

#include <cstddef>
#include <optional>

#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf {

/// Borrows a Scene (which must outlive it) and flattens it at most once. Not thread-safe.
class SceneGeometry {
 public:
  /// Checks the scene's world coordinates (Scene::check_coordinate_range, throws vf::Error).
  explicit SceneGeometry(const Scene& scene);
  /// The scene.
  const Scene& scene() const { return scene_; }
  /// flatten(scene()), computed on the first call. O(instanced triangles) once.
  const TriangleSet& flattened();
  /// True once flattened() has run.
  bool is_flattened() const { return flat_.has_value(); }
  /// Triangles of every object (each mesh's count times its objects), without flattening.
  std::size_t instanced_triangle_count() const { return scene_.instanced_triangle_count(); }
  /// Triangles of the meshes some object uses, each mesh counted once.
  std::size_t unique_triangle_count() const;

 private:
  const Scene& scene_;
  std::optional<TriangleSet> flat_;
};

}  // namespace vf

#include "visfield/registry/scene_geometry.hpp"

#include <vector>

namespace vf {

SceneGeometry::SceneGeometry(const Scene& scene) : scene_(scene) {
  scene_.check_coordinate_range(scene.name.empty() ? "scene" : scene.name);
}

const TriangleSet& SceneGeometry::flattened() {
  if (!flat_) flat_ = flatten(scene_);
  return *flat_;
}

std::size_t SceneGeometry::unique_triangle_count() const {
  std::vector<std::uint8_t> used(scene_.meshes.size(), 0);
  std::size_t total = 0;
  for (const Instance& inst : scene_.instances()) {
    if (used[inst.mesh]) continue;
    used[inst.mesh] = 1;
    total += scene_.meshes[inst.mesh].triangles.size();
  }
  return total;
}

}  // namespace vf

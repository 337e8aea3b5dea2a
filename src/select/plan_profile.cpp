// The planner's view of a scene: counts, and sample rays through a two-level BVH and a uniform grid.
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "visfield/accel/bvh.hpp"
#include "visfield/accel/instance_layer.hpp"
#include "visfield/accel/uniform_grid.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/select/calibration.hpp"
#include "visfield/select/plan.hpp"
#include "visfield/select/workload.hpp"

namespace vf {
namespace {

// Timed passes of each sample. A pass of a few thousand rays takes a fraction of a millisecond, so
// one pass per timing swings by tens of per cent; the median of nine warm passes is stable, and warm
// as the calibration's repeated passes over its larger sets are (decisions right, leave-one-out over
// the built-in calibration: 83-85% with one cold pass per part, 87-88% with this).
constexpr int kProfileTimedPasses = 9;

}  // namespace

SceneProfile profile_scene(const Scene& scene, const TriangleSet* triangles, std::span<const RayKind> kinds,
                           std::size_t sample_rays, std::uint64_t seed, int path_bounces) {
  SceneProfile p;
  p.triangles = scene.instanced_triangle_count();
  p.objects = scene.instances().size();
  std::vector<std::uint8_t> used(scene.meshes.size(), 0);
  for (const Instance& instance : scene.instances()) {
    if (used[instance.mesh]) continue;
    used[instance.mesh] = 1;
    const std::size_t n = scene.meshes[instance.mesh].triangles.size();
    p.unique_triangles += n;
    p.mesh_log2_sum += cost_log2(n);
  }
  p.threads = threads_in_force();
  // The BVH over each mesh once and the objects: built from the meshes, so it costs little for a scene
  // of many copies and needs no flattening, and its time per ray tells every tree's (they differ from
  // it by a factor the calibration measures, and by their depth).
  const InstanceLayer bvh = InstanceLayer::build(scene, [](const TriangleSet& mesh) { return MeshStructure(Bvh::build(mesh)); });
  p.bvh_build_ms = bvh.stats().build_ms;
  const bool flattened = triangles && triangles->size() > 0;
  std::optional<UniformGrid> grid;
  if (flattened) {
    grid.emplace(UniformGrid::build(*triangles));
    p.grid_build_ms = grid->stats().build_ms;
  }
  const Bounds3f bounds = flattened ? triangles->bounds : scene.bounds();
  for (RayKind kind : kinds) {
    const QuerySet sample = make_queries(kind, bvh, scene, bounds, sample_rays, seed, path_bounces);
    const std::size_t k = plan_kind_index(kind);
    if (grid) p.grid_sample_us[k] = std::max(batch_passes_query_us(*grid, sample, kProfileTimedPasses), 0.0);
    p.bvh_sample_us[k] = std::max(batch_passes_query_us(bvh, sample, kProfileTimedPasses), 0.0);
  }
  const QuerySet ao = make_queries(RayKind::ao, bvh, scene, bounds, sample_rays, seed, path_bounces);
  std::size_t occluded = 0;
  for (const Ray& ray : ao.shadow) occluded += bvh.occluded(ray) ? 1 : 0;
  p.ao_occluded = ao.shadow.empty() ? 0.0 : static_cast<double>(occluded) / static_cast<double>(ao.shadow.size());
  return p;
}

}  // namespace vf

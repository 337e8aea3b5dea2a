// The planner's view of a scene: counts, and sample rays through a uniform grid.
#include <algorithm>
#include <cmath>
#include <vector>

#include "visfield/accel/uniform_grid.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/select/calibration.hpp"
#include "visfield/select/plan.hpp"
#include "visfield/select/workload.hpp"

namespace vf {

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
  if (!triangles || triangles->size() == 0) return p;
  const UniformGrid grid = UniformGrid::build(*triangles);
  p.grid_build_ms = grid.stats().build_ms;
  for (RayKind kind : kinds) {
    const SampleTiming sample = time_sample(kind, grid, scene, *triangles, sample_rays, seed, path_bounces, p.threads);
    p.grid_sample_us[plan_kind_index(kind)] = sample.query_us;
  }
  const QuerySet ao = make_queries(RayKind::ao, grid, scene, *triangles, sample_rays, seed, path_bounces);
  std::size_t occluded = 0;
  for (const Ray& ray : ao.shadow) occluded += grid.occluded(ray) ? 1 : 0;
  p.ao_occluded = ao.shadow.empty() ? 0.0 : static_cast<double>(occluded) / static_cast<double>(ao.shadow.size());
  return p;
}

}  // namespace vf

#include "shading_context.hpp"

namespace vf::render_detail {

Image render_raycast(const ShadingContext& context, const Camera& camera, RenderStats* stats) {
  return render_pixels("raycast", camera, context.options, stats, [&](const Ray& ray, Rng&, RayCounts& rays) {
    const Hit hit = context.queries.intersect_camera(ray);
    if (!hit) return Vec3f{0.0f};
    return local_lighting(context, surface_hit(context, ray, hit), /*shadows=*/false, /*highlights=*/false, rays);
  });
}

}  // namespace vf::render_detail

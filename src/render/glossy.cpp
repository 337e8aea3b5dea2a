#include "shading_context.hpp"

namespace vf::render_detail {

// Per sample: emission plus local lighting with hard shadows (the whole smooth lobe, so rough
// highlights show), and at a reflective surface options.glossy_rays rays drawn from the specular
// lobe (GGX by its normal distribution; a mirror's single direction). Each reflection ray's hit is
// shaded by its local light without shadows: off a field-represented object that is the field's
// distance and normal (SceneQueries::intersect_secondary), as in the GPU fields paper's reflections.
Image render_glossy(const ShadingContext& context, const Camera& camera, RenderStats* stats) {
  const float per_ray = 1.0f / static_cast<float>(context.options.glossy_rays);
  return render_pixels("glossy", camera, context.options, stats, [&](const Ray& ray, Rng& rng, RayCounts& rays) {
    const Hit hit = context.queries.intersect_camera(ray);
    if (!hit) return Vec3f{0.0f};
    const SurfaceHit surface = surface_hit(context, ray, hit);
    Vec3f radiance = surface.material->emission + local_lighting(context, surface, /*shadows=*/true, /*highlights=*/true, rays);
    if (!surface.bsdf.reflective()) return radiance;
    for (int k = 0; k < context.options.glossy_rays; ++k) {
      const std::optional<BsdfSample> sample = surface.bsdf.sample_specular(surface.wo, rng);
      if (!sample) continue;
      ++rays.reflection;
      const Ray reflected{surface.point.position, sample->wi};
      const Hit seen = context.queries.intersect_secondary(reflected);
      if (!seen) continue;
      const SurfaceHit there = surface_hit(context, reflected, seen);
      radiance += sample->weight * (there.material->emission + local_lighting(context, there, false, false, rays)) * per_ray;
    }
    return radiance;
  });
}

}  // namespace vf::render_detail

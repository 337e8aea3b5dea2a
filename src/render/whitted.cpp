#include <cmath>

#include "shading_context.hpp"

namespace vf::render_detail {
namespace {

// Radiance along `ray` (a camera ray at depth 0): local lighting with hard shadows, then one mirror
// ray for the specular colour plus the dielectric's Fresnel reflection, and one refracted ray for the
// rest of the dielectric, each while depth < max_depth. Classic Whitted: no random numbers.
Vec3f whitted_radiance(const ShadingContext& context, const Ray& ray, int depth, RayCounts& rays) {
  const Hit hit = depth == 0 ? context.queries.intersect_camera(ray) : context.queries.intersect_secondary(ray);
  if (!hit) return Vec3f{0.0f};
  const SurfaceHit surface = surface_hit(context, ray, hit);
  Vec3f radiance = surface.material->emission + local_lighting(context, surface, /*shadows=*/true, /*highlights=*/false, rays);
  if (depth >= context.options.max_depth) return radiance;
  const Material& m = *surface.material;
  const Vec3f& n = surface.point.normal;
  const float cos_o = dot(surface.wo, n);
  const float eta = surface.point.entering ? 1.0f / m.ior : m.ior;
  const float transmission = std::fmin(std::fmax(m.transmission, 0.0f), 1.0f);
  const float fresnel = transmission > 0.0f ? fresnel_dielectric(cos_o, eta) : 0.0f;
  const Vec3f mirror = m.specular * (1.0f - transmission) + Vec3f{transmission * fresnel};
  if (max_component(mirror) > 0.0f) {
    ++rays.reflection;
    radiance += mirror * whitted_radiance(context, Ray{surface.point.position, reflect(surface.wo, n)}, depth + 1, rays);
  }
  if (transmission > 0.0f && fresnel < 1.0f)
    if (const std::optional<Vec3f> through = refract(surface.wo, n, eta)) {
      ++rays.reflection;
      radiance += whitted_radiance(context, Ray{surface.point.behind, *through}, depth + 1, rays) *
                  (transmission * (1.0f - fresnel) * eta * eta);
    }
  return radiance;
}

}  // namespace

Image render_whitted(const ShadingContext& context, const Camera& camera, RenderStats* stats) {
  return render_pixels("whitted", camera, context.options, stats,
                       [&](const Ray& ray, Rng&, RayCounts& rays) { return whitted_radiance(context, ray, 0, rays); });
}

}  // namespace vf::render_detail

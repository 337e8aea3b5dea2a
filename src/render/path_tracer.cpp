#include <algorithm>
#include <cmath>

#include "shading_context.hpp"

namespace vf::render_detail {
namespace {

constexpr int kRouletteDepth = 3;  // bounces before Russian roulette may end a path

// Power heuristic (beta = 2) weight of a strategy with density `a` against one with density `b`.
float power_heuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

// Light arriving at a path vertex: one light sample (NEE) through its shadow ray, weighted against
// the Bsdf's own chance of finding it (MIS), point lights unweighted (no Bsdf reaches them).
Vec3f sample_direct(const ShadingContext& context, const SurfaceHit& surface, Rng& rng, RayCounts& rays) {
  const std::optional<LightSample> light = context.lights.sample(surface.point.position, rng);
  if (!light) return Vec3f{0.0f};
  const Vec3f f_cos = surface.bsdf.eval(surface.wo, light->wi);
  if (!(max_component(f_cos) > 0.0f)) return Vec3f{0.0f};
  ++rays.shadow;
  const Ray shadow{surface.point.position, light->wi, 0.0f, light->distance * (1.0f - 1e-4f)};
  if (context.queries.occluded(shadow)) return Vec3f{0.0f};
  if (light->delta) return f_cos * light->radiance;
  const float weight = power_heuristic(light->pdf, surface.bsdf.pdf(surface.wo, light->wi));
  return f_cos * light->radiance * (weight / light->pdf);
}

// One path from the camera ray: at each vertex the emission it sees (MIS-weighted against light
// sampling unless the previous bounce was a delta lobe or the camera), a light sample, then a Bsdf
// bounce; sphere lights are met analytically along every ray; Russian roulette after kRouletteDepth
// bounces; at most options.max_depth bounces.
Vec3f path_radiance(const ShadingContext& context, Ray ray, Rng& rng, RayCounts& rays) {
  Vec3f radiance{0.0f}, throughput{1.0f};
  bool specular = true;  // the camera, or a delta bounce: emission is counted unweighted
  float bsdf_pdf = 0.0f;
  Vec3f previous = ray.org;
  for (int depth = 0;; ++depth) {
    const Hit hit = depth == 0 ? context.queries.intersect_camera(ray) : context.queries.intersect_secondary(ray);
    if (const std::optional<SphereLightHit> lamp = context.lights.first_sphere(ray, hit ? hit.t : ray.tmax)) {
      const Vec3f& emitted = context.lights.sphere_lights()[lamp->light].radiance;
      const float weight = specular ? 1.0f : power_heuristic(bsdf_pdf, context.lights.sphere_pdf(lamp->light, previous));
      radiance += throughput * emitted * weight;
      break;
    }
    if (!hit) break;
    const SurfaceHit surface = surface_hit(context, ray, hit);
    if (max_component(surface.material->emission) > 0.0f) {
      float weight = 1.0f;
      if (!specular && hit.has_triangle()) {
        const Vec3f at = ray.org + ray.dir * hit.t;
        weight = power_heuristic(bsdf_pdf, context.lights.emitter_pdf(hit.instance, hit.prim, previous, at, hit.normal));
      }
      radiance += throughput * surface.material->emission * weight;
    }
    if (depth >= context.options.max_depth) break;
    if (surface.bsdf.has_smooth_lobe()) radiance += throughput * sample_direct(context, surface, rng, rays);
    const std::optional<BsdfSample> bounce = surface.bsdf.sample(surface.wo, rng);
    if (!bounce) break;
    throughput = throughput * bounce->weight;
    if (depth + 1 >= kRouletteDepth) {
      const float survive = std::clamp(max_component(throughput), 0.05f, 1.0f);
      if (rng.uniform() >= survive) break;
      throughput = throughput * (1.0f / survive);
    }
    specular = bounce->delta;
    bsdf_pdf = bounce->pdf;
    previous = surface.point.position;
    ray = Ray{bounce->transmitted ? surface.point.behind : surface.point.position, bounce->wi};
    ++rays.reflection;
  }
  return radiance;
}

}  // namespace

Image render_path(const ShadingContext& context, const Camera& camera, RenderStats* stats) {
  return render_pixels("path", camera, context.options, stats,
                       [&](const Ray& ray, Rng& rng, RayCounts& rays) { return path_radiance(context, ray, rng, rays); });
}

}  // namespace vf::render_detail

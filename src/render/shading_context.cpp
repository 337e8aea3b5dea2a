#include "shading_context.hpp"

#include <cmath>
#include <numbers>

#include "visfield/core/error.hpp"
#include "visfield/render/tiles.hpp"

namespace vf {
namespace render_detail {

SurfaceHit surface_hit(const ShadingContext& context, const Ray& ray, const Hit& hit) {
  const SurfacePoint point = context.spawner.surface_point(ray, hit);
  const Material& material = context.scene.material_of(hit.instance, hit.prim);
  return SurfaceHit{point, &material, Bsdf(material, point, point.entering), -normalize(ray.dir)};
}

Vec3f local_lighting(const ShadingContext& context, const SurfaceHit& surface, bool shadows, bool highlights, RayCounts& rays) {
  const Vec3f diffuse = surface.bsdf.diffuse();
  Vec3f radiance = diffuse * context.options.ambient;
  auto add = [&](const Vec3f& position, const Vec3f& intensity) {
    const Vec3f to = position - surface.point.position;
    const float d2 = dot(to, to);
    if (!(d2 > 0.0f)) return;
    const Vec3f wi = to * (1.0f / std::sqrt(d2));
    const float cos_i = dot(wi, surface.point.normal);
    if (!(cos_i > 0.0f)) return;
    const Vec3f f_cos = highlights ? surface.bsdf.eval(surface.wo, wi) : diffuse * (cos_i / std::numbers::pi_v<float>);
    if (!(max_component(f_cos) > 0.0f)) return;
    if (shadows) {
      ++rays.shadow;
      if (context.queries.occluded(shadow_ray(surface.point, position))) return;
    }
    radiance += f_cos * intensity * (1.0f / d2);
  };
  for (const PointLight& light : context.lights.point_lights()) add(light.position, light.intensity);
  for (const SphereLight& light : context.lights.sphere_lights())
    add(light.center, light.radiance * (std::numbers::pi_v<float> * light.radius * light.radius));
  return radiance;
}

Image render_pixels(const char* label, const Camera& camera, const ShadingOptions& options, RenderStats* stats,
                    const SampleShader& shade) {
  const PinholeCamera pinhole(camera);
  const ImageTile region = render_region(options.region, pinhole.width(), pinhole.height());
  Image image(region.x1 - region.x0, region.y1 - region.y0);
  auto shade_tile = [&](const ImageTile& tile) -> RayCounts {
    RayCounts rays;
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        const std::uint64_t pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(pinhole.width()) + x;
        Vec3f sum{0.0f};
        for (int s = 0; s < options.spp; ++s) {
          Rng rng(options.seed, pixel, static_cast<std::uint64_t>(s));
          const Ray camera_ray = pixel_ray(pinhole, x, y, options.spp > 1, rng);
          ++rays.camera;
          sum += shade(camera_ray, rng, rays);
        }
        image.at(x - region.x0, y - region.y0) = sum * (1.0f / static_cast<float>(options.spp));
      }
    return rays;
  };
  for_each_tile(region, options.tile_size, label, options.progress, shade_tile, stats);
  return image;
}

}  // namespace render_detail

void validate_shading_options(const ShadingOptions& o) {
  auto at_least_one = [](const char* name, int value) {
    if (value < 1) throw Error(std::string("render: ") + name + " must be at least 1, got " + std::to_string(value));
  };
  at_least_one("spp", o.spp);
  at_least_one("tile_size", o.tile_size);
  at_least_one("max_depth", o.max_depth);
  at_least_one("shadow_rays", o.shadow_rays);
  at_least_one("glossy_rays", o.glossy_rays);
  if (!(o.ambient >= 0.0f) || !std::isfinite(o.ambient))
    throw Error("render: ambient must be a finite number >= 0, got " + std::to_string(o.ambient));
}

Image render_shaded(Integrator integrator, const SceneQueries& queries, const Scene& scene, const Camera& camera,
                    const ShadingOptions& options, RenderStats* stats) {
  validate_shading_options(options);
  using namespace render_detail;
  switch (integrator) {
    case Integrator::raycast: return render_raycast(ShadingContext(queries, scene, options, false), camera, stats);
    case Integrator::whitted: return render_whitted(ShadingContext(queries, scene, options, false), camera, stats);
    case Integrator::softshadow: return render_soft_shadows(ShadingContext(queries, scene, options, false), camera, stats);
    case Integrator::glossy: return render_glossy(ShadingContext(queries, scene, options, false), camera, stats);
    case Integrator::path: return render_path(ShadingContext(queries, scene, options, true), camera, stats);
    case Integrator::ao: break;
  }
  throw Error("render: the ao integrator is render_ao()");
}

}  // namespace vf

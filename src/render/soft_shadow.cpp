#include <cmath>
#include <span>
#include <vector>

#include "occlusion_batch.hpp"
#include "shading_context.hpp"
#include "visfield/render/tiles.hpp"

namespace vf::render_detail {

static_assert(OcclusionBatch::kSlack >= kSphereLightRaysSlack, "sphere_light_rays() writes whole packets into the batch's room");

// Per sample: emission and ambient, each point light by one shadow ray, and each sphere light by
// options.shadow_rays rays uniform in the cone it subtends (the estimator f cos L / pdf, averaged).
// A tile's shadow rays are traced together (OcclusionBatch), so field occluders run their batch
// kernel; contributions are summed in the order they were made, so the image is the ray-by-ray one.
Image render_soft_shadows(const ShadingContext& context, const Camera& camera, RenderStats* stats) {
  const ShadingOptions& options = context.options;
  const PinholeCamera pinhole(camera);
  const ImageTile region = render_region(options.region, pinhole.width(), pinhole.height());
  Image image(region.x1 - region.x0, region.y1 - region.y0);
  auto shade_tile = [&](const ImageTile& tile) -> RayCounts {
    RayCounts rays;
    const std::size_t samples = static_cast<std::size_t>(tile.x1 - tile.x0) * static_cast<std::size_t>(tile.y1 - tile.y0) *
                                static_cast<std::size_t>(options.spp);
    OcclusionBatch batch(context.queries, samples);
    std::vector<Vec3f> base(samples, Vec3f{0.0f});  // what needs no shadow ray: emission and ambient
    std::size_t slot = 0;
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        const std::uint64_t pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(pinhole.width()) + x;
        for (int s = 0; s < options.spp; ++s, ++slot) {
          Rng rng(options.seed, pixel, static_cast<std::uint64_t>(s));
          const Ray primary = pixel_ray(pinhole, x, y, options.spp > 1, rng);
          ++rays.camera;
          const Hit hit = context.queries.intersect_camera(primary);
          if (!hit) continue;
          const SurfaceHit surface = surface_hit(context, primary, hit);
          base[slot] = surface.material->emission + surface.bsdf.diffuse() * options.ambient;
          for (const PointLight& light : context.lights.point_lights()) {
            const Vec3f to = light.position - surface.point.position;
            const float d2 = dot(to, to);
            const Vec3f f_cos = d2 > 0.0f ? surface.bsdf.eval(surface.wo, to * (1.0f / std::sqrt(d2))) : Vec3f{0.0f};
            if (!(max_component(f_cos) > 0.0f)) continue;
            ++rays.shadow;
            batch.add(shadow_ray(surface.point, light.position), slot, f_cos * light.intensity * (1.0f / d2));
          }
          // The sphere lights' samples drawn, shaded and queued together (on lanes where the surface is Lambertian).
          const std::span<const SphereLight> spheres = context.lights.sphere_lights();
          if (spheres.empty()) continue;
          const OcclusionBatch::Room room = batch.reserve_each(spheres.size() * static_cast<std::size_t>(options.shadow_rays));
          const std::size_t queued = sphere_light_rays(spheres, surface.point.position, surface.bsdf, surface.wo, options.shadow_rays, rng,
                                                       room.rays, room.contributions);
          batch.commit_each(queued, slot);
          rays.shadow += queued;
        }
      }
    batch.flush();
    slot = 0;
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        Vec3f sum{0.0f};
        for (int s = 0; s < options.spp; ++s, ++slot) sum += base[slot] + batch.sum(slot);
        image.at(x - region.x0, y - region.y0) = sum * (1.0f / static_cast<float>(options.spp));
      }
    return rays;
  };
  for_each_tile(region, options.tile_size, "softshadow", options.progress, shade_tile, stats);
  return image;
}

}  // namespace vf::render_detail

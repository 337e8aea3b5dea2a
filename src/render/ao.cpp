#include "visfield/render/ao.hpp"

#include <cmath>
#include <optional>
#include <vector>

#include "occlusion_batch.hpp"
#include "visfield/core/direction_lines.hpp"
#include "visfield/core/error.hpp"
#include "visfield/render/camera.hpp"
#include "visfield/render/sample_rays.hpp"
#include "visfield/render/tiles.hpp"

namespace vf {

void validate_ao_options(const AoOptions& options) {
  if (options.spp < 1) throw Error("ao: spp must be at least 1, got " + std::to_string(options.spp));
  if (options.ao_rays < 1) throw Error("ao: ao_rays must be at least 1, got " + std::to_string(options.ao_rays));
  if (!(options.max_distance > 0.0f))
    throw Error("ao: max_distance must be positive, got " + std::to_string(options.max_distance));
  if (options.psf_level != 0 && (options.psf_level < DirectionLines::kMinLevel || options.psf_level > DirectionLines::kMaxLevel))
    throw Error("ao: psf_level must be 0 or in [2, 6], got " + std::to_string(options.psf_level));
  if (options.tile_size < 1) throw Error("ao: tile_size must be at least 1, got " + std::to_string(options.tile_size));
}

Image render_ao(const SceneQueries& queries, const Scene& scene, const Camera& camera, const AoOptions& opt,
                RenderStats* stats) {
  validate_ao_options(opt);
  const PinholeCamera pinhole(camera);
  const SurfaceSpawner spawner(scene);
  const ImageTile region = render_region(opt.region, pinhole.width(), pinhole.height());
  Image image(region.x1 - region.x0, region.y1 - region.y0);
  const std::optional<DirectionLines> lines =
      opt.psf_level > 0 ? std::optional<DirectionLines>(std::in_place, opt.psf_level) : std::nullopt;
  auto shade_tile = [&](const ImageTile& tile) -> RayCounts {
    RayCounts rays;
    const std::size_t samples = static_cast<std::size_t>(tile.x1 - tile.x0) * static_cast<std::size_t>(tile.y1 - tile.y0) *
                                static_cast<std::size_t>(opt.spp);
    render_detail::OcclusionBatch batch(queries, samples);
    std::vector<float> total(samples, 0.0f);  // the weight of each sample's AO rays; < 0 for a miss
    std::size_t slot = 0;
    for (int y = tile.y0; y < tile.y1; ++y) {
      for (int x = tile.x0; x < tile.x1; ++x) {
        const std::uint64_t pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(pinhole.width()) + x;
        for (int s = 0; s < opt.spp; ++s, ++slot) {
          Rng rng(opt.seed, pixel, static_cast<std::uint64_t>(s));
          const Ray primary = pixel_ray(pinhole, x, y, opt.spp > 1, rng);
          ++rays.camera;
          const Hit hit = queries.intersect_camera(primary);
          if (!hit) {
            total[slot] = -1.0f;
            continue;
          }
          const SurfacePoint point = spawner.surface_point(primary, hit);
          if (lines) {
            for (std::size_t k = 0; k < lines->size(); ++k) {
              const Vec3f& w = lines->direction(k);
              const float c = dot(point.normal, w);
              if (c == 0.0f) continue;
              ++rays.ao;
              total[slot] += std::fabs(c);
              batch.add(Ray{point.position, c > 0.0f ? w : -w, 0.0f, opt.max_distance}, slot, Vec3f{std::fabs(c)});
            }
          } else {
            for (int k = 0; k < opt.ao_rays; ++k) batch.add(ao_ray(point, rng, opt.max_distance), slot, Vec3f{1.0f});
            total[slot] = static_cast<float>(opt.ao_rays);
            rays.ao += static_cast<std::uint64_t>(opt.ao_rays);
          }
        }
      }
    }
    batch.flush();
    slot = 0;
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        float sum = 0.0f;
        for (int s = 0; s < opt.spp; ++s, ++slot)
          sum += total[slot] < 0.0f ? kAoBackground : total[slot] > 0.0f ? batch.sum(slot).x / total[slot] : 1.0f;
        image.at(x - region.x0, y - region.y0) = Vec3f(sum / static_cast<float>(opt.spp));
      }
    return rays;
  };
  for_each_tile(region, opt.tile_size, "ao", opt.progress, shade_tile, stats);
  return image;
}

}  // namespace vf

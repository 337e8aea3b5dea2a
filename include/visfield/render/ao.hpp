#pragma once
/// \file Ambient occlusion: per pixel, the fraction of cosine-weighted directions from the first
/// visible surface that reach max_distance (or the sky) unoccluded. Grey, no albedo. Camera rays go
/// to one structure (the closest-hit role) and occlusion rays to another (the occlusion role), which
/// may be the same object, an exact one or an approximate one.

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "visfield/accel/query.hpp"
#include "visfield/core/direction_lines.hpp"
#include "visfield/core/image.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/render/camera.hpp"
#include "visfield/render/render_stats.hpp"
#include "visfield/render/sample_rays.hpp"
#include "visfield/render/tiles.hpp"

namespace vf {

/// Parameters of render_ao.
struct AoOptions {
  int spp = 1;                 ///< Primary samples per pixel (>= 1): the pixel centre when 1, jittered when more.
  int ao_rays = 64;            ///< Occlusion rays per primary hit (>= 1).
  float max_distance = std::numeric_limits<float>::infinity();  ///< Occluders farther than this do not count (> 0).
  std::uint64_t seed = 1;      ///< The image depends on this seed only, never on threads or tiles.
  int tile_size = 16;          ///< Tile edge in pixels (>= 1): the unit of parallel work and of progress.
  bool progress = true;        ///< Progress bar on stderr for renders that take over ~1 s.
  /// 0: `ao_rays` random cosine-weighted directions per hit. L in [2, 6]: instead one ray along each
  /// line of the level-L octahedral set (33, 129, 513, 2049, 8193 lines), turned into the normal's
  /// hemisphere and weighted by the cosine (VLF-RT §7: a BeamField of the same level answers every
  /// one of them on its single-tile fast path). Deterministic; no random numbers.
  int psf_level = 0;
};

/// Value of a pixel sample whose primary ray misses everything: an unoccluded white sky.
inline constexpr float kAoBackground = 1.0f;

/// Throws vf::Error naming the field when an option is out of range.
void validate_ao_options(const AoOptions& options);

/// Ambient occlusion of one primary hit: the fraction of `ao_rays` rays from `point` (drawn from `rng`
/// by ao_ray()) that occluder.occluded() reports clear.
template <OcclusionQuery O>
float ambient_occlusion(const O& occluder, const SurfacePoint& point, Rng& rng, int ao_rays, float max_distance) {
  int clear = 0;
  for (int k = 0; k < ao_rays; ++k) clear += occluder.occluded(ao_ray(point, rng, max_distance)) ? 0 : 1;
  return static_cast<float>(clear) / static_cast<float>(ao_rays);
}

/// Ambient occlusion of one primary hit along the lines of `lines`: every line not perpendicular to the
/// normal gives one ray along its stored direction or its negation (whichever faces the normal's side),
/// weighted by |cos| to the normal; the result is the weighted fraction that occluder.occluded()
/// reports clear. Adds the rays traced to `rays`.
template <OcclusionQuery O>
float psf_ambient_occlusion(const O& occluder, const SurfacePoint& point, const DirectionLines& lines, float max_distance,
                            std::uint64_t& rays) {
  float clear = 0.0f, total = 0.0f;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const Vec3f& w = lines.direction(k);
    const float c = dot(point.normal, w);
    if (c == 0.0f) continue;
    const Ray ray{point.position, c > 0.0f ? w : -w, 0.0f, max_distance};
    ++rays;
    total += std::fabs(c);
    if (!occluder.occluded(ray)) clear += std::fabs(c);
  }
  return total > 0.0f ? clear / total : 1.0f;
}

/// Renders `camera`'s view of `scene` with ambient occlusion, camera rays traced through `closest` and
/// AO rays through `occluder` (both built over `scene`; they may be the same structure): per pixel and
/// sample s, Rng(seed, pixel, s) draws the jitter and the AO directions; the pixel is the mean over
/// samples of the unoccluded fraction, or kAoBackground on a miss. Parallel over tiles; identical
/// images for any thread count. `stats` (optional) gets every ray traced and the wall time. Throws
/// vf::Error on bad options or camera. Cost: width*height*spp*(1 + ao_rays * hit fraction) queries.
template <ClosestHitQuery C, OcclusionQuery O>
Image render_ao(const C& closest, const O& occluder, const Scene& scene, const Camera& camera, const AoOptions& opt,
                RenderStats* stats = nullptr) {
  validate_ao_options(opt);
  const PinholeCamera pinhole(camera);
  const SurfaceSpawner spawner(scene);
  Image image(pinhole.width(), pinhole.height());
  const std::optional<DirectionLines> lines =
      opt.psf_level > 0 ? std::optional<DirectionLines>(std::in_place, opt.psf_level) : std::nullopt;
  auto shade_tile = [&](const ImageTile& tile) -> std::uint64_t {
    std::uint64_t rays = 0;
    for (int y = tile.y0; y < tile.y1; ++y) {
      for (int x = tile.x0; x < tile.x1; ++x) {
        const std::uint64_t pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(image.width) + x;
        float sum = 0.0f;
        for (int s = 0; s < opt.spp; ++s) {
          Rng rng(opt.seed, pixel, static_cast<std::uint64_t>(s));
          const Ray primary = pixel_ray(pinhole, x, y, opt.spp > 1, rng);
          ++rays;
          const Hit hit = closest.intersect(primary);
          if (!hit) {
            sum += kAoBackground;
            continue;
          }
          const SurfacePoint point = spawner.surface_point(primary, hit);
          if (lines) {
            sum += psf_ambient_occlusion(occluder, point, *lines, opt.max_distance, rays);
          } else {
            sum += ambient_occlusion(occluder, point, rng, opt.ao_rays, opt.max_distance);
            rays += static_cast<std::uint64_t>(opt.ao_rays);
          }
        }
        image.at(x, y) = Vec3f(sum / static_cast<float>(opt.spp));
      }
    }
    return rays;
  };
  for_each_tile(image.width, image.height, opt.tile_size, "ao", opt.progress, shade_tile, stats);
  return image;
}

}  // namespace vf

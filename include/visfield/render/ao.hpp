#pragma once
/// \file Ambient occlusion: per pixel, the fraction of cosine-weighted directions from the first
/// visible surface that reach max_distance (or the sky) unoccluded. Grey, no albedo. Camera rays go
/// to one structure (the closest-hit role) and occlusion rays to another (the occlusion role), which
/// may be the same object, an exact one or an approximate one.

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "visfield/accel/batch.hpp"
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

namespace detail {

/// The AO rays of one tile's pixel samples on their way to a batch query: each ray with the sample
/// it belongs to and its weight (1 for random directions, |cos| for the line set). Traced
/// kCapacity at a time through occluded_block(), so an occluder with a batch path (the ObjectFields'
/// SIMD kernel) runs it; the unoccluded weights are summed per sample in the order the rays were
/// added, which is the order the per-ray loop always summed them in: images do not change.
struct AoRayBatch {
  static constexpr std::size_t kCapacity = 4096;
  std::vector<Ray> rays;
  std::vector<std::uint32_t> sample;
  std::vector<float> weight;
  std::vector<std::uint8_t> occluded;
  std::vector<float> clear;  ///< Per sample of the tile: the weight of its unoccluded rays so far.

  template <OcclusionQuery O>
  void flush(const O& occluder) {
    occluded.resize(rays.size());
    occluded_block(occluder, std::span<const Ray>(rays), std::span<std::uint8_t>(occluded));
    for (std::size_t i = 0; i < rays.size(); ++i)
      if (!occluded[i]) clear[sample[i]] += weight[i];
    rays.clear();
    sample.clear();
    weight.clear();
  }
  template <OcclusionQuery O>
  void add(const O& occluder, const Ray& ray, std::size_t of_sample, float w) {
    rays.push_back(ray);
    sample.push_back(static_cast<std::uint32_t>(of_sample));
    weight.push_back(w);
    if (rays.size() == kCapacity) flush(occluder);
  }
};

}  // namespace detail

/// Renders `camera`'s view of `scene` with ambient occlusion, camera rays traced through `closest` and
/// AO rays through `occluder` (both built over `scene`; they may be the same structure): per pixel and
/// sample s, Rng(seed, pixel, s) draws the jitter and the AO directions; the pixel is the mean over
/// samples of the unoccluded fraction (of `ao_rays` cosine-weighted rays, or, with `psf_level`, of
/// one ray along each line not perpendicular to the normal, weighted by |cos|), or kAoBackground on
/// a miss. A tile's AO rays are traced together (occluded_block), so occluders with a batch path use
/// it. Parallel over tiles; identical images for any thread count. `stats` (optional) gets every ray
/// traced and the wall time. Throws vf::Error on bad options or camera. Cost:
/// width*height*spp*(1 + ao_rays * hit fraction) queries.
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
    const std::size_t samples = static_cast<std::size_t>(tile.x1 - tile.x0) * static_cast<std::size_t>(tile.y1 - tile.y0) *
                                static_cast<std::size_t>(opt.spp);
    detail::AoRayBatch batch;
    batch.clear.assign(samples, 0.0f);
    std::vector<float> total(samples, 0.0f);  // the weight of each sample's AO rays; < 0 for a miss
    std::size_t slot = 0;
    for (int y = tile.y0; y < tile.y1; ++y) {
      for (int x = tile.x0; x < tile.x1; ++x) {
        const std::uint64_t pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(image.width) + x;
        for (int s = 0; s < opt.spp; ++s, ++slot) {
          Rng rng(opt.seed, pixel, static_cast<std::uint64_t>(s));
          const Ray primary = pixel_ray(pinhole, x, y, opt.spp > 1, rng);
          ++rays;
          const Hit hit = closest.intersect(primary);
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
              ++rays;
              total[slot] += std::fabs(c);
              batch.add(occluder, Ray{point.position, c > 0.0f ? w : -w, 0.0f, opt.max_distance}, slot, std::fabs(c));
            }
          } else {
            for (int k = 0; k < opt.ao_rays; ++k) batch.add(occluder, ao_ray(point, rng, opt.max_distance), slot, 1.0f);
            total[slot] = static_cast<float>(opt.ao_rays);
            rays += static_cast<std::uint64_t>(opt.ao_rays);
          }
        }
      }
    }
    batch.flush(occluder);
    slot = 0;
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        float sum = 0.0f;
        for (int s = 0; s < opt.spp; ++s, ++slot)
          sum += total[slot] < 0.0f ? kAoBackground : total[slot] > 0.0f ? batch.clear[slot] / total[slot] : 1.0f;
        image.at(x, y) = Vec3f(sum / static_cast<float>(opt.spp));
      }
    return rays;
  };
  for_each_tile(image.width, image.height, opt.tile_size, "ao", opt.progress, shade_tile, stats);
  return image;
}

}  // namespace vf

#pragma once
/// \file Fixed ray sets for benchmarks and tests: the primary, ambient-occlusion and shadow rays of a
/// view (exactly the rays the renderers trace), and the "random rays" of the grids-vs-hierarchies paper.
/// Every set is a pure function of its arguments: same inputs, same rays, whatever the thread count.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "visfield/accel/query.hpp"
#include "visfield/accel/batch.hpp"
#include "visfield/core/direction_lines.hpp"
#include "visfield/core/bounds.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/scene.hpp"

namespace vf {

/// One ray per pixel centre of `camera`, row-major from the top-left (the scene is not consulted: all
/// ray-set generators take the same (scene, camera) pair). Throws vf::Error on a bad camera or when the
/// set would not fit in memory. O(pixels).
std::vector<Ray> make_primary_rays(const Scene& scene, const Camera& camera);

/// The AO rays of the primary hits: for each pixel whose ray hits (pixel order), `rays_per_hit` rays
/// drawn from Rng(seed, pixel, 0) by ao_ray(), exactly the rays render_ao traces with spp = 1 and the
/// same seed, ao_rays and max_distance. `primary` and `hits` come from make_primary_rays and a closest-hit
/// pass. Throws vf::Error on rays_per_hit < 1, max_distance <= 0 or a set that would not fit in memory.
std::vector<Ray> ao_rays_from_hits(const Scene& scene, std::span<const Ray> primary, std::span<const Hit> hits,
                                   int rays_per_hit, float max_distance, std::uint64_t seed);

/// VLF-RT's AO rays of the primary hits: for each pixel whose ray hits (pixel order), one ray along each
/// line of `lines` (its stored direction, or the negation on the normal's side), exactly the rays
/// render_ao traces with psf_level = lines.level() and spp = 1 (a line perpendicular to the normal
/// gives a ray along its stored direction, which render_ao skips). Throws vf::Error on max_distance
/// <= 0 or a set that would not fit in memory.
std::vector<Ray> psf_ao_rays_from_hits(const Scene& scene, std::span<const Ray> primary, std::span<const Hit> hits,
                                       const DirectionLines& lines, float max_distance);

/// One shadow ray per primary hit (pixel order), from the surface point towards a point on one of the
/// scene's lights drawn from Rng(seed, pixel, 0) by LightTargets (above the scene when it has no light),
/// stopping just short of the light.
std::vector<Ray> shadow_rays_from_hits(const Scene& scene, std::span<const Ray> primary, std::span<const Hit> hits,
                                       std::uint64_t seed);

/// AO rays of `camera`'s view, the primary hits found by `closest` (built over `scene`); see
/// ao_rays_from_hits.
template <ClosestHitQuery C>
std::vector<Ray> make_ao_rays(const C& closest, const Scene& scene, const Camera& camera, int rays_per_hit,
                              float max_distance, std::uint64_t seed) {
  const std::vector<Ray> primary = make_primary_rays(scene, camera);
  std::vector<Hit> hits(primary.size());
  intersect_batch(closest, std::span<const Ray>(primary), std::span<Hit>(hits));
  return ao_rays_from_hits(scene, primary, hits, rays_per_hit, max_distance, seed);
}

/// psf_ao_rays_from_hits for `camera`'s view, the primary hits found by `closest`.
template <ClosestHitQuery C>
std::vector<Ray> make_psf_ao_rays(const C& closest, const Scene& scene, const Camera& camera, const DirectionLines& lines,
                                  float max_distance) {
  const std::vector<Ray> primary = make_primary_rays(scene, camera);
  std::vector<Hit> hits(primary.size());
  intersect_batch(closest, std::span<const Ray>(primary), std::span<Hit>(hits));
  return psf_ao_rays_from_hits(scene, primary, hits, lines, max_distance);
}

/// Shadow rays of `camera`'s view, the primary hits found by `closest`; see shadow_rays_from_hits.
template <ClosestHitQuery C>
std::vector<Ray> make_shadow_rays(const C& closest, const Scene& scene, const Camera& camera, std::uint64_t seed) {
  const std::vector<Ray> primary = make_primary_rays(scene, camera);
  std::vector<Hit> hits(primary.size());
  intersect_batch(closest, std::span<const Ray>(primary), std::span<Hit>(hits));
  return shadow_rays_from_hits(scene, primary, hits, seed);
}

/// `count` segments between two independent uniform random points on the bounding sphere of `bounds`
/// (centre, half the diagonal), the "random rays" of Havran's grids-vs-hierarchies paper: unit
/// direction, t in [0, segment length]. Ray i is drawn from Rng(seed, i). Throws vf::Error on empty
/// bounds or a set that would not fit in memory.
std::vector<Ray> make_random_rays(const Bounds3f& bounds, std::size_t count, std::uint64_t seed);

}  // namespace vf

#pragma once
/// \file Fixed ray sets for benchmarks and tests: the primary, ambient-occlusion and shadow rays of a
/// view (exactly the rays the renderers trace), and the "random rays" of the grids-vs-hierarchies paper.
/// Every set is a pure function of its arguments: same inputs, same rays, whatever the thread count.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "visfield/accel/query.hpp"
#include "visfield/accel/batch.hpp"
#include "visfield/core/direction_lines.hpp"
#include "visfield/core/bounds.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/render/ray_kind.hpp"

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

/// What to generate. Deterministic: the same request gives the same rays on every machine and
/// thread count (given structures that agree on the primary hits).
struct RaySetRequest {
  RayKind kind = RayKind::primary;
  Camera camera;    ///< Base camera; its resolution sets the default ray count.
  int ao_rays = 4;  ///< AO rays per primary hit.
  int psf_level = 0;  ///< 0: random AO directions; L: one AO ray along each line of the level-L set (VLF-RT).
  float max_distance = std::numeric_limits<float>::infinity();  ///< Length of AO rays, scene units.
  std::optional<std::size_t> count;  ///< Exact ray count; absent = whatever the camera's image gives.
  std::uint64_t seed = 1;
};

/// Picks `count` rays spread evenly over `rays` (indices floor(i * size / count)), keeping their
/// order. Needs 1 <= count <= rays.size() and count < 2^32.
std::vector<Ray> take_evenly(const std::vector<Ray>& rays, std::size_t count);

/// Rays from `generate(camera)`, brought to exactly `count` rays when given: when the image could
/// give over 4 count rays (at most `rays_per_pixel` per pixel) the camera is first scaled down to
/// about count / rays_per_pixel pixels; then its resolution is scaled up (same aspect) until the
/// image yields at least `count` rays, and take_evenly picks `count`. Throws vf::Error when the
/// image yields no ray at all (nothing seen) or when reaching `count` would need an image beyond
/// 65536 pixels a side.
std::vector<Ray> rays_for_count(const Camera& camera, std::optional<std::size_t> count,
                                const std::function<std::vector<Ray>(const Camera&)>& generate,
                                std::size_t rays_per_pixel = 1);

/// A fixed ray set of `request.kind` (the benchmark's, the planner's samples). AO and shadow rays start at primary hits found with `hits_from` (any
/// exact structure gives the same hits); random rays come from make_random_rays over the scene
/// bounds, `count` of them (default: one per pixel of the camera's image). Path rays are traced,
/// not fixed: make_path_rays (select/path_rays.hpp) makes them (throws vf::Error here).
template <ClosestHitQuery C>
std::vector<Ray> make_ray_set(const C& hits_from, const Scene& scene, const RaySetRequest& request) {
  switch (request.kind) {
    case RayKind::primary:
      return rays_for_count(request.camera, request.count,
                            [&](const Camera& camera) { return make_primary_rays(scene, camera); });
    case RayKind::ao:
      return rays_for_count(
          request.camera, request.count,
          [&](const Camera& camera) {
            if (request.psf_level > 0)
              return make_psf_ao_rays(hits_from, scene, camera, DirectionLines(request.psf_level), request.max_distance);
            return make_ao_rays(hits_from, scene, camera, request.ao_rays, request.max_distance, request.seed);
          },
          request.psf_level > 0 ? DirectionLines::count(request.psf_level) : static_cast<std::size_t>(request.ao_rays));
    case RayKind::shadow:
      return rays_for_count(request.camera, request.count, [&](const Camera& camera) {
        return make_shadow_rays(hits_from, scene, camera, request.seed);
      });
    case RayKind::random: {
      const std::size_t pixels =
          static_cast<std::size_t>(request.camera.width) * static_cast<std::size_t>(request.camera.height);
      return make_random_rays(scene.bounds(), request.count.value_or(pixels), request.seed);
    }
    case RayKind::path: break;
  }
  throw Error(std::string(ray_kind_name(request.kind)) + " rays are not a fixed ray set");
}

}  // namespace vf

#pragma once
/// \file The one fixed ray set a benchmark run traces through every structure.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "visfield/accel/query.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/render/ray_kind.hpp"
#include "visfield/render/ray_sets.hpp"

namespace vf::bench {

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

/// The benchmark's ray set. AO and shadow rays start at primary hits found with `hits_from` (any
/// exact structure gives the same hits); random rays come from make_random_rays over the scene
/// bounds, `count` of them (default: one per pixel of the camera's image). Path rays are not a
/// benchmark set (throws vf::Error).
template <ClosestHitQuery C>
std::vector<Ray> make_bench_rays(const C& hits_from, const Scene& scene, const RaySetRequest& request) {
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
  throw Error("visfield-bench: " + std::string(ray_kind_name(request.kind)) + " rays are not a benchmark ray set");
}

}  // namespace vf::bench

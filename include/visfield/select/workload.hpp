#pragma once
/// \file A scene ready for measuring, and the query set of a ray kind over it.

#include <cstddef>
#include <cstdint>
#include <string>

#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/render/ray_sets.hpp"
#include "visfield/select/path_rays.hpp"
#include "visfield/render/ray_kind.hpp"
#include "visfield/select/query_set.hpp"
#include "visfield/select/timing.hpp"

namespace vf {

/// A scene with its flattened triangles and the name the user gave it.
struct NamedScene {
  std::string name;
  Scene scene;
  TriangleSet triangles;
};

/// Loads what a user named (mesh file, scene .json, builtin:NAME[:...]) and flattens it. Throws vf::Error
/// on bad input or a scene without non-degenerate triangles.
NamedScene load_named_scene(const std::string& spec);

/// Side of the base image the camera-based kinds (primary, ao, shadow) are drawn from before
/// make_ray_set scales it to the count asked for.
inline constexpr int kWorkloadImageSide = 256;

/// `count` queries of `kind` over `scene` (whose triangles lie in `bounds`): random rays
/// (make_random_rays over `bounds`, closest-hit queries), path-tracing rays traced
/// through `accel` (make_path_rays with `path_bounces` bounces), or the camera's primary rays
/// (closest hit), AO rays (4 per hit, unlimited length) or shadow rays (both occlusion queries) of
/// make_ray_set, the primary hits found through `accel`; the camera is the scene's, else the default
/// framing. Deterministic in `seed`; throws vf::Error when the camera sees nothing.
template <Accelerator A>
QuerySet make_queries(RayKind kind, const A& accel, const Scene& scene, const Bounds3f& bounds, std::size_t count,
                      std::uint64_t seed, int path_bounces) {
  switch (kind) {
    case RayKind::random: return QuerySet{make_random_rays(bounds, count, seed), {}};
    case RayKind::path: return make_path_rays(accel, scene, count, PathRayOptions{path_bounces, seed});
    default: break;
  }
  RaySetRequest request;
  request.kind = kind;
  request.camera = scene.camera_or_default(kWorkloadImageSide, kWorkloadImageSide);
  request.count = count;
  request.seed = seed;
  std::vector<Ray> rays = make_ray_set(accel, scene, request);
  if (is_occlusion_kind(kind)) return QuerySet{{}, std::move(rays)};
  return QuerySet{std::move(rays), {}};
}

/// What the decision algorithm learns from its sample: how many queries it traced and their time.
struct SampleTiming {
  std::size_t count = 0;   ///< Queries in the sample.
  double query_us = 0.0;   ///< Microseconds per query on `threads` threads (sample_query_us).
};

/// Step 2 of the decision algorithm: `count` queries of `kind` drawn with `seed` (path rays traced
/// through `accel` itself), timed through `accel` by sample_query_us.
template <Accelerator A>
SampleTiming time_sample(RayKind kind, const A& accel, const Scene& scene, const Bounds3f& bounds, std::size_t count,
                         std::uint64_t seed, int path_bounces, int threads) {
  const QuerySet sample = make_queries(kind, accel, scene, bounds, count, seed, path_bounces);
  return {sample.size(), sample_query_us(accel, sample, threads)};
}

}  // namespace vf

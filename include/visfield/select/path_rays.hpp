#pragma once
/// \file The "path-tracing rays" of the grids-vs-hierarchies experiments: camera rays through random film
/// points, then cosine-weighted diffuse bounces from every hit, each hit also sending one shadow ray to
/// a light (or to a point above the scene when it has none). Bounces need hits, so the set is traced
/// through a caller-given structure; any exact structure gives the same rays.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "visfield/accel/query.hpp"
#include "visfield/accel/batch.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/render/ray_kind.hpp"
#include "visfield/render/sample_rays.hpp"
#include "visfield/select/query_set.hpp"

namespace vf {

/// Shape of the traced paths.
struct PathRayOptions {
  int max_bounces = 2;     ///< Diffuse bounces after the camera ray (0 = camera and shadow rays only); 0..16.
  std::uint64_t seed = 1;  ///< Path p draws its numbers from Rng(seed, p, depth).
};

namespace detail {

/// The paths [first_path, first_path + path_count) traced one depth at a time: pending() lists the
/// closest-hit rays of the current depth, advance() takes their hits and spawns the shadow rays and the
/// next bounces. Rays are stored per path and handed out path by path (camera ray, its shadow ray, the
/// first bounce, its shadow ray, ...), so any prefix of the concatenated chunks is a set of whole paths
/// plus part of one. Not thread-safe; one per chunk.
class PathChunk {
 public:
  /// Prepares the camera rays of the chunk's paths. Throws vf::Error on a bad camera or options.
  PathChunk(const Scene& scene, const PathRayOptions& options, std::size_t first_path, std::size_t path_count);
  /// Closest-hit rays still to trace (empty once every path has ended).
  std::span<const Ray> pending() const { return pending_; }
  /// Consumes the closest hits of pending() (same order).
  void advance(std::span<const Hit> hits);
  /// Appends the chunk's rays, path by path, to `out` until it holds `limit` queries.
  void append_to(QuerySet& out, std::size_t limit) const;

 private:
  const Scene& scene_;
  SurfaceSpawner spawner_;
  PathRayOptions options_;
  std::size_t first_path_ = 0;
  int depth_ = 0;                       // depth of the rays in pending_
  std::vector<Ray> slots_;              // per path 2 * (max_bounces + 1) slots: (closest, shadow) per depth
  std::vector<std::uint8_t> used_;      // slot holds a ray
  std::vector<Ray> pending_;
  std::vector<std::size_t> pending_path_;  // path (chunk-relative) of each pending ray
};

/// Paths to trace next when `missing` queries are still wanted (at least 256, at most 65536).
std::size_t path_chunk_size(std::size_t missing);

}  // namespace detail

/// Exactly `count` path-tracing queries of `scene`, traced through `closest` (built over `scene`):
/// paths 0, 1, 2, ... taken whole, in order, the last one cut at `count`. Camera: the scene's (or the
/// default framing), film points uniform over the image. A pure function of (scene, count, options):
/// the same rays whatever the structure or thread count. Throws vf::Error on a bad camera or options.
/// Cost: about `count` closest-hit queries through `closest`, parallel.
template <ClosestHitQuery C>
QuerySet make_path_rays(const C& closest, const Scene& scene, std::size_t count, const PathRayOptions& options = {}) {
  QuerySet out;
  std::size_t next_path = 0;
  std::vector<Hit> hits;
  while (out.size() < count) {
    const std::size_t paths = detail::path_chunk_size(count - out.size());
    detail::PathChunk chunk(scene, options, next_path, paths);
    while (!chunk.pending().empty()) {
      hits.resize(chunk.pending().size());
      intersect_batch(closest, chunk.pending(), std::span<Hit>(hits));
      chunk.advance(hits);
    }
    chunk.append_to(out, count);
    next_path += paths;
  }
  return out;
}

}  // namespace vf

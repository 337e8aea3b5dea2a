#pragma once
/// \file Ambient occlusion: per pixel, the fraction of cosine-weighted directions from the first
/// visible surface that reach max_distance (or the sky) unoccluded. Grey, no albedo. Camera rays go
/// to one structure (the closest-hit role) and occlusion rays to another (the occlusion role), which
/// may be the same object, an exact one or an approximate one.

#include <cstdint>
#include <limits>

#include "visfield/accel/query.hpp"
#include "visfield/accel/scene_queries.hpp"
#include "visfield/core/image.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/render/render_stats.hpp"
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
  /// The pixels to render (render_region(): unset = all); the image returned is the region, each
  /// pixel equal to the whole image's at the same place.
  ImageTile region{};
};

/// Value of a pixel sample whose primary ray misses everything: an unoccluded white sky.
inline constexpr float kAoBackground = 1.0f;

/// Throws vf::Error naming the field when an option is out of range.
void validate_ao_options(const AoOptions& options);

/// Renders `camera`'s view of `scene` with ambient occlusion, camera rays traced through
/// queries.intersect_camera and AO rays through queries.occluded_block: per pixel and sample s,
/// Rng(seed, pixel, s) draws the jitter and the AO directions; the pixel is the mean over samples of
/// the unoccluded fraction (of `ao_rays` cosine-weighted rays, or, with `psf_level`, of one ray along
/// each line not perpendicular to the normal, weighted by |cos|), or kAoBackground on a miss. A tile's
/// AO rays are traced together, so occluders with a batch path use it; along the lines, an occluder
/// that prefers line streams (SceneQueries::occluder_prefers_line_streams: a BeamField) gets each
/// line's rays from a whole block of the image (up to 64 MiB of answers: samples × lines bytes) in
/// one call instead, summed in the same order to the same image. Parallel over tiles;
/// identical images for any thread count. `stats` (optional) gets every ray traced by kind and the
/// wall time. Throws vf::Error on bad options or camera. Cost: width*height*spp*(1 + ao_rays * hit fraction) queries.
Image render_ao(const SceneQueries& queries, const Scene& scene, const Camera& camera, const AoOptions& opt,
                RenderStats* stats = nullptr);

/// render_ao() with camera rays through `closest` and AO rays through `occluder` (both built over
/// `scene`; they may be the same structure).
template <ClosestHitQuery C, OcclusionQuery O>
Image render_ao(const C& closest, const O& occluder, const Scene& scene, const Camera& camera, const AoOptions& opt,
                RenderStats* stats = nullptr) {
  return render_ao(QueriesOver<C, O>(closest, occluder), scene, camera, opt, stats);
}

}  // namespace vf

#pragma once
/// \file The integrators beyond AO: what `visfield render --integrator` draws. Each takes the scene's
/// queries by role (accel/scene_queries.hpp) and never names a structure, so every exact structure,
/// and any mix of exact geometry and field occluders, renders through them. Pixels are deterministic
/// per (seed, pixel, sample): images do not depend on the thread count. Radiance is linear; the image
/// writers encode it (sRGB for PNG).
///
/// Lights: the scene's point lights, sphere lights and (path only) emitting triangles; a scene with
/// none gets default_point_light() (lights.hpp). Materials: render/bsdf.hpp. The background is black.

#include <array>
#include <optional>
#include <string_view>

#include "visfield/accel/scene_queries.hpp"
#include "visfield/core/image.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/render/render_stats.hpp"
#include "visfield/render/tiles.hpp"

namespace vf {

/// What a render computes per pixel.
enum class Integrator {
  raycast,     ///< Camera rays only; diffuse colour lit by the point lights by distance and angle, no shadows (VLF-RT's "OpenGL-like" mode).
  whitted,     ///< Hard shadows from point lights, perfect mirror reflection and refraction, to a depth limit.
  ao,          ///< Ambient occlusion (render/ao.hpp).
  softshadow,  ///< Sphere lights sampled by `shadow_rays` rays each per sample (GPU fields paper's soft shadows).
  glossy,      ///< Direct light plus `glossy_rays` reflection rays from the specular lobe per reflective sample.
  path,        ///< Unidirectional path tracing: next-event estimation, MIS (power heuristic), Russian roulette.
};

/// Every integrator, in the order help texts list them.
inline constexpr std::array<Integrator, 6> kIntegrators{Integrator::raycast, Integrator::whitted,  Integrator::ao,
                                                        Integrator::softshadow, Integrator::glossy, Integrator::path};

/// The command-line spelling of `integrator`.
constexpr std::string_view integrator_name(Integrator integrator) {
  switch (integrator) {
    case Integrator::raycast: return "raycast";
    case Integrator::whitted: return "whitted";
    case Integrator::ao: return "ao";
    case Integrator::softshadow: return "softshadow";
    case Integrator::glossy: return "glossy";
    case Integrator::path: return "path";
  }
  return "ao";
}

/// The integrator spelled `name`, or nothing.
constexpr std::optional<Integrator> parse_integrator(std::string_view name) {
  for (Integrator integrator : kIntegrators)
    if (integrator_name(integrator) == name) return integrator;
  return std::nullopt;
}

/// Parameters of the shading integrators (all but AO, which has AoOptions).
struct ShadingOptions {
  int spp = 1;               ///< Camera samples per pixel (>= 1): the pixel centre when 1, jittered when more.
  std::uint64_t seed = 1;    ///< The image depends on this seed only, never on threads or tiles.
  int tile_size = 16;        ///< Tile edge in pixels (>= 1): the unit of parallel work and of progress.
  bool progress = true;      ///< Progress bar on stderr for renders that take over ~1 s.
  int max_depth = 5;         ///< whitted: reflection/refraction levels; path: bounces (>= 1).
  int shadow_rays = 20;      ///< softshadow: rays per sphere light per sample (>= 1; the GPU paper uses 20).
  int glossy_rays = 4;       ///< glossy: reflection rays per reflective sample (>= 1; the GPU paper uses 4).
  float ambient = 0.1f;      ///< raycast, whitted, softshadow, glossy: ambient light as a fraction of the diffuse colour (>= 0).
  /// The pixels to render (render_region(): unset = all); the image returned is the region, each
  /// pixel equal to the whole image's at the same place.
  ImageTile region{};
};

/// Throws vf::Error naming the field when an option is out of range.
void validate_shading_options(const ShadingOptions& options);

/// Renders `camera`'s view of `scene` with `integrator` (not ao: render_ao()), camera rays through
/// queries.intersect_camera and every later ray through the other roles. Parallel over tiles; `stats`
/// (optional) gets the rays by kind and the wall time. Throws vf::Error on bad options or camera, or
/// for Integrator::ao.
Image render_shaded(Integrator integrator, const SceneQueries& queries, const Scene& scene, const Camera& camera,
                    const ShadingOptions& options, RenderStats* stats = nullptr);

}  // namespace vf

#pragma once
/// \file What the shading integrators share: the scene's queries, lights and spawner in one context,
/// the surface a ray reached, local lighting from point-like lights, and the per-pixel sample loop.

#include <functional>

#include "visfield/accel/scene_queries.hpp"
#include "visfield/core/image.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/render/bsdf.hpp"
#include "visfield/render/camera.hpp"
#include "visfield/render/integrators.hpp"
#include "visfield/render/lights.hpp"
#include "visfield/render/render_stats.hpp"
#include "visfield/render/sample_rays.hpp"

namespace vf::render_detail {

/// Everything an integrator reads while shading; built once per render, shared by the tiles.
struct ShadingContext {
  /// `emitters`: collect emitting triangles as lights (the path tracer) instead of the proxies.
  ShadingContext(const SceneQueries& q, const Scene& s, const ShadingOptions& o, bool emitters)
      : queries(q), scene(s), options(o), spawner(s), lights(s, emitters) {}
  const SceneQueries& queries;
  const Scene& scene;
  const ShadingOptions& options;
  SurfaceSpawner spawner;
  SceneLights lights;
};

/// The surface a ray reached: where secondary rays leave, what it is made of, how it scatters.
struct SurfaceHit {
  SurfacePoint point;
  const Material* material = nullptr;
  Bsdf bsdf;
  Vec3f wo;  ///< Unit direction back along the ray.
};

/// The SurfaceHit of `hit`, found by tracing `ray`.
SurfaceHit surface_hit(const ShadingContext& context, const Ray& ray, const Hit& hit);

/// Ambient (options.ambient times the diffuse colour) plus every point light and every sphere light
/// taken as a point at its centre (intensity radiance * pi r^2), through the diffuse lobe only
/// (`highlights` false) or the whole smooth Bsdf. With `shadows`, each light's shadow ray is traced
/// (counted in rays.shadow) and blocked lights add nothing.
Vec3f local_lighting(const ShadingContext& context, const SurfaceHit& surface, bool shadows, bool highlights, RayCounts& rays);

/// Radiance of one camera sample: the camera ray, the sample's own random numbers, the ray counts to add to.
using SampleShader = std::function<Vec3f(const Ray& camera_ray, Rng& rng, RayCounts& rays)>;

/// The image of `camera`, each pixel the mean over options.spp samples of `shade` (sample s of pixel p
/// draws from Rng(seed, p, s): the jitter first, then whatever `shade` draws). Parallel over tiles.
Image render_pixels(const char* label, const Camera& camera, const ShadingOptions& options, RenderStats* stats,
                    const SampleShader& shade);

/// The integrators, each over a context made for it (render_shaded dispatches).
Image render_raycast(const ShadingContext& context, const Camera& camera, RenderStats* stats);
Image render_whitted(const ShadingContext& context, const Camera& camera, RenderStats* stats);
Image render_soft_shadows(const ShadingContext& context, const Camera& camera, RenderStats* stats);
Image render_glossy(const ShadingContext& context, const Camera& camera, RenderStats* stats);
Image render_path(const ShadingContext& context, const Camera& camera, RenderStats* stats);

}  // namespace vf::render_detail

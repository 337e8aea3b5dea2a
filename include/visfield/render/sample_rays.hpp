#pragma once
/// \file The rays renderers and ray-set generators trace, built one way in one place: primary rays per
/// pixel sample, the surface point secondary rays start from, ambient-occlusion rays and shadow rays.
/// Every function draws its random numbers from a caller-owned Rng keyed by (seed, pixel, sample), so
/// results never depend on threads or tile order.

#include <vector>

#include "visfield/core/ray.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/render/camera.hpp"

namespace vf {

/// Primary ray through the centre of pixel (x, y).
Ray pixel_center_ray(const PinholeCamera& camera, int x, int y);

/// Primary ray of pixel (x, y): pixel_center_ray() when `jitter` is false (no numbers drawn), else
/// through a uniform random point of the pixel (two numbers drawn from `rng`).
Ray pixel_ray(const PinholeCamera& camera, int x, int y, bool jitter, Rng& rng);

/// A hit prepared for spawning secondary rays. Plain value.
struct SurfacePoint {
  Vec3f position;   ///< The hit point lifted off the surface by spawn_offset() along `normal`.
  Vec3f normal;     ///< Unit geometric normal, flipped to face the incoming ray's origin.
  Vec3f tangent;    ///< Completes an orthonormal frame (tangent, bitangent, normal).
  Vec3f bitangent;  ///< Completes an orthonormal frame (tangent, bitangent, normal).
  Vec3f behind;     ///< The hit point moved the same way to the other side: where refracted rays leave.
  bool entering = true;  ///< The ray arrived on the side the geometric normal points to (or the hit had no normal).
};

/// Largest coordinate magnitude of the scene's bounds, the scene-size term of spawn_offset(); O(instances),
/// compute once per render.
float spawn_scale(const Scene& scene);

/// Distance a hit point is lifted along its normal before secondary rays leave it. Float error in the hit
/// point grows with the magnitude of the coordinates involved: the ray origin and hit distance (covering
/// the hit point itself) and the triangle's vertices (bounded by the scene scale). The offset is about
/// 80 float ulps of the first and 8 ulps of the second, far above the error of the watertight test and
/// far below any feature size of sensible scenes, so secondary rays neither re-hit their own surface nor
/// skip a nearby one.
float spawn_offset(const Ray& ray, float hit_t, float scene_scale);

/// Where secondary rays leave a surface: the offset rule of every renderer and ray generator.
/// The hit point moves spawn_offset() along the normal, to the side the ray came from, and the same
/// distance (at most half-way) toward the centroid of the hit triangle. The first move keeps a
/// secondary ray from re-hitting its own surface (no acne). The second takes the point off the
/// triangle's edges: a hit on an edge shared with a perpendicular surface (a room's corner, a box
/// standing on a floor) would otherwise start exactly on that surface, which rays entering it would
/// pass unseen (tmin is exclusive): light would leak through corners. Holds a reference to the scene;
/// immutable and thread-safe.
class SurfaceSpawner {
 public:
  /// Prepares for hits in `scene`, which must outlive this; O(objects + vertices).
  explicit SurfaceSpawner(const Scene& scene);
  /// Surface point of `hit` (found by tracing `ray`). The normal is the hit's (exact structures always
  /// give one; a hit without a normal faces the ray's origin); a hit without a triangle moves only
  /// along the normal. O(log objects).
  SurfacePoint surface_point(const Ray& ray, const Hit& hit) const;

 private:
  const Scene& scene_;
  float scale_;
};

/// The next ambient-occlusion ray from `point`: cosine-weighted about its normal (two numbers drawn from
/// `rng`), unit direction, t in [0, max_distance].
Ray ao_ray(const SurfacePoint& point, Rng& rng, float max_distance);

/// The next `count` ambient-occlusion rays from `point` into out[0 .. count): bit for bit the rays
/// `count` calls of ao_ray() return, and `rng` left where they leave it; 16 at a time on lanes
/// with AVX-512, 8 with AVX2 (the generator stepped ahead per lane), one by one elsewhere. O(count).
void ao_rays(const SurfacePoint& point, Rng& rng, float max_distance, std::size_t count, Ray* out);

/// The points shadow rays aim at: every point and sphere light of a scene, or, when it has none, the
/// position of default_point_light() (lights.hpp). Immutable; thread-safe.
class LightTargets {
 public:
  /// Collects the lights of `scene`; O(lights + instances).
  explicit LightTargets(const Scene& scene);
  /// A point on a light chosen uniformly among them (three numbers drawn from `rng`): the light position
  /// for point lights, a uniform point on the hemisphere of a sphere light that faces `from`.
  Vec3f sample(const Vec3f& from, Rng& rng) const;

 private:
  struct Target {
    Vec3f center;
    float radius = 0.0f;
  };
  std::vector<Target> targets_;
};

/// Shadow ray from `point` towards `target`: unit direction, t in [0, just short of the target]
/// (distance * (1 - 1e-4)) so geometry the light point sits on does not count as an occluder.
Ray shadow_ray(const SurfacePoint& point, const Vec3f& target);

}  // namespace vf

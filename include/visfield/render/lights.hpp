#pragma once
/// \file The lights of a scene as the integrators see them: point lights, spherical area lights and
/// emitting triangles (materials with emission), each sampled from a shading point, and a default
/// light for scenes that bring none.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "visfield/core/ray.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/scene.hpp"

namespace vf {

class Bsdf;

/// The light a scene without point or sphere lights gets: a point light one bounds extent above the
/// top of its bounds, over their centre, bright enough (intensity pi * d^2 at distance d from the
/// centre) that a white surface facing it there reflects radiance 1. Also where shadow-ray sets aim.
PointLight default_point_light(const Scene& scene);

/// A sampled direction towards a light.
struct LightSample {
  Vec3f wi;               ///< Unit direction from the shading point to the light point.
  float distance = 0.0f;  ///< Distance to the light point (the shadow ray stops short of it).
  Vec3f radiance;         ///< Radiance arriving along wi (for point lights: intensity / distance^2).
  float pdf = 0.0f;       ///< Solid-angle density of wi, light choice included; 1 for point lights (delta).
  bool delta = false;     ///< A point light: no other strategy can reach it (no MIS).
};

/// The cone of directions from one point into one sphere light, prepared once for many samples.
/// Plain value.
class SphereCone {
 public:
  /// The cone from `from` into `light`; nothing when `from` is inside the sphere.
  static std::optional<SphereCone> toward(const SphereLight& light, const Vec3f& from);
  /// A direction uniform in the cone (two numbers in [0, 1)), its distance to the sphere's surface
  /// and the light's radiance; pdf = 1 / solid angle.
  LightSample sample(float u, float v) const;
  /// `count` samples as sample(rng.uniform(), rng.uniform()) one after another draws them, bit for
  /// bit, and `rng` left where they leave it: directions into `wi`, distances into `distance`. 16 at
  /// a time on lanes with AVX-512 (F and DQ), 8 with AVX2.
  void sample(Rng& rng, std::size_t count, Vec3f* wi, float* distance) const;
  /// The light's radiance, arriving along every direction of the cone.
  const Vec3f& radiance() const { return radiance_; }
  /// 1 / the cone's solid angle.
  float pdf() const { return pdf_; }
  /// What sample() computes with: the unit axis towards the centre and the frame around it, the
  /// distance to the centre, the radius, and 1 − cos of the cone's half-angle.
  struct Shape {
    Vec3f axis, tangent, bitangent;
    float distance, radius, one_minus_cos_max;
  };
  Shape shape() const { return {axis_, tangent_, bitangent_, distance_, radius_, one_minus_cos_max_}; }

 private:
  Vec3f axis_, tangent_, bitangent_, radiance_;
  float distance_ = 0.0f, radius_ = 0.0f, one_minus_cos_max_ = 0.0f, pdf_ = 0.0f;
};

/// Places past lights.size() · per_light that sphere_light_rays() may write (whole packets of lanes).
inline constexpr std::size_t kSphereLightRaysSlack = 16;

/// The shadow rays the softshadow integrator sends from a shading point at `from` to sphere lights,
/// with what each adds when unoccluded. For each of `lights` in turn, `per_light` directions wi drawn
/// as SphereCone::sample(rng, per_light, ...) draws them (a light whose sphere holds `from` skips its
/// 2·per_light numbers); each wi where f = bsdf.eval(wo, wi) has a positive component gives the ray
/// from `from` along wi over [0, (1 − 1e-4) · the distance to the light's surface] into rays[n] and
/// f · radiance · ((1 / per_light) / pdf) into contribution[n], in that order. Returns n (both need
/// room for lights.size() · per_light + kSphereLightRaysSlack); `rng` moves on by 2·per_light numbers
/// a light. Bit for bit that loop a sample at a time; on lanes where only the diffuse lobe is smooth.
std::size_t sphere_light_rays(std::span<const SphereLight> lights, const Vec3f& from, const Bsdf& bsdf, const Vec3f& wo, int per_light,
                              Rng& rng, Ray* rays, Vec3f* contribution);

/// Where a ray meets a sphere light first.
struct SphereLightHit {
  float t = 0.0f;        ///< Ray parameter of the entry point.
  std::uint32_t light = 0;  ///< Index into the scene's sphere lights.
};

/// Every light a render uses, collected once. Immutable and thread-safe after construction.
class SceneLights {
 public:
  /// Collects the point lights (without proxies when `emitters` is set), the sphere lights and, when
  /// `emitters` is set, every triangle whose material emits (in world space, chosen in proportion to
  /// area times emitted luminance). A scene with none of these gets default_point_light(). O(triangles).
  SceneLights(const Scene& scene, bool emitters);

  /// The point lights in use (the scene's, or the default one).
  std::span<const PointLight> point_lights() const { return points_; }
  /// The scene's sphere lights.
  std::span<const SphereLight> sphere_lights() const { return spheres_; }

  /// One light sample for a shading point at `from`: a light chosen uniformly among the point lights,
  /// the sphere lights and (as one more choice) the emitting triangles, then a point on it (sphere:
  /// uniform in the cone it subtends; triangle: uniform in area). Draws four numbers. Nothing when the
  /// chosen light cannot be sampled from `from` (inside a sphere light, behind an emitter).
  std::optional<LightSample> sample(const Vec3f& from, Rng& rng) const;
  /// A direction from `from` into sphere light `light`, uniform in the cone the sphere subtends (two
  /// numbers in [0, 1)); pdf without the light choice. Nothing when `from` is inside the sphere.
  std::optional<LightSample> sample_sphere(std::uint32_t light, const Vec3f& from, float u, float v) const;
  /// Solid-angle density with which sample() picks the direction from `from` that enters sphere light
  /// `light` (the light choice included).
  float sphere_pdf(std::uint32_t light, const Vec3f& from) const;
  /// Solid-angle density with which sample() reaches the point `at` with geometric normal `normal` of
  /// emitting triangle (instance, prim) from `from`; 0 when it is not a collected emitter.
  float emitter_pdf(ObjectId instance, std::uint32_t prim, const Vec3f& from, const Vec3f& at, const Vec3f& normal) const;
  /// The first sphere light `ray` enters within (tmin, t_max), if any. O(sphere lights).
  std::optional<SphereLightHit> first_sphere(const Ray& ray, float t_max) const;

 private:
  struct Emitter {
    Vec3f p0, e1, e2;  // world-space corner and edges
    Vec3f radiance;
    float area = 0.0f;
    ObjectId instance = kInvalidId;
    std::uint32_t prim = 0;
  };
  std::size_t choices() const { return points_.size() + spheres_.size() + (triangles_.empty() ? 0 : 1); }
  std::vector<PointLight> points_;
  std::vector<SphereLight> spheres_;
  std::vector<Emitter> triangles_;   // sorted by (instance, prim) for emitter_pdf's search
  std::vector<float> triangle_cdf_;  // running sums of area x luminance, normalised to end at 1
};

}  // namespace vf

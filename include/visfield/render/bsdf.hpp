#pragma once
/// \file How a surface scatters light, from its Material: a Lambertian lobe, a specular lobe (a perfect
/// mirror below roughness 0.02, else GGX with alpha = roughness^2, reflectance `specular`, Smith
/// shadowing) and a smooth dielectric for the transmissive fraction (Fresnel reflection and
/// refraction by `ior`). The diffuse albedo is scaled by 1 - max(specular) so that no material
/// reflects more than it receives. All directions are world-space unit vectors pointing away from
/// the surface; wo towards the viewer.

#include <optional>
#include <span>

#include "visfield/core/rng.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/render/sample_rays.hpp"

namespace vf {

/// The Rec. 709 luminance of a linear RGB colour.
inline float luminance(const Vec3f& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

/// Roughness below which the specular lobe is a perfect mirror (a delta lobe).
inline constexpr float kMirrorRoughness = 0.02f;

/// A direction drawn from a Bsdf.
struct BsdfSample {
  Vec3f wi;             ///< Unit direction of the scattered ray.
  Vec3f weight;         ///< f * |cos wi| / pdf: what the path's throughput is multiplied by.
  float pdf = 0.0f;     ///< Solid-angle density of wi (0 for delta lobes).
  bool delta = false;   ///< A mirror or dielectric direction: light sampling cannot reach it (no MIS).
  bool transmitted = false;  ///< The ray crosses the surface (it starts from SurfacePoint::behind).
};

/// Mirror of unit `w` about unit `n`: 2 (w.n) n - w.
Vec3f reflect(const Vec3f& w, const Vec3f& n);
/// Fresnel reflectance of a smooth dielectric for light arriving at cosine `cos_i` (> 0) from the side
/// of index ratio `eta` = n_incident / n_transmitted; 1 under total internal reflection.
float fresnel_dielectric(float cos_i, float eta);

/// Direction of unit `w` (pointing away from the surface, on the side of unit `n`) refracted through
/// the surface with index ratio `eta` = n_incident / n_transmitted; nothing under total internal reflection.
std::optional<Vec3f> refract(const Vec3f& w, const Vec3f& n, float eta);

/// The scattering of one material at one surface point. Plain value; cheap to make per hit.
class Bsdf {
 public:
  /// For `material` at `point` (its normal faces wo); `entering` tells that the ray arrived on the side
  /// the geometric normal points to (outside a closed mesh wound counter-clockwise).
  Bsdf(const Material& material, const SurfacePoint& point, bool entering);

  /// f(wo, wi) * |cos wi| of the smooth lobes (diffuse and GGX; delta lobes give 0).
  Vec3f eval(const Vec3f& wo, const Vec3f& wi) const;
  /// eval(wo, wi[k]) into f[k] for every k, bit for bit; one pass without calls when only the
  /// diffuse lobe is smooth.
  void eval(const Vec3f& wo, std::span<const Vec3f> wi, Vec3f* f) const;
  /// Density with which sample() draws wi for wo, over the smooth lobes.
  float pdf(const Vec3f& wo, const Vec3f& wi) const;
  /// A scattered direction: a lobe chosen in proportion to its reflectance, then a direction in it.
  /// Draws three numbers. Nothing when the material absorbs everything or the direction falls below
  /// the surface.
  std::optional<BsdfSample> sample(const Vec3f& wo, Rng& rng) const;
  /// A direction of the specular lobe alone (mirror, or GGX by its normal distribution), weighted by
  /// f * cos / pdf of that lobe: the glossy integrator's reflection rays. Two numbers drawn.
  std::optional<BsdfSample> sample_specular(const Vec3f& wo, Rng& rng) const;
  /// True when the material has a smooth lobe, so that light sampling can contribute.
  bool has_smooth_lobe() const { return max_component(diffuse_) > 0.0f || (glossy() && max_component(specular_) > 0.0f); }
  /// True when the specular lobe reflects anything.
  bool reflective() const { return max_component(specular_) > 0.0f; }
  /// The diffuse albedo after the energy scaling, times the opaque fraction.
  Vec3f diffuse() const { return diffuse_ * (1.0f - transmission_); }
  /// eval()'s terms when the diffuse lobe is its only smooth one (no GGX lobe), for evaluations on
  /// lanes: eval(wo, wi) = dot(wo, normal) > 0 && c > 0 ? albedo · (c / π) · opaque : 0, c = dot(wi, normal).
  struct Lambert {
    Vec3f albedo, normal;
    float opaque;
  };
  std::optional<Lambert> lambert() const {
    if (glossy()) return std::nullopt;
    return Lambert{diffuse_, n_, 1.0f - transmission_};
  }

 private:
  bool glossy() const { return alpha_ > 0.0f; }
  float specular_probability() const;
  Vec3f glossy_eval(const Vec3f& wo, const Vec3f& wi) const;  // GGX f * cos, both in the upper hemisphere
  float glossy_pdf(const Vec3f& wo, const Vec3f& wi) const;
  Vec3f to_world(const Vec3f& local) const { return t_ * local.x + b_ * local.y + n_ * local.z; }
  Vec3f diffuse_, specular_;
  float alpha_ = 0.0f;  // 0: mirror
  float transmission_ = 0.0f, eta_ = 1.0f;  // eta: n_incident / n_transmitted
  Vec3f t_, b_, n_;
};

}  // namespace vf

#include "visfield/render/bsdf.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "visfield/core/sampling.hpp"

namespace vf {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// GGX (Trowbridge-Reitz) normal distribution for a half vector at cosine `cos_h` to the normal.
float ggx_d(float cos_h, float alpha) {
  const float a2 = alpha * alpha;
  const float k = cos_h * cos_h * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * k * k);
}

// Smith's masking for GGX of a direction at cosine `c` (> 0) to the normal.
float smith_g1(float c, float alpha) {
  const float a2 = alpha * alpha;
  return 2.0f * c / (c + std::sqrt(a2 + (1.0f - a2) * c * c));
}

// A half vector (local frame, +z the normal) drawn with density D(h) cos_h from two numbers in [0, 1).
Vec3f ggx_half_vector(float u, float v, float alpha) {
  const float tan2 = alpha * alpha * u / (1.0f - u);
  const float cos_h = 1.0f / std::sqrt(1.0f + tan2);
  const float sin_h = std::sqrt(std::fmax(0.0f, 1.0f - cos_h * cos_h));
  float sin_phi, cos_phi;
  sincos_turn(v, sin_phi, cos_phi);  // of 2πv
  return {sin_h * cos_phi, sin_h * sin_phi, cos_h};
}

}  // namespace

Vec3f reflect(const Vec3f& w, const Vec3f& n) { return n * (2.0f * dot(w, n)) - w; }

float fresnel_dielectric(float cos_i, float eta) {
  const float sin2_t = eta * eta * (1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) return 1.0f;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  const float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

std::optional<Vec3f> refract(const Vec3f& w, const Vec3f& n, float eta) {
  const float cos_i = dot(w, n);
  const float sin2_t = eta * eta * std::fmax(0.0f, 1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) return std::nullopt;
  return normalize(w * -eta + n * (eta * cos_i - std::sqrt(1.0f - sin2_t)));
}

Bsdf::Bsdf(const Material& material, const SurfacePoint& point, bool entering)
    : diffuse_(material.diffuse * (1.0f - std::clamp(max_component(material.specular), 0.0f, 1.0f))),
      specular_(material.specular),
      alpha_(material.roughness < kMirrorRoughness ? 0.0f : std::fmax(material.roughness * material.roughness, 1e-3f)),
      transmission_(std::clamp(material.transmission, 0.0f, 1.0f)),
      eta_(entering ? 1.0f / material.ior : material.ior),
      t_(point.tangent),
      b_(point.bitangent),
      n_(point.normal) {}

float Bsdf::specular_probability() const {
  const float s = luminance(specular_), d = luminance(diffuse_);
  return s + d > 0.0f ? s / (s + d) : 0.0f;
}

Vec3f Bsdf::glossy_eval(const Vec3f& wo, const Vec3f& wi) const {
  const float cos_o = dot(wo, n_), cos_i = dot(wi, n_);
  const Vec3f h = normalize(wo + wi);
  return specular_ * (ggx_d(dot(h, n_), alpha_) * smith_g1(cos_o, alpha_) * smith_g1(cos_i, alpha_) / (4.0f * cos_o));
}

float Bsdf::glossy_pdf(const Vec3f& wo, const Vec3f& wi) const {
  const Vec3f h = normalize(wo + wi);
  return ggx_d(dot(h, n_), alpha_) * dot(h, n_) / (4.0f * std::fmax(dot(wo, h), 1e-8f));
}

Vec3f Bsdf::eval(const Vec3f& wo, const Vec3f& wi) const {
  const float cos_o = dot(wo, n_), cos_i = dot(wi, n_);
  if (!(cos_o > 0.0f && cos_i > 0.0f)) return Vec3f{0.0f};
  Vec3f f = diffuse_ * (cos_i / kPi);
  if (glossy()) f += glossy_eval(wo, wi);
  return f * (1.0f - transmission_);
}

void Bsdf::eval(const Vec3f& wo, std::span<const Vec3f> wi, Vec3f* f) const {
  if (glossy()) {
    for (std::size_t k = 0; k < wi.size(); ++k) f[k] = eval(wo, wi[k]);
    return;
  }
  const float cos_o = dot(wo, n_), opaque = 1.0f - transmission_;
  for (std::size_t k = 0; k < wi.size(); ++k) {
    const float cos_i = dot(wi[k], n_);
    f[k] = cos_o > 0.0f && cos_i > 0.0f ? diffuse_ * (cos_i / kPi) * opaque : Vec3f{0.0f};
  }
}

float Bsdf::pdf(const Vec3f& wo, const Vec3f& wi) const {
  const float cos_o = dot(wo, n_), cos_i = dot(wi, n_);
  if (!(cos_o > 0.0f && cos_i > 0.0f)) return 0.0f;
  const float p_specular = specular_probability();
  float p = (1.0f - p_specular) * cos_i / kPi;
  if (glossy()) p += p_specular * glossy_pdf(wo, wi);
  return p * (1.0f - transmission_);
}

std::optional<BsdfSample> Bsdf::sample(const Vec3f& wo, Rng& rng) const {
  float choose = rng.uniform();
  const float u = rng.uniform(), v = rng.uniform();
  const float cos_o = dot(wo, n_);
  if (!(cos_o > 0.0f)) return std::nullopt;
  if (choose < transmission_) {
    // The dielectric: reflect with the Fresnel probability, else refract; the choice cancels F.
    const float f = fresnel_dielectric(cos_o, eta_);
    if (u < f) return BsdfSample{reflect(wo, n_), Vec3f{1.0f}, 0.0f, true, false};
    const std::optional<Vec3f> wt = refract(wo, n_, eta_);
    if (!wt) return BsdfSample{reflect(wo, n_), Vec3f{1.0f}, 0.0f, true, false};  // f < 1 only by rounding
    // Radiance is compressed by (n_i / n_t)^2 crossing into the denser side (pbrt's non-symmetric scattering).
    return BsdfSample{*wt, Vec3f{eta_ * eta_}, 0.0f, true, true};
  }
  choose = transmission_ > 0.0f ? (choose - transmission_) / (1.0f - transmission_) : choose;
  const float p_specular = specular_probability();
  if (p_specular == 0.0f && max_component(diffuse_) <= 0.0f) return std::nullopt;
  Vec3f wi;
  if (choose < p_specular) {
    if (!glossy()) return BsdfSample{reflect(wo, n_), specular_ * (1.0f / p_specular), 0.0f, true, false};
    wi = reflect(wo, to_world(ggx_half_vector(u, v, alpha_)));
  } else {
    wi = to_world(cosine_hemisphere(u, v));
  }
  const float p = pdf(wo, wi);
  if (!(p > 0.0f)) return std::nullopt;
  return BsdfSample{wi, eval(wo, wi) * (1.0f / p), p, false, false};
}

std::optional<BsdfSample> Bsdf::sample_specular(const Vec3f& wo, Rng& rng) const {
  const float u = rng.uniform(), v = rng.uniform();
  const float cos_o = dot(wo, n_);
  if (!(cos_o > 0.0f) || !reflective()) return std::nullopt;
  if (!glossy()) return BsdfSample{reflect(wo, n_), specular_, 0.0f, true, false};
  const Vec3f local_h = ggx_half_vector(u, v, alpha_);
  const Vec3f h = to_world(local_h);
  const float cos_h = local_h.z;
  const Vec3f wi = reflect(wo, h);
  const float cos_i = dot(wi, n_);
  const float o_h = dot(wo, h);
  if (!(cos_i > 0.0f && o_h > 0.0f)) return std::nullopt;
  // f cos / pdf of GGX sampled by its normal distribution: specular G (wo.h) / (cos_o cos_h).
  const Vec3f weight = specular_ * (smith_g1(cos_o, alpha_) * smith_g1(cos_i, alpha_) * o_h / (cos_o * cos_h));
  return BsdfSample{wi, weight, glossy_pdf(wo, wi), false, false};
}

}  // namespace vf

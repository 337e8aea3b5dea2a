#pragma once
/// \file The secondary rays the GPU kernels generate, host and device, so that the CPU can generate
/// the very same rays and compare answers bit for bit: ambient-occlusion rays (cosine-weighted, the
/// concentric map lifted by Malley, as core/sampling.hpp's cosine_hemisphere), soft-shadow rays
/// uniform in the cone a sphere light subtends (render/lights.cpp's SphereCone), and glossy
/// reflection rays (GGX by its normal distribution, render/bsdf.cpp's sample_specular). Random
/// numbers come from the project's Rng keyed by (seed, point, sample), so a ray depends on nothing
/// but its keys, or, for AO rays, continue a given generator as the CPU renderer draws them.
/// Directions are drawn with core/sampling.hpp's maps and polynomial sines, as the CPU renderers
/// draw theirs: an AO ray is the renderer's bit for bit; cone and GGX rays, whose frames and
/// normalisations are written apart, equal the renderers' to a few ulps.

#include "visfield/core/host_device.hpp"
#include "visfield/core/orthonormal_basis.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"

namespace vf::gpu {

/// Where secondary rays leave a surface: render's SurfacePoint reduced to what ray generation reads
/// (its position, lifted off the surface, and its unit normal with the tangent frame). 48 bytes.
struct SurfaceFrame {
  Vec3f position, normal, tangent, bitangent;
};

/// `local` taken from the frame (tangent, bitangent, normal) to world space.
VF_HOST_DEVICE inline Vec3f to_world(const SurfaceFrame& f, const Vec3f& local) {
  return f.tangent * local.x + f.bitangent * local.y + f.normal * local.z;
}

/// The AO ray from `f` for the next two numbers of `rng`: a cosine-weighted direction about the
/// normal (unit to rounding), t in [0, max_distance].
VF_HOST_DEVICE inline Ray ao_ray(const SurfaceFrame& f, Rng& rng, float max_distance) {
  const float s = rng.uniform();
  const float t = rng.uniform();
  return Ray{f.position, to_world(f, cosine_hemisphere(s, t)), 0.0f, max_distance};
}

/// AO ray `sample` of surface point `point`: its numbers from Rng(seed, point, sample).
VF_HOST_DEVICE inline Ray ao_ray(const SurfaceFrame& f, unsigned long long seed, unsigned long long point, unsigned long long sample,
                                 float max_distance) {
  Rng rng(seed, point, sample);
  return ao_ray(f, rng, max_distance);
}

/// AO ray `sample` of a point whose rays continue `stream`: numbers 2·sample and 2·sample + 1 of it
/// (a jump ahead, O(log sample)), bit for bit the ray the CPU renderer draws `sample`-th from a pixel
/// sample's generator (render's ao_rays()).
VF_HOST_DEVICE inline Ray ao_ray(const SurfaceFrame& f, const Rng& stream, unsigned long long sample, float max_distance) {
  Rng rng = stream.advanced(2 * sample);
  return ao_ray(f, rng, max_distance);
}

/// A sphere light as the shadow kernels read it.
struct SphereLightData {
  Vec3f centre;
  float radius;
};

/// Shadow ray `sample` from `from` towards `light`: a direction uniform in the cone the sphere
/// subtends (two numbers from Rng(seed, point, sample)), t up to just short of the sphere's
/// surface (SphereCone::sample and the soft-shadow integrator's 1 − 1e-4). A point inside the
/// light gets an empty ray (tmax = 0), which nothing occludes.
VF_HOST_DEVICE inline Ray cone_ray(const Vec3f& from, const SphereLightData& light, unsigned long long seed, unsigned long long point,
                                   unsigned long long sample) {
  Rng rng(seed, point, sample);
  const float u = rng.uniform(), v = rng.uniform();
  const Vec3f to = light.centre - from;
  const float d = hd::sqrt(dot(to, to));
  if (!(d > light.radius)) return Ray{from, Vec3f{0.0f, 0.0f, 1.0f}, 0.0f, 0.0f};
  const Vec3f axis = to * (1.0f / d);
  const OrthonormalBasis<float> basis = orthonormal_basis(hd::Vec3<float>{axis.x, axis.y, axis.z});
  const float sin2 = (light.radius * light.radius) / (d * d);
  const float one_minus_cos_max = sin2 / (1.0f + hd::sqrt(hd::max(0.0f, 1.0f - sin2)));
  const float cos_theta = 1.0f - u * one_minus_cos_max;
  const float sin_theta = hd::sqrt(hd::max(0.0f, 1.0f - cos_theta * cos_theta));
  float sp, cp;
  sincos_turn(v, sp, cp);
  const Vec3f tangent{basis.u.x, basis.u.y, basis.u.z}, bitangent{basis.v.x, basis.v.y, basis.v.z};
  Vec3f wi = tangent * (sin_theta * cp) + bitangent * (sin_theta * sp) + axis * cos_theta;
  wi = wi * (1.0f / hd::sqrt(dot(wi, wi)));
  const float inside = light.radius * light.radius - d * d * (1.0f - cos_theta * cos_theta);
  const float t = d * cos_theta - hd::sqrt(hd::max(0.0f, inside));
  return Ray{from, wi, 0.0f, hd::max(t, 0.0f) * (1.0f - 1e-4f)};
}

/// A glossy reflection ray and its weight f·cos/pdf over the specular colour (scalar: GGX's
/// G(wo) G(wi) (wo·h) / (cos_o cos_h), 1 for a mirror); `valid` false when the sampled direction
/// falls below the surface (the ray is then empty).
struct GlossySample {
  Ray ray;
  float weight = 0.0f;
  bool valid = false;
};

/// Smith's masking for GGX of a direction at cosine c (> 0) to the normal (render/bsdf.cpp's).
VF_HOST_DEVICE inline float smith_g1(float c, float alpha) {
  const float a2 = alpha * alpha;
  return 2.0f * c / (c + hd::sqrt(a2 + (1.0f - a2) * c * c));
}

/// Reflection ray `sample` at frame `f` seen from unit `wo` (towards the viewer, on the normal's
/// side): a mirror for alpha = 0, else a GGX half vector of roughness alpha drawn by its normal
/// distribution from two numbers of Rng(seed, point, sample). Bsdf::sample_specular's maths.
VF_HOST_DEVICE inline GlossySample glossy_ray(const SurfaceFrame& f, const Vec3f& wo, float alpha, unsigned long long seed,
                                              unsigned long long point, unsigned long long sample) {
  Rng rng(seed, point, sample);
  const float u = rng.uniform(), v = rng.uniform();
  GlossySample out;
  out.ray = Ray{f.position, f.normal, 0.0f, 0.0f};
  const float cos_o = dot(wo, f.normal);
  if (!(cos_o > 0.0f)) return out;
  if (!(alpha > 0.0f)) {
    out.ray = Ray{f.position, f.normal * (2.0f * cos_o) - wo};
    out.weight = 1.0f;
    out.valid = true;
    return out;
  }
  const float tan2 = alpha * alpha * u / (1.0f - u);
  const float cos_h = 1.0f / hd::sqrt(1.0f + tan2);
  const float sin_h = hd::sqrt(hd::max(0.0f, 1.0f - cos_h * cos_h));
  float sp, cp;
  sincos_turn(v, sp, cp);
  const Vec3f h = to_world(f, Vec3f{sin_h * cp, sin_h * sp, cos_h});
  const float o_h = dot(wo, h);
  const Vec3f wi = h * (2.0f * o_h) - wo;
  const float cos_i = dot(wi, f.normal);
  if (!(cos_i > 0.0f && o_h > 0.0f)) return out;
  out.ray = Ray{f.position, wi};
  out.weight = smith_g1(cos_o, alpha) * smith_g1(cos_i, alpha) * o_h / (cos_o * cos_h);
  out.valid = true;
  return out;
}

}  // namespace vf::gpu

// GCC 12 reports the undefined-value operands of its own avx512fintrin.h (_mm512_undefined_*) as
// uninitialised once the cone's lane intrinsics are inlined (as in sample_rays.cpp).
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "visfield/render/lights.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sample_lanes.hpp"
#include "visfield/core/sampling.hpp"

namespace vf {
namespace {

float luminance(const Vec3f& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// 1 - cos of the half-angle a sphere of radius r subtends at distance d > r, without the
// cancellation of 1 - sqrt(1 - s) for small lights far away.
float one_minus_cos_max(float r, float d) {
  const float sin2 = (r * r) / (d * d);
  return sin2 / (1.0f + std::sqrt(std::fmax(0.0f, 1.0f - sin2)));
}

}  // namespace

PointLight default_point_light(const Scene& scene) {
  const Bounds3f b = scene.bounds();
  const Vec3f center = b.empty() ? Vec3f{0.0f} : b.center();
  const float lift = b.empty() ? 1.0f : std::fmax(max_component(b.extent()), 1e-3f);
  const float top = b.empty() ? 0.0f : b.hi.y;
  PointLight light;
  light.position = {center.x, top + lift, center.z};
  const float d = light.position.y - center.y;
  light.intensity = Vec3f{std::numbers::pi_v<float> * d * d};
  return light;
}

SceneLights::SceneLights(const Scene& scene, bool emitters) {
  for (const PointLight& light : scene.point_lights)
    if (!(emitters && light.proxy)) points_.push_back(light);
  spheres_ = scene.sphere_lights;
  if (emitters) {
    for (const Instance& object : scene.instances()) {
      const TriangleMesh& mesh = scene.meshes[object.mesh];
      for (std::uint32_t prim = 0; prim < mesh.triangles.size(); ++prim) {
        const Material& material = scene.material_of(object.id, prim);
        if (!(max_component(material.emission) > 0.0f)) continue;
        const TriangleIndices& t = mesh.triangles[prim];
        Emitter e;
        e.p0 = object.transform.apply_point(mesh.positions[t[0]]);
        e.e1 = object.transform.apply_point(mesh.positions[t[1]]) - e.p0;
        e.e2 = object.transform.apply_point(mesh.positions[t[2]]) - e.p0;
        e.area = 0.5f * length(cross(e.e1, e.e2));
        if (!(e.area > 0.0f)) continue;
        e.radiance = material.emission;
        e.instance = object.id;
        e.prim = prim;
        triangles_.push_back(e);
      }
    }
    double sum = 0.0;
    for (const Emitter& e : triangles_) {
      sum += static_cast<double>(e.area) * luminance(e.radiance);
      triangle_cdf_.push_back(static_cast<float>(sum));
    }
    if (sum > 0.0)
      for (float& c : triangle_cdf_) c = static_cast<float>(c / sum);
    else
      triangles_.clear(), triangle_cdf_.clear();
    if (!triangle_cdf_.empty()) triangle_cdf_.back() = 1.0f;
  }
  if (points_.empty() && spheres_.empty() && triangles_.empty()) points_.push_back(default_point_light(scene));
}

std::optional<LightSample> SceneLights::sample(const Vec3f& from, Rng& rng) const {
  const std::size_t n = choices();
  const std::size_t pick = std::min<std::size_t>(static_cast<std::size_t>(rng.uniform() * static_cast<float>(n)), n - 1);
  const float u = rng.uniform(), v = rng.uniform(), w = rng.uniform();
  const float choose = 1.0f / static_cast<float>(n);
  if (pick < points_.size()) {
    const PointLight& light = points_[pick];
    const Vec3f to = light.position - from;
    const float d2 = dot(to, to);
    if (!(d2 > 0.0f)) return std::nullopt;
    const float d = std::sqrt(d2);
    return LightSample{to * (1.0f / d), d, light.intensity * (1.0f / (d2 * choose)), 1.0f, true};
  }
  if (pick < points_.size() + spheres_.size()) {
    std::optional<LightSample> sample = sample_sphere(static_cast<std::uint32_t>(pick - points_.size()), from, u, v);
    if (sample) sample->pdf *= choose;
    return sample;
  }
  // Emitting triangles: one by the area x luminance table, then a uniform point on it.
  const auto found = std::lower_bound(triangle_cdf_.begin(), triangle_cdf_.end(), w);
  const std::size_t index = std::min<std::size_t>(static_cast<std::size_t>(found - triangle_cdf_.begin()), triangles_.size() - 1);
  const Emitter& e = triangles_[index];
  const float root = std::sqrt(u);
  const Vec3f at = e.p0 + e.e1 * (1.0f - v) * root + e.e2 * (v * root);
  const Vec3f to = at - from;
  const float d2 = dot(to, to);
  if (!(d2 > 0.0f)) return std::nullopt;
  const float d = std::sqrt(d2);
  const Vec3f wi = to * (1.0f / d);
  const Vec3f normal = cross(e.e1, e.e2);
  const float cos_light = std::fabs(dot(normal, wi)) / length(normal);
  if (!(cos_light > 0.0f)) return std::nullopt;
  const float chosen = triangle_cdf_[index] - (index ? triangle_cdf_[index - 1] : 0.0f);
  const float pdf = choose * chosen / e.area * d2 / cos_light;
  return LightSample{wi, d, e.radiance, pdf, false};
}

std::optional<SphereCone> SphereCone::toward(const SphereLight& light, const Vec3f& from) {
  const Vec3f to = light.center - from;
  const float d = length(to);
  if (!(d > light.radius)) return std::nullopt;
  SphereCone cone;
  cone.axis_ = to * (1.0f / d);
  orthonormal_basis(cone.axis_, cone.tangent_, cone.bitangent_);
  cone.radiance_ = light.radiance;
  cone.distance_ = d;
  cone.radius_ = light.radius;
  cone.one_minus_cos_max_ = one_minus_cos_max(light.radius, d);
  cone.pdf_ = 1.0f / (2.0f * std::numbers::pi_v<float> * cone.one_minus_cos_max_);
  return cone;
}

LightSample SphereCone::sample(float u, float v) const {
  const float cos_theta = 1.0f - u * one_minus_cos_max_;
  const float sin_theta = std::sqrt(std::fmax(0.0f, 1.0f - cos_theta * cos_theta));
  float sin_phi, cos_phi;
  sincos_turn(v, sin_phi, cos_phi);  // of 2πv
  const Vec3f wi = normalize(tangent_ * (sin_theta * cos_phi) + bitangent_ * (sin_theta * sin_phi) + axis_ * cos_theta);
  // Entry point along wi: the nearer root of |from + t wi - c| = r.
  const float inside = radius_ * radius_ - distance_ * distance_ * (1.0f - cos_theta * cos_theta);
  const float t = distance_ * cos_theta - std::sqrt(std::fmax(0.0f, inside));
  return LightSample{wi, std::fmax(t, 0.0f), radiance_, pdf_, false};
}

void SphereCone::sample(Rng& rng, std::size_t count, Vec3f* wi, float* distance) const {
  std::size_t k = 0;
#if defined(VF_SAMPLE_LANES)
  if (count >= 4) {
    // sample(u, v) on lanes, its operations in its order (no fused multiply-adds). On AVX2 too:
    // drawn one at a time, the samples were half of a soft-shadow render's time through fields.
    using L = render_detail::SampleLanes;
    constexpr int kWidth = L::kWidth;
    render_detail::PairLanes lanes(rng);
    const L::F zero = L::splat(0.0f), one = L::splat(1.0f);
    const L::F one_minus_cos_max = L::splat(one_minus_cos_max_), d = L::splat(distance_);
    const L::F r2 = L::splat(radius_ * radius_), d2 = L::splat(distance_ * distance_);
    alignas(64) float x[kWidth], y[kWidth], z[kWidth], t[kWidth];
    for (; k < count; k += kWidth) {  // the last packet's spare lanes are not kept
      L::F u, v;
      lanes.pairs(u, v);
      const L::F cos_theta = L::sub(one, L::mul(u, one_minus_cos_max));
      const L::F sin2 = L::sub(one, L::mul(cos_theta, cos_theta));
      const L::F sin_theta = L::sqrt(L::max(sin2, zero));
      L::F sin_phi, cos_phi;
      render_detail::sincos_turn(v, sin_phi, cos_phi);
      const L::F a = L::mul(sin_theta, cos_phi), b = L::mul(sin_theta, sin_phi);
      const auto component = [&](float tc, float bc, float ac) {
        return L::add(L::add(L::mul(L::splat(tc), a), L::mul(L::splat(bc), b)), L::mul(L::splat(ac), cos_theta));
      };
      const L::F wx = component(tangent_.x, bitangent_.x, axis_.x), wy = component(tangent_.y, bitangent_.y, axis_.y),
                 wz = component(tangent_.z, bitangent_.z, axis_.z);
      const L::F length = L::sqrt(L::add(L::add(L::mul(wx, wx), L::mul(wy, wy)), L::mul(wz, wz)));
      const L::F inverse = L::div(one, length);
      L::store(x, L::mul(wx, inverse));
      L::store(y, L::mul(wy, inverse));
      L::store(z, L::mul(wz, inverse));
      const L::F inside = L::sub(r2, L::mul(d2, sin2));
      const L::F entry = L::sub(L::mul(d, cos_theta), L::sqrt(L::max(inside, zero)));
      L::store(t, L::max(entry, zero));
      for (std::size_t lane = 0; lane < std::min<std::size_t>(kWidth, count - k); ++lane) {
        wi[k + lane] = Vec3f{x[lane], y[lane], z[lane]};
        distance[k + lane] = t[lane];
      }
    }
    k = count;
    rng = rng.advanced(2 * count);
  }
#endif
  for (; k < count; ++k) {
    const float u = rng.uniform(), v = rng.uniform();
    const LightSample s = sample(u, v);
    wi[k] = s.wi;
    distance[k] = s.distance;
  }
}

std::optional<LightSample> SceneLights::sample_sphere(std::uint32_t index, const Vec3f& from, float u, float v) const {
  const std::optional<SphereCone> cone = SphereCone::toward(spheres_[index], from);
  if (!cone) return std::nullopt;
  return cone->sample(u, v);
}

float SceneLights::sphere_pdf(std::uint32_t light, const Vec3f& from) const {
  const SphereLight& s = spheres_[light];
  const float d = length(s.center - from);
  if (!(d > s.radius)) return 0.0f;
  return 1.0f / (static_cast<float>(choices()) * 2.0f * std::numbers::pi_v<float> * one_minus_cos_max(s.radius, d));
}

float SceneLights::emitter_pdf(ObjectId instance, std::uint32_t prim, const Vec3f& from, const Vec3f& at,
                               const Vec3f& normal) const {
  const auto found = std::lower_bound(triangles_.begin(), triangles_.end(), std::pair{instance, prim}, [](const Emitter& e, const auto& key) {
    return e.instance != key.first ? e.instance < key.first : e.prim < key.second;
  });
  if (found == triangles_.end() || found->instance != instance || found->prim != prim) return 0.0f;
  const std::size_t index = static_cast<std::size_t>(found - triangles_.begin());
  const Vec3f to = at - from;
  const float d2 = dot(to, to);
  const float cos_light = std::fabs(dot(normal, to)) / (length(normal) * std::sqrt(d2));
  if (!(cos_light > 0.0f)) return 0.0f;
  const float chosen = triangle_cdf_[index] - (index ? triangle_cdf_[index - 1] : 0.0f);
  return chosen / (static_cast<float>(choices()) * found->area) * d2 / cos_light;
}

std::optional<SphereLightHit> SceneLights::first_sphere(const Ray& ray, float t_max) const {
  std::optional<SphereLightHit> best;
  float nearest = t_max;
  for (std::uint32_t i = 0; i < spheres_.size(); ++i) {
    const SphereLight& s = spheres_[i];
    const Vec3f oc = ray.org - s.center;
    const float b = dot(oc, ray.dir), c = dot(oc, oc) - s.radius * s.radius;
    const float disc = b * b - c;
    if (!(disc >= 0.0f) || c < 0.0f) continue;  // missed, or the origin is inside (the light is seen from outside only)
    const float t = -b - std::sqrt(disc);
    if (t > ray.tmin && t < nearest) nearest = t, best = SphereLightHit{t, i};
  }
  return best;
}

}  // namespace vf

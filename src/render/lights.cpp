// GCC 12 reports the undefined-value operands of its own avx512fintrin.h (_mm512_undefined_*) as
// uninitialised once the cone's lane intrinsics are inlined (as in sample_rays.cpp).
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "visfield/render/lights.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numbers>

#include "core/isa_dispatch.hpp"
#include "sample_lanes.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/render/bsdf.hpp"

namespace vf::isa_avx512 {
void sphere_cone_sample(const SphereCone& cone, Rng& rng, std::size_t count, Vec3f* wi, float* distance);
std::size_t sphere_light_rays(std::span<const SphereLight> lights, const Vec3f& from, const Bsdf& bsdf, const Vec3f& wo, int per_light,
                              Rng& rng, Ray* rays, Vec3f* contribution);
}  // namespace vf::isa_avx512

namespace vf {
namespace {

// 1 - cos of the half-angle a sphere of radius r subtends at distance d > r, without the
// cancellation of 1 - sqrt(1 - s) for small lights far away.
float one_minus_cos_max(float r, float d) {
  const float sin2 = (r * r) / (d * d);
  return sin2 / (1.0f + std::sqrt(std::fmax(0.0f, 1.0f - sin2)));
}

#if defined(VF_SAMPLE_LANES)
/// The cone of `shape` in every lane.
render_detail::ConeLanes lanes_of(const SphereCone::Shape& shape) {
  using L = render_detail::SampleLanes;
  render_detail::ConeLanes c;
  for (int i = 0; i < 3; ++i) {
    c.axis[i] = L::splat(shape.axis[i]);
    c.tangent[i] = L::splat(shape.tangent[i]);
    c.bitangent[i] = L::splat(shape.bitangent[i]);
  }
  c.distance = L::splat(shape.distance);
  c.radius2 = L::splat(shape.radius * shape.radius);
  c.distance2 = L::splat(shape.distance * shape.distance);
  c.one_minus_cos_max = L::splat(shape.one_minus_cos_max);
  return c;
}

/// sphere_light_rays() on lanes for a Lambertian surface (`cos_o` = dot(wo, normal) > 0), up to
/// kWidth lights: a lane a sample, the lights' samples one after another across the lanes, each
/// lane's cone looked up by its light. Returns how many rays it wrote.
std::size_t lambert_light_rays(std::span<const SphereLight> lights, const Vec3f& from, const Bsdf::Lambert& lambert, int per_light,
                               Rng& rng, Ray* rays, Vec3f* contribution) {
  using L = render_detail::SampleLanes;
  constexpr int kWidth = L::kWidth;
  // Each light's values, a table a value (lane j: light j): axis, tangent and bitangent x y z, then
  // distance, radius², distance², 1 − cos max, radiance x y z and (1 / per_light) / pdf.
  enum : int { kAxis = 0, kTangent = 3, kBitangent = 6, kDistance = 9, kRadius2, kDistance2, kOneMinusCosMax, kWeight, kScale = kWeight + 3, kValues };
  alignas(64) float table[kValues][kWidth] = {};
  std::uint32_t present = 0;
  const float per_ray = 1.0f / static_cast<float>(per_light);
  for (std::size_t j = 0; j < lights.size(); ++j) {
    const std::optional<SphereCone> cone = SphereCone::toward(lights[j], from);
    if (!cone) continue;
    present |= 1u << j;
    const SphereCone::Shape s = cone->shape();
    for (int i = 0; i < 3; ++i) {
      table[kAxis + i][j] = s.axis[i];
      table[kTangent + i][j] = s.tangent[i];
      table[kBitangent + i][j] = s.bitangent[i];
      table[kWeight + i][j] = cone->radiance()[i];
    }
    table[kDistance][j] = s.distance;
    table[kRadius2][j] = s.radius * s.radius;
    table[kDistance2][j] = s.distance * s.distance;
    table[kOneMinusCosMax][j] = s.one_minus_cos_max;
    table[kScale][j] = per_ray / cone->pdf();
  }
  const std::size_t count = lights.size() * static_cast<std::size_t>(per_light);
  std::size_t n = 0;
  if (present != 0) {
    render_detail::PairLanes lanes(rng);
    const L::F zero = L::splat(0.0f);
    const L::F normal[3] = {L::splat(lambert.normal.x), L::splat(lambert.normal.y), L::splat(lambert.normal.z)};
    const L::F albedo[3] = {L::splat(lambert.albedo.x), L::splat(lambert.albedo.y), L::splat(lambert.albedo.z)};
    const L::F opaque = L::splat(lambert.opaque), pi = L::splat(std::numbers::pi_v<float>), shorter = L::splat(1.0f - 1e-4f);
    alignas(64) std::int32_t light_of[kWidth];
    // A chunk of packets at a time in two passes: first each packet's samples, shading and kept
    // lanes (independent packets, so that the core overlaps their long chains: the cone's square
    // roots, sine and cosine, the normalisation's division), then the kept rays written out.
    constexpr std::size_t kPackets = 8;
    alignas(64) float column[7][kPackets][kWidth];  // direction x y z, tmax, contribution x y z
    std::uint32_t kept[kPackets];
    // The light and sample of the packet's first lane. Without branches on the lanes where a light
    // holds a packet's worth of samples (a packet then spans two lights at most).
    std::size_t light = 0, sample = 0;
    const auto per = static_cast<std::size_t>(per_light);
    const auto lanes_below = [](std::size_t k) { return k >= kWidth ? (1u << kWidth) - 1u : (1u << k) - 1u; };
    for (std::size_t chunk = 0; chunk < count; chunk += kPackets * kWidth) {
      const std::size_t packets = std::min(kPackets, (count - chunk + kWidth - 1) / kWidth);
      for (std::size_t p = 0; p < packets; ++p) {
        const std::size_t at = chunk + p * kWidth;
        L::I which;
        std::uint32_t live;
        if (per >= kWidth) {
          const auto boundary = static_cast<int>(per - sample);  // the first lane of the next light, when below kWidth
          which = L::step_at(static_cast<int>(light), boundary);
          const std::uint32_t below = lanes_below(static_cast<std::size_t>(boundary));
          const std::uint32_t next_present = light + 1 < lights.size() ? (present >> (light + 1)) & 1u : 0u;
          live = ((0u - ((present >> light) & 1u)) & below) | ((0u - next_present) & ~below);
          sample += kWidth;
          const bool wrap = sample >= per;
          sample -= wrap ? per : 0;
          light += wrap ? 1 : 0;
        } else {
          live = 0;
          for (int lane = 0; lane < kWidth; ++lane) {
            light_of[lane] = light < lights.size() ? static_cast<std::int32_t>(light) : 0;
            if (light < lights.size() && ((present >> light) & 1u)) live |= 1u << lane;
            if (++sample == per) sample = 0, ++light;
          }
          which = L::load(light_of);
        }
        live &= lanes_below(count - at) & ((1u << kWidth) - 1u);
        L::F u, v;
        lanes.pairs(u, v);  // every packet draws, so that the lanes stay on the stream
        const auto value = [&](int k) { return L::lookup(table[k], which); };
        render_detail::ConeLanes cone;
        for (int i = 0; i < 3; ++i) {
          cone.axis[i] = value(kAxis + i);
          cone.tangent[i] = value(kTangent + i);
          cone.bitangent[i] = value(kBitangent + i);
        }
        cone.distance = value(kDistance);
        cone.radius2 = value(kRadius2);
        cone.distance2 = value(kDistance2);
        cone.one_minus_cos_max = value(kOneMinusCosMax);
        L::F wi[3], distance;
        render_detail::cone_sample(cone, u, v, wi, distance);
        // Bsdf::eval's diffuse lobe, its operations in its order, and max_component(f) > 0.
        const L::F cos_i = L::add(L::add(L::mul(wi[0], normal[0]), L::mul(wi[1], normal[1])), L::mul(wi[2], normal[2]));
        const L::F per_pi = L::div(cos_i, pi);
        L::F f[3];
        for (int i = 0; i < 3; ++i) f[i] = L::mul(L::mul(albedo[i], per_pi), opaque);
        const auto larger = [](L::F a, L::F b) { return L::blend(L::less(a, b), a, b); };  // std::max(a, b)
        kept[p] = L::bits(L::both(L::both(L::from_bits(live), L::less(zero, cos_i)), L::less(zero, larger(f[0], larger(f[1], f[2])))));
        const L::F scale = value(kScale);
        for (int i = 0; i < 3; ++i) {
          L::store(column[i][p], wi[i]);
          L::store(column[4 + i][p], L::mul(L::mul(f[i], value(kWeight + i)), scale));
        }
        L::store(column[3][p], L::mul(distance, shorter));
      }
      for (std::size_t p = 0; p < packets; ++p) {
        if (kept[p] == 0) continue;
        const L::M keep = L::from_bits(kept[p]);
        const auto compressed = [&](int c) { return L::compress(L::load(column[c][p]), keep); };
        const L::F ray_column[8] = {L::splat(from.x), L::splat(from.y), L::splat(from.z), compressed(0), compressed(1), compressed(2), zero, compressed(3)};
        L::store_rays(rays + n, ray_column);
        alignas(64) float c[3][kWidth];
        for (int i = 0; i < 3; ++i) L::store(c[i], compressed(4 + i));
        // Whole packets (the room's slack), so that the loop has no branch on how many were kept.
        for (int lane = 0; lane < kWidth; ++lane) contribution[n + static_cast<std::size_t>(lane)] = Vec3f{c[0][lane], c[1][lane], c[2][lane]};
        n += static_cast<std::size_t>(std::popcount(kept[p]));
      }
    }
  }
  rng = rng.advanced(2 * count);
  return n;
}
#endif

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
  VF_USE_WIDER(sphere_cone_sample, *this, rng, count, wi, distance);
  std::size_t k = 0;
#if defined(VF_SAMPLE_LANES)
  if (count >= 4) {
    // sample(u, v) on lanes, its operations in its order (no fused multiply-adds). On AVX2 too:
    // drawn one at a time, the samples were half of a soft-shadow render's time through fields.
    using L = render_detail::SampleLanes;
    constexpr int kWidth = L::kWidth;
    render_detail::PairLanes lanes(rng);
    const render_detail::ConeLanes cone = lanes_of(shape());
    alignas(64) float x[kWidth], y[kWidth], z[kWidth], t[kWidth];
    for (; k < count; k += kWidth) {  // the last packet's spare lanes are not kept
      L::F u, v, w[3], entry;
      lanes.pairs(u, v);
      render_detail::cone_sample(cone, u, v, w, entry);
      L::store(x, w[0]);
      L::store(y, w[1]);
      L::store(z, w[2]);
      L::store(t, entry);
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

std::size_t sphere_light_rays(std::span<const SphereLight> lights, const Vec3f& from, const Bsdf& bsdf, const Vec3f& wo, int per_light,
                              Rng& rng, Ray* rays, Vec3f* contribution) {
  VF_USE_WIDER(sphere_light_rays, lights, from, bsdf, wo, per_light, rng, rays, contribution);
  std::size_t n = 0;
#if defined(VF_SAMPLE_LANES)
  // Lanes across the samples of all lights (the GPU paper's 20 rays a light: 60 samples in 8 packets
  // of 8, where a light at a time took 9 and waited on each call's few).
  if (const std::optional<Bsdf::Lambert> lambert = bsdf.lambert()) {
    if (!(dot(wo, lambert->normal) > 0.0f)) {  // eval() is 0 for every direction
      rng = rng.advanced(2 * lights.size() * static_cast<std::size_t>(per_light));
      return 0;
    }
    constexpr std::size_t kGroup = render_detail::SampleLanes::kWidth;  // lights a table holds
    for (std::size_t first = 0; first < lights.size(); first += kGroup)
      n += lambert_light_rays(lights.subspan(first, std::min(kGroup, lights.size() - first)), from, *lambert, per_light, rng, rays + n,
                              contribution + n);
    return n;
  }
#endif
  constexpr std::size_t kChunk = 64;  // a light's samples drawn and evaluated together
  std::array<Vec3f, kChunk> wi, f;
  std::array<float, kChunk> distance;
  const float per_ray = 1.0f / static_cast<float>(per_light);
  for (const SphereLight& light : lights) {
    const std::optional<SphereCone> cone = SphereCone::toward(light, from);
    if (!cone) {
      rng = rng.advanced(2 * static_cast<std::uint64_t>(per_light));
      continue;
    }
    const float scale = per_ray / cone->pdf();
    for (std::size_t first = 0; first < static_cast<std::size_t>(per_light); first += kChunk) {
      const std::size_t count = std::min(kChunk, static_cast<std::size_t>(per_light) - first);
      cone->sample(rng, count, wi.data(), distance.data());
      bsdf.eval(wo, std::span<const Vec3f>(wi.data(), count), f.data());
      for (std::size_t k = 0; k < count; ++k) {
        if (!(max_component(f[k]) > 0.0f)) continue;
        rays[n] = Ray{from, wi[k], 0.0f, distance[k] * (1.0f - 1e-4f)};
        contribution[n++] = f[k] * cone->radiance() * scale;
      }
    }
  }
  return n;
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

#if VF_IN_WIDER_COPY
namespace vf::isa_avx512 {
VF_WIDER_ENTRY void sphere_cone_sample(const SphereCone& cone, Rng& rng, std::size_t count, Vec3f* wi, float* distance) {
  cone.sample(rng, count, wi, distance);
}
VF_WIDER_ENTRY std::size_t sphere_light_rays(std::span<const SphereLight> lights, const Vec3f& from, const Bsdf& bsdf, const Vec3f& wo,
                                             int per_light, Rng& rng, Ray* rays, Vec3f* contribution) {
  return vf::sphere_light_rays(lights, from, bsdf, wo, per_light, rng, rays, contribution);
}
}  // namespace vf::isa_avx512
#endif

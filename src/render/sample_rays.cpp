// GCC 12 reports the undefined-value operands of its own avx512fintrin.h (_mm512_undefined_*) as
// uninitialised once the AO packets' intrinsics are inlined (as in src/field/field_batch.cpp).
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "visfield/render/sample_rays.hpp"

#include <algorithm>
#include <cmath>

#include "core/isa_dispatch.hpp"
#include "sample_lanes.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/render/lights.hpp"

namespace vf::isa_avx512 {
void ao_rays(const SurfacePoint& point, Rng& rng, float max_distance, std::size_t count, Ray* out);
}  // namespace vf::isa_avx512

namespace vf {
namespace {

constexpr float kRayRelativeOffset = 1e-5f;    // ~80 ulps of the ray's coordinate magnitudes
constexpr float kSceneRelativeOffset = 1e-6f;  // ~8 ulps of the largest scene coordinate
constexpr float kShadowShortfall = 1e-4f;      // shadow rays stop this fraction short of the light

}  // namespace

Ray pixel_center_ray(const PinholeCamera& camera, int x, int y) {
  return camera.generate(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
}

Ray pixel_ray(const PinholeCamera& camera, int x, int y, bool jitter, Rng& rng) {
  if (!jitter) return pixel_center_ray(camera, x, y);
  const float dx = rng.uniform();
  const float dy = rng.uniform();
  return camera.generate(static_cast<float>(x) + dx, static_cast<float>(y) + dy);
}

float spawn_scale(const Scene& scene) {
  const Bounds3f b = scene.bounds();
  if (b.empty()) return 0.0f;
  return max_component(max(abs(b.lo), abs(b.hi)));
}

float spawn_offset(const Ray& ray, float hit_t, float scene_scale) {
  const float ray_scale = max_component(abs(ray.org)) + std::fabs(hit_t) * length(ray.dir);
  return kRayRelativeOffset * ray_scale + kSceneRelativeOffset * scene_scale;
}

SurfaceSpawner::SurfaceSpawner(const Scene& scene) : scene_(scene), scale_(spawn_scale(scene)) {}

SurfacePoint SurfaceSpawner::surface_point(const Ray& ray, const Hit& hit) const {
  SurfacePoint point;
  point.normal = hit.has_normal ? normalize(hit.normal) : -normalize(ray.dir);
  point.entering = dot(point.normal, ray.dir) <= 0.0f;
  if (!point.entering) point.normal = -point.normal;
  const Vec3f hit_point = ray.org + ray.dir * hit.t;
  const float offset = spawn_offset(ray, hit.t, scale_);
  point.position = hit_point + point.normal * offset;
  point.behind = hit_point - point.normal * offset;
  if (hit.has_triangle()) {
    const Instance& object = scene_.instance(hit.instance);
    const TriangleMesh& mesh = scene_.meshes[object.mesh];
    const TriangleIndices& corners = mesh.triangles[hit.prim];
    Vec3f centroid{0.0f};
    for (std::uint32_t index : corners) centroid += object.transform.apply_point(mesh.positions[index]);
    const Vec3f inward = centroid * (1.0f / 3.0f) - hit_point;
    const float distance = length(inward);
    if (distance > 0.0f) {
      const Vec3f toward_centroid = inward * (std::fmin(offset, 0.5f * distance) / distance);
      point.position += toward_centroid;
      point.behind += toward_centroid;
    }
  }
  orthonormal_basis(point.normal, point.tangent, point.bitangent);
  return point;
}

Ray ao_ray(const SurfacePoint& point, Rng& rng, float max_distance) {
  const float s = rng.uniform();
  const float t = rng.uniform();
  const Vec3f local = cosine_hemisphere(s, t);
  const Vec3f dir = point.tangent * local.x + point.bitangent * local.y + point.normal * local.z;
  return Ray{point.position, dir, 0.0f, max_distance};
}

#if defined(VF_SAMPLE_LANES)
namespace {

/// `count` (<= the lanes' width) AO rays of `point` from the next packet of `lanes` (lane l's s and t its two numbers).
void ao_packet(const SurfacePoint& point, float max_distance, render_detail::PairLanes& lanes, std::size_t count, Ray* out) {
  using L = render_detail::SampleLanes;
  L::F s, t;
  lanes.pairs(s, t);
  // concentric_disk() and cosine_hemisphere(), branches as masks.
  const L::F zero = L::splat(0.0f), one = L::splat(1.0f), two = L::splat(2.0f);
  const L::F a = L::sub(L::mul(two, s), one), b = L::sub(L::mul(two, t), one);
  const L::M centre = L::both(L::equal(a, zero), L::equal(b, zero));
  const L::M a_major = L::greater_equal(L::abs(a), L::abs(b));
  const L::F ratio = L::blend(a_major, L::div(a, b), L::div(b, a));
  const L::F phi = L::mul(L::splat(hd::kPi<float> / 4.0f), ratio);
  L::F sn, cs;
  render_detail::quadrant_sincos(L::abs(phi), sn, cs);
  sn = L::copysign(sn, phi);
  L::F x = L::blend(a_major, L::mul(b, sn), L::mul(a, cs));
  L::F y = L::blend(a_major, L::mul(b, cs), L::mul(a, sn));
  x = L::blend(centre, x, zero);
  y = L::blend(centre, y, zero);
  const L::F rest = L::sub(L::sub(one, L::mul(x, x)), L::mul(y, y));
  const L::F z = L::sqrt(L::blend(L::less(zero, rest), zero, rest));  // hd::max(0, rest)
  // tangent·x + bitangent·y + normal·z, a component at a time.
  const auto world = [&](float tc, float bc, float nc) {
    return L::add(L::add(L::mul(L::splat(tc), x), L::mul(L::splat(bc), y)), L::mul(L::splat(nc), z));
  };
  alignas(64) float dx[L::kWidth], dy[L::kWidth], dz[L::kWidth];
  L::store(dx, world(point.tangent.x, point.bitangent.x, point.normal.x));
  L::store(dy, world(point.tangent.y, point.bitangent.y, point.normal.y));
  L::store(dz, world(point.tangent.z, point.bitangent.z, point.normal.z));
  for (std::size_t lane = 0; lane < count; ++lane) out[lane] = Ray{point.position, Vec3f{dx[lane], dy[lane], dz[lane]}, 0.0f, max_distance};
}

}  // namespace
#endif

void ao_rays(const SurfacePoint& point, Rng& rng, float max_distance, std::size_t count, Ray* out) {
  VF_USE_WIDER(ao_rays, point, rng, max_distance, count, out);
  std::size_t k = 0;
#if defined(VF_SAMPLE_LANES)
  if (count >= 4) {  // the last packet's spare lanes are not kept
    constexpr std::size_t kWidth = render_detail::SampleLanes::kWidth;
    render_detail::PairLanes lanes(rng);
    for (; k < count; k += kWidth) ao_packet(point, max_distance, lanes, std::min(kWidth, count - k), out + k);
    k = count;
    rng = rng.advanced(2 * count);
  }
#endif
  for (; k < count; ++k) out[k] = ao_ray(point, rng, max_distance);
}

LightTargets::LightTargets(const Scene& scene) {
  for (const PointLight& light : scene.point_lights) targets_.push_back({light.position, 0.0f});
  for (const SphereLight& light : scene.sphere_lights) targets_.push_back({light.center, light.radius});
  if (targets_.empty()) targets_.push_back({default_point_light(scene).position, 0.0f});
}

Vec3f LightTargets::sample(const Vec3f& from, Rng& rng) const {
  const Target& target = targets_[rng.next_u32() % targets_.size()];
  const float s = rng.uniform();
  const float t = rng.uniform();
  if (target.radius <= 0.0f) return target.center;
  Vec3f w = uniform_sphere(s, t);
  if (dot(w, from - target.center) < 0.0f) w = -w;
  return target.center + w * target.radius;
}

Ray shadow_ray(const SurfacePoint& point, const Vec3f& target) {
  const Vec3f to_target = target - point.position;
  const float distance = length(to_target);
  if (!(distance > 0.0f)) return Ray{point.position, point.normal, 0.0f, 0.0f};
  return Ray{point.position, to_target * (1.0f / distance), 0.0f, distance * (1.0f - kShadowShortfall)};
}

}  // namespace vf

#if VF_IN_WIDER_COPY
namespace vf::isa_avx512 {
VF_WIDER_ENTRY void ao_rays(const SurfacePoint& point, Rng& rng, float max_distance, std::size_t count, Ray* out) {
  vf::ao_rays(point, rng, max_distance, count, out);
}
}  // namespace vf::isa_avx512
#endif

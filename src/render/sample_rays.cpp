#include "visfield/render/sample_rays.hpp"

#include <cmath>

#include "visfield/core/sampling.hpp"
#include "visfield/render/lights.hpp"

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

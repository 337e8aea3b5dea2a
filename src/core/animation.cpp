#include "visfield/core/animation.hpp"

#include <algorithm>
#include <tuple>

namespace vf {
namespace {

Vec3f lerp(const Vec3f& a, const Vec3f& b, float w) { return a + (b - a) * w; }

// The keys around `time` and the weight of the second: (i, i + 1, w), held at the ends.
template <class Key>
std::tuple<const Key*, const Key*, float> bracket(const std::vector<Key>& keys, float time) {
  if (time <= keys.front().time || keys.size() == 1) return {&keys.front(), &keys.front(), 0.0f};
  if (time >= keys.back().time) return {&keys.back(), &keys.back(), 0.0f};
  const auto next = std::upper_bound(keys.begin(), keys.end(), time, [](float t, const Key& k) { return t < k.time; });
  const Key& b = *next;
  const Key& a = *(next - 1);
  return {&a, &b, (time - a.time) / (b.time - a.time)};
}

}  // namespace

std::pair<float, float> SceneAnimation::time_span() const {
  bool any = false;
  float lo = 0.0f, hi = 0.0f;
  auto take = [&](float t) {
    lo = any ? std::min(lo, t) : t;
    hi = any ? std::max(hi, t) : t;
    any = true;
  };
  for (const CameraKey& k : camera) take(k.time);
  for (const ObjectPath& path : objects)
    for (const PlacementKey& k : path.keys) take(k.time);
  return {lo, hi};
}

CameraKey SceneAnimation::camera_at(float time) const {
  const auto [a, b, w] = bracket(camera, time);
  return CameraKey{time, lerp(a->position, b->position, w), lerp(a->look_at, b->look_at, w), lerp(a->up, b->up, w)};
}

Transform SceneAnimation::placement_at(const ObjectPath& path, float time) {
  const auto [a, b, w] = bracket(path.keys, time);
  Transform t;
  t.translation = lerp(a->translate, b->translate, w);
  t.rotation = Mat3::euler_xyz(lerp(a->rotate_euler_deg, b->rotate_euler_deg, w));
  t.scale = a->scale + (b->scale - a->scale) * w;
  return t;
}

}  // namespace vf

#pragma once
/// \file Whether a world-space ray can meet an object's bounding sphere: the cheap test that lets a
/// scene of fields skip the objects a ray passes by. Host and device (FieldScene and the GPU's copy
/// of it run this one function).

#include "visfield/core/host_device.hpp"
#include "visfield/core/ray.hpp"

namespace vf::field {

/// True when `ray` may meet the sphere (centre, radius) within [tmin, tmax]: the distance from the
/// centre to the ray's line, and whether the sphere lies within the range. The sphere is widened by
/// 1e-3 of its radius so that rounding never culls a ray the object-space query would let in (a
/// batch must answer as the single-ray query does). O(1).
VF_HOST_DEVICE inline bool may_meet_sphere(const Vec3f& centre, float radius, const Ray& ray) {
  const float wide = radius * 1.001f;
  const Vec3f oc = centre - ray.org;
  const float dd = dot(ray.dir, ray.dir);
  const float along = dot(oc, ray.dir);
  const Vec3f perpendicular = oc - ray.dir * (along / dd);
  if (dot(perpendicular, perpendicular) > wide * wide) return false;
  const float reach = wide * hd::sqrt(dd);
  return along + reach >= ray.tmin * dd && along - reach <= ray.tmax * dd;
}

}  // namespace vf::field

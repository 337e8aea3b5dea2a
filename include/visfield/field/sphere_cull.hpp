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
  // The line's squared distance from the centre, times dd, as |oc x dir|^2: no division (a block's
  // sphere pass on lanes was bound by its divider on an Intel Xeon).
  const Vec3f side = cross(oc, ray.dir);
  if (dot(side, side) > wide * wide * dd) return false;
  const float along = dot(oc, ray.dir);
  const float reach = wide * hd::sqrt(dd);
  return along + reach >= ray.tmin * dd && along - reach <= ray.tmax * dd;
}

}  // namespace vf::field

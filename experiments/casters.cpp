#include "casters.hpp"

#include "visfield/field/object_field.hpp"

namespace vf::experiments {

Transform standing_transform(const TriangleSet& set, const Placement& placement) {
  const field::BoundingSphere sphere = field::bounding_sphere_of(set);
  Transform t;
  t.scale = placement.radius / sphere.radius;
  const Vec3f centre = sphere.centre * t.scale;
  t.translation = Vec3f{placement.x, -set.bounds.lo.y * t.scale, placement.z} - Vec3f{centre.x, 0.0f, centre.z};
  return t;
}

}  // namespace vf::experiments

#pragma once
/// \file Scenes of instances for the field and GPU tests: under different transforms, and many in a row.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "visfield/core/rng.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf::test {

/// builtin:boxes with `boxes` boxes on its (exact) ground, every third box turned by 25 degrees about
/// (1, 1, 0.3) and scaled by 0.8: instances of one mesh under several transforms, and an exact part.
inline Scene turned_boxes(std::size_t boxes) {
  Scene scene = make_builtin_scene("boxes", {.size = boxes});
  for (const Instance& object : std::vector<Instance>(scene.instances().begin(), scene.instances().end())) {
    if (object.id % 3 != 0 || scene.meshes[object.mesh].occluder == MeshOccluder::exact) continue;
    Transform t = object.transform;
    t.rotation = Mat3::rotation(normalize(Vec3f{1.0f, 1.0f, 0.3f}), 25.0f) * t.rotation;
    t.scale *= 0.8f;
    scene.set_transform(object.id, t);
  }
  return scene;
}

/// builtin:boxes' box and `count` − 1 copies of it along +x, each 0.2 of its width further (their
/// spheres overlap by far: a ray along the row may meet them all), on its exact ground; `box` gets
/// the first box's world-space bounds.
inline Scene boxes_in_a_row(int count, Bounds3f& box) {
  Scene scene = make_builtin_scene("boxes", {.size = 1});
  const Instance first = *std::find_if(scene.instances().begin(), scene.instances().end(),
                                       [&](const Instance& i) { return scene.meshes[i.mesh].occluder != MeshOccluder::exact; });
  box = Bounds3f{};
  const TriangleSet before = flatten(scene);
  for (std::size_t i = 0; i < before.size(); ++i)
    if (before.instance[i] == first.id)
      for (const Vec3f& p : before.triangles[i]) box.extend(p);
  const float step = 0.2f * (box.hi.x - box.lo.x);
  for (int k = 1; k < count; ++k) {
    Transform t = first.transform;
    t.translation.x += step * static_cast<float>(k);
    scene.add_instance(first.mesh, t);
  }
  return scene;
}

/// `n` rays from before the start of boxes_in_a_row()'s row (`box`: its first box), along it within
/// a hundredth of a radian.
inline std::vector<Ray> rays_along_the_row(const Scene& row, const Bounds3f& box, std::size_t n, std::uint64_t seed) {
  const Bounds3f all = flatten(row).bounds;
  const Vec3f centre = (box.lo + box.hi) * 0.5f, size = box.hi - box.lo;
  Rng rng(seed);
  std::vector<Ray> rays;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3f org{all.lo.x - size.x, centre.y + (rng.uniform() - 0.5f) * size.y, centre.z + (rng.uniform() - 0.5f) * size.z};
    const Vec3f dir{1.0f, (rng.uniform() - 0.5f) * 0.01f, (rng.uniform() - 0.5f) * 0.01f};
    rays.push_back(Ray{org, dir, 0.0f, std::numeric_limits<float>::infinity()});
  }
  return rays;
}

}  // namespace vf::test

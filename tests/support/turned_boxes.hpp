#pragma once
/// \file A scene of instances with different transforms for the field and GPU tests.

#include <cstddef>
#include <vector>

#include "visfield/core/scene.hpp"
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

}  // namespace vf::test

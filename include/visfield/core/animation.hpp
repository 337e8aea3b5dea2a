#pragma once
/// \file Keyframed motion of a scene for walkthroughs: a camera path and objects' own paths, each
/// a list of keys at increasing times, interpolated linearly between keys (held before the first and
/// after the last). Rotations are Euler angles (x, then y, then z, degrees) interpolated per angle.

#include <utility>
#include <vector>

#include "visfield/core/ray.hpp"
#include "visfield/core/transform.hpp"
#include "visfield/core/vec.hpp"

namespace vf {

/// Where the camera is at `time` (the field of view and resolution stay the scene camera's).
struct CameraKey {
  float time = 0.0f;
  Vec3f position;
  Vec3f look_at;
  Vec3f up{0.0f, 1.0f, 0.0f};
};

/// Where an object is at `time`: translation, Euler rotation in degrees, uniform scale (> 0).
struct PlacementKey {
  float time = 0.0f;
  Vec3f translate{0.0f};
  Vec3f rotate_euler_deg{0.0f};
  float scale = 1.0f;
};

/// The keys of one object.
struct ObjectPath {
  ObjectId object = kInvalidId;
  std::vector<PlacementKey> keys;  ///< At least one; times strictly increasing.
};

/// A scene's motion. Empty when the scene does not move. Plain value.
struct SceneAnimation {
  std::vector<CameraKey> camera;     ///< The camera path (empty: the scene camera stays put); times strictly increasing.
  std::vector<ObjectPath> objects;   ///< Objects that move along their own keys.

  /// True when nothing moves.
  bool empty() const { return camera.empty() && objects.empty(); }
  /// The earliest and latest key time over the camera and every object (0, 0 when empty).
  std::pair<float, float> time_span() const;
  /// The camera key interpolated at `time` (the path must not be empty).
  CameraKey camera_at(float time) const;
  /// The placement of `path` interpolated at `time`, as a transform.
  static Transform placement_at(const ObjectPath& path, float time);
};

}  // namespace vf

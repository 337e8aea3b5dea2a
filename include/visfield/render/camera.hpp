#pragma once
/// \file Pinhole camera: pixel coordinates to primary rays.

#include "visfield/core/ray.hpp"
#include "visfield/core/scene.hpp"

namespace vf {

/// Precomputed pinhole frame of a Camera. Immutable, thread-safe.
class PinholeCamera {
 public:
  /// Frame for `camera` (position, look-at, up, vertical fov in degrees, resolution). Throws vf::Error
  /// on a non-positive resolution, a fov outside (0, 180), non-finite vectors, position == look_at, or
  /// up parallel to the view direction.
  explicit PinholeCamera(const Camera& camera);
  /// Ray through film point (x, y) in pixels, (0,0) the top-left corner, (width, height) the bottom-right;
  /// unit direction, tmin 0, tmax infinity.
  Ray generate(float x, float y) const;
  /// Image width in pixels.
  int width() const { return width_; }
  /// Image height in pixels.
  int height() const { return height_; }

 private:
  // Film at unit distance: direction = lower_left_ + right_ * (x / width) + up_ * (1 - y / height).
  Vec3f origin_, lower_left_, right_, up_;
  int width_ = 0, height_ = 0;
};

}  // namespace vf

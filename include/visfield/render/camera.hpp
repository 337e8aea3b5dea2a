#pragma once
/// \file Pinhole camera: pixel coordinates to primary rays.

#include "visfield/core/ray.hpp"
#include "visfield/core/scene.hpp"

namespace vf {

/// Precomputed pinhole frame of a Camera. Immutable, thread-safe.
class PinholeCamera {
 public:
  /// Frame for `camera` (position, look-at, up, vertical fov in degrees, resolution).
  explicit PinholeCamera(const Camera& camera);
  /// Ray through film point (x, y) in pixels, (0,0) the top-left corner, (width, height) the bottom-right;
  /// unit direction, tmin 0, tmax infinity.
  Ray generate(float x, float y) const;
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  Vec3f origin_, lower_left_, right_, up_;
  int width_ = 0, height_ = 0;
};

}  // namespace vf

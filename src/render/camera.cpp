#include "visfield/render/camera.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

#include "visfield/core/error.hpp"

namespace vf {

PinholeCamera::PinholeCamera(const Camera& camera) : origin_(camera.position), width_(camera.width), height_(camera.height) {
  if (camera.width <= 0 || camera.height <= 0) {
    std::ostringstream msg;
    msg << "camera: resolution must be positive, got " << camera.width << "x" << camera.height;
    throw Error(msg.str());
  }
  if (!(camera.fov_degrees > 0.0f && camera.fov_degrees < 180.0f))
    throw Error("camera: fov_degrees must be in (0, 180), got " + std::to_string(camera.fov_degrees));
  if (!is_finite(camera.position) || !is_finite(camera.look_at) || !is_finite(camera.up))
    throw Error("camera: position, look_at and up must be finite");
  const Vec3f view = camera.look_at - camera.position;
  if (dot(view, view) == 0.0f) throw Error("camera: position and look_at coincide");
  const Vec3f forward = normalize(view);
  const Vec3f side = cross(forward, camera.up);
  // Parallel (or zero) up: the cross product vanishes relative to |up|.
  if (!(length(side) > 1e-6f * length(camera.up))) throw Error("camera: up is parallel to the view direction");
  const Vec3f right = normalize(side);
  const Vec3f true_up = cross(right, forward);
  const float half_height = std::tan(0.5f * camera.fov_degrees * std::numbers::pi_v<float> / 180.0f);
  const float half_width = half_height * static_cast<float>(camera.width) / static_cast<float>(camera.height);
  right_ = right * (2.0f * half_width);
  up_ = true_up * (2.0f * half_height);
  lower_left_ = forward - right * half_width - true_up * half_height;
}

Ray PinholeCamera::generate(float x, float y) const {
  const Vec3f dir = lower_left_ + right_ * (x / static_cast<float>(width_)) + up_ * (1.0f - y / static_cast<float>(height_));
  return Ray{origin_, normalize(dir), 0.0f, std::numeric_limits<float>::infinity()};
}

}  // namespace vf

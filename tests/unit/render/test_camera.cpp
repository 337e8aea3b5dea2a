#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "visfield/core/error.hpp"
#include "visfield/render/camera.hpp"

namespace vf {
namespace {

Camera sample_camera() {
  Camera camera;
  camera.position = {1.0f, 2.0f, 3.0f};
  camera.look_at = {0.0f, 0.5f, -1.0f};
  camera.up = {0.0f, 1.0f, 0.0f};
  camera.fov_degrees = 50.0f;
  camera.width = 640;
  camera.height = 480;
  return camera;
}

float angle_between(const Vec3f& a, const Vec3f& b) {
  return std::acos(std::clamp(dot(normalize(a), normalize(b)), -1.0f, 1.0f));
}

TEST(PinholeCamera, CentrePixelLooksAtLookAt) {
  const Camera camera = sample_camera();
  const PinholeCamera pinhole(camera);
  EXPECT_EQ(pinhole.width(), 640);
  EXPECT_EQ(pinhole.height(), 480);
  const Ray ray = pinhole.generate(320.0f, 240.0f);
  const Vec3f expected = normalize(camera.look_at - camera.position);
  EXPECT_EQ(ray.org, camera.position);
  EXPECT_NEAR(ray.dir.x, expected.x, 1e-6f);
  EXPECT_NEAR(ray.dir.y, expected.y, 1e-6f);
  EXPECT_NEAR(ray.dir.z, expected.z, 1e-6f);
  EXPECT_NEAR(length(ray.dir), 1.0f, 1e-6f);
  EXPECT_EQ(ray.tmin, 0.0f);
  EXPECT_TRUE(std::isinf(ray.tmax));
}

TEST(PinholeCamera, EdgesAndCornersSpanTheFieldOfView) {
  const Camera camera = sample_camera();
  const PinholeCamera pinhole(camera);
  const Vec3f forward = normalize(camera.look_at - camera.position);
  const float half_fov = 0.5f * camera.fov_degrees * std::numbers::pi_v<float> / 180.0f;
  const float aspect = 640.0f / 480.0f;
  // Vertical fov: the top and bottom edge centres are half the fov away from the view direction.
  EXPECT_NEAR(angle_between(pinhole.generate(320, 0).dir, forward), half_fov, 1e-5f);
  EXPECT_NEAR(angle_between(pinhole.generate(320, 480).dir, forward), half_fov, 1e-5f);
  // Horizontal extent follows the aspect ratio.
  EXPECT_NEAR(angle_between(pinhole.generate(0, 240).dir, forward), std::atan(aspect * std::tan(half_fov)), 1e-5f);
  // Corners: (0,0) is top-left, (w,h) bottom-right, seen in the camera frame.
  const Vec3f right = normalize(cross(forward, camera.up));
  const Vec3f up = cross(right, forward);
  const Ray top_left = pinhole.generate(0, 0);
  const Ray bottom_right = pinhole.generate(640, 480);
  EXPECT_NEAR(dot(top_left.dir, right) / dot(top_left.dir, forward), -aspect * std::tan(half_fov), 1e-5f);
  EXPECT_NEAR(dot(top_left.dir, up) / dot(top_left.dir, forward), std::tan(half_fov), 1e-5f);
  EXPECT_NEAR(dot(bottom_right.dir, right) / dot(bottom_right.dir, forward), aspect * std::tan(half_fov), 1e-5f);
  EXPECT_NEAR(dot(bottom_right.dir, up) / dot(bottom_right.dir, forward), -std::tan(half_fov), 1e-5f);
}

TEST(PinholeCamera, BadCamerasAreRefused) {
  auto with = [](auto change) {
    Camera camera = sample_camera();
    change(camera);
    return camera;
  };
  EXPECT_THROW(PinholeCamera(with([](Camera& c) { c.width = 0; })), Error);
  EXPECT_THROW(PinholeCamera(with([](Camera& c) { c.height = -3; })), Error);
  EXPECT_THROW(PinholeCamera(with([](Camera& c) { c.fov_degrees = 0.0f; })), Error);
  EXPECT_THROW(PinholeCamera(with([](Camera& c) { c.fov_degrees = 180.0f; })), Error);
  EXPECT_THROW(PinholeCamera(with([](Camera& c) { c.fov_degrees = std::nanf(""); })), Error);
  EXPECT_THROW(PinholeCamera(with([](Camera& c) { c.position.x = std::nanf(""); })), Error);
  EXPECT_THROW(PinholeCamera(with([](Camera& c) { c.look_at = c.position; })), Error);
  EXPECT_THROW(PinholeCamera(with([](Camera& c) { c.up = c.look_at - c.position; })), Error);
  EXPECT_THROW(PinholeCamera(with([](Camera& c) { c.up = Vec3f{0.0f}; })), Error);
}

}  // namespace
}  // namespace vf

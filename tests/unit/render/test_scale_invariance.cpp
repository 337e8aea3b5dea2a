// Scale invariance: a scene scaled by 1e-4 or 1e4 (geometry, objects and camera together) renders the
// same ambient occlusion as at scale 1, up to float rounding. The offset rule is relative to the
// scene's coordinates, so nothing in a render has an absolute length except --max-distance.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "visfield/accel/bvh.hpp"
#include "support/models.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/render/ao.hpp"
#include "visfield/render/camera.hpp"
#include "visfield/render/sample_rays.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

// `scene` with every object and the camera scaled about the origin by `s`.
Scene scaled(Scene scene, float s) {
  Camera camera = scene.camera_or_default(0, 0);  // before the objects move: it may frame them
  camera.position = camera.position * s;
  camera.look_at = camera.look_at * s;
  scene.camera = camera;
  for (const Instance& object : std::vector<Instance>(scene.instances())) {
    Transform t = object.transform;
    t.translation = t.translation * s;
    t.scale *= s;
    scene.set_transform(object.id, t);
  }
  return scene;
}

struct Difference {
  double mean = 0.0, max = 0.0, over_one_ray = 0.0;  // over_one_ray: fraction of pixels off by more than one AO ray
};

Difference compare(const Image& a, const Image& b, int ao_rays) {
  Difference d;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const double diff = std::fabs(static_cast<double>(a.pixels[i].x) - b.pixels[i].x);
    d.mean += diff;
    d.max = std::max(d.max, diff);
    d.over_one_ray += diff > 1.0 / ao_rays + 1e-6 ? 1.0 : 0.0;
  }
  d.mean /= static_cast<double>(a.pixels.size());
  d.over_one_ray /= static_cast<double>(a.pixels.size());
  return d;
}

// `max_distance` (AO ray length at scale 1) is scaled with the scene: the one absolute length of a render.
void check_scale_invariance(const Scene& scene, const char* name, int size, int ao_rays, float max_distance) {
  const auto render = [&](const Scene& s, float scale) {
    AoOptions opt;
    opt.ao_rays = ao_rays;
    opt.progress = false;
    opt.max_distance = max_distance * scale;
    const Bvh bvh = Bvh::build(flatten(s));
    return render_ao(bvh, bvh, s, s.camera_or_default(size, size), opt);
  };
  const Image reference = render(scene, 1.0f);
  for (const float s : {1e-4f, 1e4f}) {
    const Difference d = compare(reference, render(scaled(scene, s), s), ao_rays);
    std::printf("  %s scaled by %g: mean |difference| %.5f, max %.4f, pixels off by more than one ray %.4f%%\n", name, s,
                d.mean, d.max, 100.0 * d.over_one_ray);
    // Rounding moves a few hits and AO rays across edges; nothing more.
    EXPECT_LT(d.mean, 2e-3) << name << " scaled by " << s;
    EXPECT_LT(d.over_one_ray, 0.01) << name << " scaled by " << s;
  }
}

TEST(ScaleInvariance, BuiltinCornellRendersTheSameAtEveryScale) {
  check_scale_invariance(parse_builtin_scene("builtin:cornell"), "builtin:cornell", 96, 32, std::numeric_limits<float>::infinity());
}

TEST(ScaleInvariance, ConferenceWithItsAreaRatioOf1e11RendersTheSameAtEveryScale) {
  const std::filesystem::path path = test::models_dir() / "conference.obj";
  VF_SKIP_WITHOUT_MODELS(std::filesystem::exists(path), "conference.obj");
  // Inside the room, among the chairs and the table, AO within 150 units (the room is 2700 long).
  Scene scene = load_scene(path.string());
  Camera camera;
  camera.position = {1500.0f, 350.0f, 500.0f};
  camera.look_at = {0.0f, 120.0f, -400.0f};
  camera.fov_degrees = 60.0f;
  scene.camera = camera;
  check_scale_invariance(scene, "conference", 96, 16, 150.0f);
}

}  // namespace
}  // namespace vf

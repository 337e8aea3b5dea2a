#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_scenes.hpp"
#include "visfield/core/error.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/registry/walk_structures.hpp"
#include "visfield/render/walkthrough.hpp"

namespace vf {
namespace {

namespace fs = std::filesystem;

const fs::path kExamples = fs::path(VISFIELD_SOURCE_DIR) / "examples" / "scenes";

TEST(Animation, InterpolatesBetweenKeysAndHoldsAtTheEnds) {
  SceneAnimation a;
  a.camera = {CameraKey{0.0f, {0, 0, 0}, {0, 0, -1}, {0, 1, 0}}, CameraKey{2.0f, {4, 0, 0}, {4, 0, -1}, {0, 1, 0}}};
  ObjectPath path{7, {PlacementKey{1.0f, {0, 0, 0}, {0, 0, 0}, 1.0f}, PlacementKey{3.0f, {0, 2, 0}, {0, 90, 0}, 3.0f}}};
  a.objects.push_back(path);
  EXPECT_EQ(a.time_span(), (std::pair<float, float>{0.0f, 3.0f}));
  EXPECT_EQ(a.camera_at(1.0f).position, (Vec3f{2, 0, 0}));
  EXPECT_EQ(a.camera_at(-5.0f).position, (Vec3f{0, 0, 0}));
  EXPECT_EQ(a.camera_at(9.0f).look_at, (Vec3f{4, 0, -1}));
  const Transform mid = SceneAnimation::placement_at(path, 2.0f);
  EXPECT_EQ(mid.translation, (Vec3f{0, 1, 0}));
  EXPECT_FLOAT_EQ(mid.scale, 2.0f);
  // 45 degrees about y takes +x to (cos 45, 0, -sin 45).
  const Vec3f x = mid.rotation * Vec3f{1, 0, 0};
  EXPECT_NEAR(x.x, std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(x.z, -std::sqrt(0.5f), 1e-6f);
}

TEST(Animation, SceneFilesCarryCameraPathsAndKeyframes) {
  const Scene scene = load_scene((kExamples / "walk.json").string());
  ASSERT_EQ(scene.animation.camera.size(), 3u);
  ASSERT_EQ(scene.animation.objects.size(), 1u);
  EXPECT_EQ(scene.animation.objects[0].object, scene.instances()[1].id);
  EXPECT_EQ(scene.animation.objects[0].keys.size(), 3u);
  EXPECT_FLOAT_EQ(scene.animation.objects[0].keys[2].scale, 0.5f);
}

void expect_refused(const std::string& json, const std::string& needle) {
  const fs::path dir = fs::path(VISFIELD_TEST_BINARY_DIR) / "walk_json";
  fs::create_directories(dir);
  std::ofstream(dir / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(dir / "s.json") << json;
  try {
    load_scene((dir / "s.json").string());
    ADD_FAILURE() << "accepted: " << json;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(Animation, BadKeysAreRefused) {
  expect_refused(R"({"meshes": [{"path": "tri.obj"}], "camera_path": [{"time": 1, "position": [0,0,5], "look_at": [0,0,0]},
                  {"time": 1, "position": [1,0,5], "look_at": [0,0,0]}]})",
                 "camera_path[1].time: times must increase from key to key");
  expect_refused(R"({"meshes": [{"path": "tri.obj"}], "camera_path": [{"time": 0, "position": [0,0,5], "look_at": [0,0,0]}]})",
                 "camera_path: expected an array of at least 2");
  expect_refused(R"({"meshes": [{"name": "t", "path": "tri.obj"}], "instances": [{"mesh": "t", "keyframes":
                  [{"time": 0}, {"time": 1, "translate": [1e13, 0, 0]}]}]})",
                 "keyframe at time 1");
  expect_refused(R"({"meshes": [{"name": "t", "path": "tri.obj"}], "instances": [{"mesh": "t", "keyframes":
                  [{"time": 0}, {"time": 1, "scale": 0}]}]})",
                 "instances[0].keyframes[1].scale");
}

// BeamField follows the moving object in place, the BVH is rebuilt; every frame's image is the same.
TEST(Walkthrough, InPlaceUpdatesRenderTheFramesAFreshBuildDoes) {
  Scene a = load_scene((kExamples / "walk.json").string()), b = a;
  RegistryWalkStructures beam(a, "beam:dirs=129,n=32", "", {}), bvh(b, "bvh", "", {});
  WalkOptions options;
  options.frames = 5;
  options.width = 40;
  options.height = 25;
  options.shading.progress = false;
  options.integrator = Integrator::whitted;
  std::vector<Image> images_a, images_b;
  options.on_frame = [&](int, const Image& image) { images_a.push_back(image); };
  const std::vector<WalkFrame> fa = render_walkthrough(a, beam, options);
  options.on_frame = [&](int, const Image& image) { images_b.push_back(image); };
  const std::vector<WalkFrame> fb = render_walkthrough(b, bvh, options);
  ASSERT_EQ(fa.size(), 5u);
  ASSERT_EQ(images_a.size(), 5u);
  for (std::size_t f = 0; f < fa.size(); ++f) {
    EXPECT_EQ(fa[f].frame, static_cast<int>(f));
    EXPECT_FALSE(fa[f].rebuilt);
    EXPECT_TRUE(fb[f].rebuilt);
    EXPECT_GE(fa[f].rays, 40u * 25u);
    EXPECT_EQ(fa[f].rays, fb[f].rays);
    EXPECT_EQ(images_a[f].pixels, images_b[f].pixels) << "frame " << f;
  }
  EXPECT_NE(images_a.front().pixels, images_a.back().pixels);  // the camera and the object moved
  EXPECT_EQ(a.instance(a.animation.objects[0].object).transform.translation, (Vec3f{1.5f, 0.5f, 0.0f}));  // the last key
}

TEST(Walkthrough, AStillSceneOrOneFrameIsRefused) {
  Scene still = test::plane_scene(1.0f);
  RegistryWalkStructures bvh(still, "bvh", "", {});
  WalkOptions options;
  EXPECT_THROW(render_walkthrough(still, bvh, options), Error);
  Scene moving = load_scene((kExamples / "walk.json").string());
  options.frames = 1;
  EXPECT_THROW(render_walkthrough(moving, bvh, options), Error);
}

TEST(WalkCsv, RoundTripsAndRefusesOtherFiles) {
  const fs::path dir = fs::path(VISFIELD_TEST_BINARY_DIR) / "walk_csv";
  fs::create_directories(dir);
  const WalkSeries series{"beam:dirs=513,n=128", {{0, 1.5, 20.25, 65536, false}, {1, 0.0, 19.0, 70000, true}}};
  write_walk_csv(dir / "a.csv", series);
  const WalkSeries back = read_walk_csv(dir / "a.csv");
  EXPECT_EQ(back.label, series.label);
  ASSERT_EQ(back.frames.size(), 2u);
  EXPECT_DOUBLE_EQ(back.frames[0].trace_ms, 20.25);
  EXPECT_EQ(back.frames[1].rays, 70000u);
  EXPECT_TRUE(back.frames[1].rebuilt);
  std::ofstream(dir / "bad.csv") << "# visfield walk: x\nframe,update_ms,trace_ms,rays,rebuilt\n0,1,nan,5,0\n";
  try {
    read_walk_csv(dir / "bad.csv");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv: line 3: expected frame,update_ms"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "other.csv") << "a,b,c\n";
  EXPECT_THROW(read_walk_csv(dir / "other.csv"), Error);
}

TEST(WalkPlot, IsAnSvgWithEverySeriesItsPointsAndItsLabel) {
  const WalkSeries a{"beam", {{0, 0, 10, 1, false}, {1, 0, 12, 1, false}, {2, 0, 11, 1, false}}};
  const WalkSeries b{"bvh <&>", {{0, 2, 30, 1, true}, {1, 2, 28, 1, true}, {2, 2, 31, 1, true}}};
  const std::string svg = walk_plot_svg({a, b}, 640, 360);
  EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"640\" height=\"360\"", 0), 0u) << svg.substr(0, 80);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  const auto count = [&](const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = svg.find(what); at != std::string::npos; at = svg.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("class=\"frame\""), 2u) << "one frame-time line a series";
  EXPECT_EQ(count("class=\"update\""), 1u) << "an update line only where updates took time";
  EXPECT_NE(svg.find(">beam</text>"), std::string::npos);
  EXPECT_NE(svg.find(">bvh &lt;&amp;&gt;</text>"), std::string::npos) << "labels are escaped";
  // Three frames: the second series' points at the plot's left and right ends (x 80 and 620), its
  // largest frame time (33 ms) below the top grid line.
  EXPECT_NE(svg.find("points=\"80.0,"), std::string::npos);
  EXPECT_NE(svg.find(" 620.0,"), std::string::npos);
  EXPECT_THROW(walk_plot_svg({a}, 100, 100), Error);
  EXPECT_THROW(walk_plot_svg({}, 640, 360), Error);
}

TEST(WalkPlot, RefusesAPlotNotNamedSvgBeforeAnyWork) {
  try {
    check_walk_plot_path("walk.png");
    ADD_FAILURE() << "walk.png accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("walk.png: the plot is written as SVG"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vf

// The view a render takes of a scene (framed_view(), view_camera(), the option texts) and the
// background it puts where camera rays miss.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "test_scenes.hpp"
#include "visfield/core/error.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/registry/render_scene.hpp"
#include "visfield/render/view.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

// Adds the closed box [lo, hi] (12 triangles) to `mesh`.
void add_box(TriangleMesh& mesh, const Vec3f& lo, const Vec3f& hi) {
  const auto first = static_cast<std::uint32_t>(mesh.positions.size());
  for (std::uint32_t c = 0; c < 8; ++c) mesh.positions.push_back({(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z});
  const std::uint32_t faces[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                                      {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  for (const auto& f : faces) mesh.triangles.push_back({first + f[0], first + f[1], first + f[2]});
}

// A "T" standing on +Z, as a scan with +Z up would: a post 3 high with a wide bar on top.
Scene z_up_t() {
  TriangleMesh mesh;
  mesh.name = "t";
  add_box(mesh, {-0.3f, -0.3f, 0.0f}, {0.3f, 0.3f, 3.0f});
  add_box(mesh, {-1.5f, -0.3f, 3.0f}, {1.5f, 0.3f, 3.4f});
  return scene_from_mesh(mesh);
}

// A UV sphere of radius 2 far from the origin.
Scene far_sphere() {
  TriangleMesh mesh;
  mesh.name = "sphere";
  const int rings = 16, segments = 32;
  const Vec3f c{50.0f, -20.0f, 70.0f};
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const float theta = std::numbers::pi_v<float> * static_cast<float>(i) / rings, phi = 2.0f * std::numbers::pi_v<float> * static_cast<float>(j) / segments;
      mesh.positions.push_back(c + Vec3f{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)} * 2.0f);
    }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const auto at = [&](int a, int b) { return static_cast<std::uint32_t>(a * segments + (b % segments)); };
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return scene_from_mesh(mesh);
}

// A long low slab, as a nave seen from afar.
Scene long_slab() {
  TriangleMesh mesh;
  mesh.name = "slab";
  add_box(mesh, {-10.0f, 0.0f, -1.0f}, {10.0f, 0.6f, 1.0f});
  return scene_from_mesh(mesh);
}

struct Queries {
  explicit Queries(const Scene& scene) : geometry(scene), built(build_structure("bvh", geometry)), queries(scene_queries(built.structure, built.structure)) {}
  SceneGeometry geometry;
  BuiltStructure built;
  std::unique_ptr<SceneQueries> queries;
};

// Where the covered pixels lie: their bounding rectangle as fractions of the image.
struct Covered {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
  bool touches_border = false;
  double fill = 0.0;  // the larger of the rectangle's width and height fractions
};

Covered covered(const std::vector<float>& coverage, int width, int height) {
  Covered c;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (coverage[static_cast<std::size_t>(y) * width + x] > 0.0f) {
        c.x0 = std::min(c.x0, x), c.x1 = std::max(c.x1, x), c.y0 = std::min(c.y0, y), c.y1 = std::max(c.y1, y);
        c.touches_border = c.touches_border || x == 0 || y == 0 || x == width - 1 || y == height - 1;
      }
  if (c.x1 >= 0) c.fill = std::max(static_cast<double>(c.x1 - c.x0 + 1) / width, static_cast<double>(c.y1 - c.y0 + 1) / height);
  return c;
}

TEST(FramedView, TheSceneFillsHalfTo95PercentOfTheImageFromEveryAxisAndAngle) {
  const std::vector<std::pair<float, float>> views = {{kDefaultAzimuth, kDefaultElevation}, {45, 30}, {0, 0}, {-120, -40}, {200, 90}, {10, -90}};
  int checked = 0;
  for (const Scene& scene : {z_up_t(), far_sphere(), long_slab()}) {
    const Queries q(scene);
    for (const char* up : {"x", "-x", "y", "-y", "z", "-z"})
      for (const auto& [az, el] : views)
        for (const auto& [w, h] : {std::pair{64, 48}, std::pair{40, 72}}) {
          const Camera camera = framed_view(scene, parse_up(up), az, el, 45.0f, w, h);
          const Covered c = covered(camera_coverage(*q.queries, camera, 1, 1, ImageTile{0, 0, w, h}), w, h);
          const std::string where = scene.name + " up " + up + " view " + std::to_string(az) + "," + std::to_string(el) + " " +
                                    std::to_string(w) + "x" + std::to_string(h);
          ASSERT_GE(c.x1, 0) << where << ": nothing in view";
          EXPECT_FALSE(c.touches_border) << where;
          EXPECT_GE(c.fill, 0.5) << where;
          EXPECT_LE(c.fill, 0.95) << where;
          // Centred: the margins on either side differ by a few pixels at most.
          EXPECT_LE(std::abs(c.x0 - (w - 1 - c.x1)), 3) << where;
          EXPECT_LE(std::abs(c.y0 - (h - 1 - c.y1)), 3) << where;
          ++checked;
        }
  }
  EXPECT_EQ(checked, 3 * 6 * 6 * 2);
}

// The row where the covered span is widest, as a fraction of the image's height (0 = top).
double widest_row(const std::vector<float>& coverage, int width, int height) {
  int best = 0, best_row = 0;
  for (int y = 0; y < height; ++y) {
    int n = 0;
    for (int x = 0; x < width; ++x) n += coverage[static_cast<std::size_t>(y) * width + x] > 0.0f;
    if (n > best) best = n, best_row = y;
  }
  return (best_row + 0.5) / height;
}

TEST(FramedView, TheUpAxisIsTheImagesUp) {
  const Scene scene = z_up_t();
  const Queries q(scene);
  const auto coverage_from = [&](const char* up) {
    return camera_coverage(*q.queries, framed_view(scene, parse_up(up), 30.0f, 10.0f, 45.0f, 48, 48), 1, 1, ImageTile{0, 0, 48, 48});
  };
  // Standing on +Z, the T's bar is at the top of the image; upside down (-Z up) at the bottom.
  const std::vector<float> upright = coverage_from("z"), flipped = coverage_from("-z");
  EXPECT_LT(widest_row(upright, 48, 48), 0.3);
  EXPECT_GT(widest_row(flipped, 48, 48), 0.7);
  const Covered c = covered(upright, 48, 48);
  EXPECT_GT(c.y1 - c.y0, 2 * (c.x1 - c.x0) / 3) << "the post stands up the image";
}

TEST(FramedView, AzimuthTurnsRightAndElevationRises) {
  const Scene scene = test::closed_box_scene();
  const Vec3f y{0.0f, 1.0f, 0.0f}, z{0.0f, 0.0f, 1.0f};
  const Camera front = framed_view(scene, y, 0.0f, 0.0f, 45.0f, 32, 32);
  EXPECT_GT(front.position.z, 1.0f);
  EXPECT_NEAR(front.position.x, 0.0f, 1e-4f);
  EXPECT_GT(framed_view(scene, y, 90.0f, 0.0f, 45.0f, 32, 32).position.x, 1.0f);  // from the right (+X)
  EXPECT_GT(framed_view(scene, y, 0.0f, 60.0f, 45.0f, 32, 32).position.y, 1.0f);  // from above
  EXPECT_LT(framed_view(scene, z, 0.0f, 0.0f, 45.0f, 32, 32).position.y, -1.0f);  // Z up: the front is -Y
  const Camera top = framed_view(scene, y, 0.0f, 90.0f, 45.0f, 32, 32);
  EXPECT_GT(top.position.y, 1.0f);
  EXPECT_LT(top.up.z, -0.99f);  // looking down, the far side (-Z) is the image's up
  EXPECT_THROW(framed_view(scene, Vec3f{0.0f}, 0.0f, 0.0f, 45.0f, 32, 32), Error);
  EXPECT_THROW(framed_view(scene, y, 0.0f, 91.0f, 45.0f, 32, 32), Error);
  EXPECT_THROW(framed_view(scene, y, std::nanf(""), 0.0f, 45.0f, 32, 32), Error);
}

TEST(ViewCamera, ThePlacementWinsThenTheViewThenTheScenesCamera) {
  const Scene cornell = parse_builtin_scene("builtin:cornell");
  ASSERT_TRUE(cornell.camera.has_value());
  const Camera own = view_camera(cornell, std::nullopt, std::nullopt, std::nullopt, 40, 30);
  EXPECT_EQ(own.position.x, cornell.camera->position.x);
  EXPECT_EQ(own.width, 40);
  EXPECT_EQ(own.height, 30);
  const Camera framed = view_camera(cornell, std::nullopt, ViewAngles{45.0f, 30.0f}, std::nullopt, 40, 30);
  const Camera expected = framed_view(cornell, {0.0f, 1.0f, 0.0f}, 45.0f, 30.0f, cornell.camera->fov_degrees, 40, 30);
  EXPECT_EQ(framed.position.x, expected.position.x);
  EXPECT_EQ(framed.position.z, expected.position.z);
  const Camera placed = view_camera(cornell, Vec3f{0.0f, 0.0f, 1.0f}, ViewAngles{}, parse_camera_placement("1,2,3,0,0,0"), 0, 0);
  EXPECT_EQ(placed.position.y, 2.0f);
  EXPECT_EQ(placed.up.z, 1.0f);  // the up axis when the placement has none
  EXPECT_EQ(placed.fov_degrees, cornell.camera->fov_degrees);
  EXPECT_EQ(placed.width, cornell.camera->width);
  const Camera full = view_camera(cornell, std::nullopt, std::nullopt, parse_camera_placement("1,2,3,0,0,0,1,0,0,20"), 0, 0);
  EXPECT_EQ(full.up.x, 1.0f);
  EXPECT_EQ(full.fov_degrees, 20.0f);
  // Up along the view: refused before a render starts.
  EXPECT_THROW(view_camera(cornell, Vec3f{0.0f, 1.0f, 0.0f}, std::nullopt, parse_camera_placement("0,5,0,0,0,0"), 0, 0), Error);
}

void expect_refused(const std::function<void()>& parse, const std::string& needle) {
  try {
    parse();
    ADD_FAILURE() << "accepted; expected an error naming " << needle;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
}

TEST(ViewOptions, TextsReadAsDocumentedAndBadOnesAreRefusedInOneLine) {
  EXPECT_EQ(parse_up("z").z, 1.0f);
  EXPECT_EQ(parse_up("+Z").z, 1.0f);
  EXPECT_EQ(parse_up("-y").y, -1.0f);
  EXPECT_EQ(parse_up("X").x, 1.0f);
  for (const char* bad : {"", "w", "+", "xy", "1,0,0", "--z"}) expect_refused([&] { parse_up(bad); }, "up: expected");
  const ViewAngles v = parse_view("45,30");
  EXPECT_EQ(v.azimuth, 45.0f);
  EXPECT_EQ(v.elevation, 30.0f);
  EXPECT_EQ(parse_view("-400.5,-90").elevation, -90.0f);
  for (const char* bad : {"45", "45,30,1", "a,b", "45,", "inf,0", "nan,3"}) expect_refused([&] { parse_view(bad); }, "view: expected");
  expect_refused([] { parse_view("0,91"); }, "elevation");
  const CameraPlacement p = parse_camera_placement("0,1,5,0,0,0");
  EXPECT_EQ(p.from.z, 5.0f);
  EXPECT_FALSE(p.up.has_value());
  EXPECT_FALSE(p.fov_degrees.has_value());
  EXPECT_EQ(*parse_camera_placement("0,1,5,0,0,0,0,0,1,30").fov_degrees, 30.0f);
  for (const char* bad : {"1,2,3", "1,2,3,4,5,6,7", "1,2,3,4,5,6,7,8,9,10,11", "a,2,3,4,5,6"})
    expect_refused([&] { parse_camera_placement(bad); }, "camera: expected");
  expect_refused([] { parse_camera_placement("1,2,3,1,2,3"); }, "coincide");
  expect_refused([] { parse_camera_placement("0,0,5,0,0,0,0,0,1"); }, "parallel");
  expect_refused([] { parse_camera_placement("0,0,5,0,0,0,0,1,0,180"); }, "field of view");
  EXPECT_TRUE(parse_background("transparent").transparent);
  EXPECT_TRUE(parse_background("Transparent").transparent);
  EXPECT_EQ(parse_background("white").color.y, 1.0f);
  EXPECT_EQ(parse_background("#ffffff").color.x, 1.0f);
  EXPECT_EQ(parse_background("#000000").color.z, 0.0f);
  EXPECT_NEAR(parse_background("#808080").color.x, 0.2158605f, 1e-6f);  // sRGB 128 in linear light
  EXPECT_EQ(parse_background("0.5,0.5,0.5").color.x, parse_background("#808080").color.x);
  EXPECT_EQ(parse_background("grey").color.x, parse_background("gray").color.x);
  for (const char* bad : {"pink", "#12345", "#12345g", "1,2,3", "0.5,0.5", "-0.1,0,0", ""})
    expect_refused([&] { parse_background(bad); }, "background: expected");
  const Background d = default_background();
  EXPECT_FALSE(d.transparent);
  EXPECT_LT(d.color.x, 0.1f);  // dark: apart from AO's white
  EXPECT_GT(d.color.z, 0.0f);  // and not black
}

TEST(Background, CoverageIsTheCameraSamplesThatHit) {
  // A ground plane seen from above the horizon: some pixels see it, some the sky.
  const Scene scene = test::plane_scene(2.0f);
  const Queries q(scene);
  const Camera camera = test::camera_looking_at({0.0f, 1.0f, 4.0f}, {0.0f, 0.3f, 0.0f}, 24, 20, 60.0f);
  Camera upright = camera;
  upright.up = {0.0f, 1.0f, 0.0f};
  for (int spp : {1, 4}) {
    ShadingOptions o;
    o.spp = spp;
    const Image raycast = render_shaded(Integrator::raycast, *q.queries, scene, upright, o);
    const std::vector<float> coverage = camera_coverage(*q.queries, upright, spp, o.seed, ImageTile{0, 0, 24, 20});
    int some = 0, none = 0;
    for (std::size_t i = 0; i < coverage.size(); ++i) {
      // The raycast image is black exactly where no sample hit (its ambient term lights every hit).
      EXPECT_EQ(coverage[i] == 0.0f, raycast.pixels[i].x == 0.0f) << "pixel " << i << " spp " << spp;
      EXPECT_EQ(coverage[i] * static_cast<float>(spp), std::round(coverage[i] * static_cast<float>(spp)));
      some += coverage[i] == 1.0f, none += coverage[i] == 0.0f;
    }
    EXPECT_GT(some, 20);
    EXPECT_GT(none, 20);
  }
}

TEST(Background, OpaqueReplacesTheMissesAndTransparentKeepsTheCoveredColour) {
  const Scene scene = test::plane_scene(2.0f);
  Camera camera = test::camera_looking_at({0.0f, 1.0f, 4.0f}, {0.0f, 0.3f, 0.0f}, 24, 20, 60.0f);
  camera.up = {0.0f, 1.0f, 0.0f};
  Scene placed = scene;
  placed.camera = camera;
  RenderSettings s;
  s.ao_rays = 4;
  s.spp = 4;
  s.background = parse_background("white");  // AO's own: the image as the integrator left it
  const SceneRenderer renderer(placed, s);
  const Image white = renderer.render(s).image;
  EXPECT_TRUE(white.alpha.empty());
  const Queries q(placed);
  const std::vector<float> coverage = camera_coverage(*q.queries, camera, s.spp, s.seed, ImageTile{0, 0, 24, 20});

  s.background = parse_background("#204060");
  const Image opaque = renderer.render(s).image;
  EXPECT_TRUE(opaque.alpha.empty());
  s.background = parse_background("transparent");
  const Image clear = renderer.render(s).image;
  ASSERT_EQ(clear.alpha.size(), clear.pixels.size());
  const Vec3f b = parse_background("#204060").color;
  int partial = 0;
  for (std::size_t i = 0; i < white.pixels.size(); ++i) {
    EXPECT_EQ(clear.alpha[i], coverage[i]);
    if (coverage[i] == 1.0f) {
      EXPECT_EQ(opaque.pixels[i].x, white.pixels[i].x);
      EXPECT_EQ(clear.pixels[i].x, white.pixels[i].x);
    } else if (coverage[i] == 0.0f) {
      EXPECT_EQ(opaque.pixels[i].z, b.z);
      EXPECT_EQ(clear.pixels[i].x, 0.0f);
    } else {
      ++partial;
      // Both are the covered colour c, mixed with what shows behind it.
      const float c = coverage[i];
      EXPECT_NEAR(opaque.pixels[i].y, c * clear.pixels[i].y + (1.0f - c) * b.y, 1e-5f);
      EXPECT_NEAR(white.pixels[i].y, c * clear.pixels[i].y + (1.0f - c), 1e-5f);
    }
  }
  EXPECT_GT(partial, 0) << "the horizon's pixels are partly covered at 4 jittered samples";
}

}  // namespace
}  // namespace vf

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "test_scenes.hpp"
#include "visfield/accel/beam_field.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/core/direction_lines.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/render/ao.hpp"
#include "visfield/render/camera.hpp"
#include "visfield/render/sample_rays.hpp"
#include "visfield/render/ray_sets.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

AoOptions quiet_options(int ao_rays) {
  AoOptions opt;
  opt.ao_rays = ao_rays;
  opt.progress = false;
  return opt;
}

TEST(RenderAo, UnoccludedPlaneIsWhite) {
  const Scene scene = test::plane_scene(1000.0f);
  const BruteForce accel = test::scene_oracle(scene);
  const Camera camera = test::camera_looking_at({0, 10, 0}, {0, 0, 0}, 32, 24, 60.0f);
  RenderStats stats;
  const Image image = render_ao(accel, accel, scene, camera, quiet_options(16), &stats);
  ASSERT_EQ(image.width, 32);
  ASSERT_EQ(image.height, 24);
  for (const Vec3f& p : image.pixels) EXPECT_EQ(p, Vec3f{1.0f});
  EXPECT_EQ(stats.rays, 32u * 24u * (1u + 16u));  // every pixel hits the plane
}

TEST(RenderAo, InsideAClosedBoxEverythingIsOccluded) {
  const Scene scene = test::closed_box_scene();
  const BruteForce accel = test::scene_oracle(scene);
  const Camera camera = test::camera_looking_at({0, 0, 0}, {0, -1, 0}, 24, 24, 60.0f);
  const Image image = render_ao(accel, accel, scene, camera, quiet_options(32));
  for (const Vec3f& p : image.pixels) EXPECT_EQ(p, Vec3f{0.0f});
}

TEST(RenderAo, MaxDistanceIgnoresFartherOccluders) {
  // Inside the box the visible floor is at least 0.42 from any wall: with max_distance 0.4 nothing counts.
  const Scene scene = test::closed_box_scene();
  const BruteForce accel = test::scene_oracle(scene);
  const Camera camera = test::camera_looking_at({0, 0, 0}, {0, -1, 0}, 16, 16, 60.0f);
  AoOptions opt = quiet_options(32);
  opt.max_distance = 0.4f;
  for (const Vec3f& p : render_ao(accel, accel, scene, camera, opt).pixels) EXPECT_EQ(p, Vec3f{1.0f});
}

// Cosine-weighted visible fraction at distance d from an infinite wall on an infinite floor, counting
// occluders within r. Cosine-weighted directions project to uniform points on the unit disk; the wall
// blocks those with x <= -d/r (a circular segment), or every direction towards it when r is infinite.
double crease_ao(double d, double r) {
  if (std::isinf(r)) return 0.5;
  const double a = d / r;
  if (a >= 1.0) return 1.0;
  const double segment = std::acos(a) - a * std::sqrt(1.0 - a * a);
  return 1.0 - segment / std::numbers::pi;
}

TEST(RenderAo, CreaseMatchesTheAnalyticVisibleFraction) {
  const Scene scene = test::crease_scene(1000.0f);
  const BruteForce accel = test::scene_oracle(scene);
  const int ao_rays = 40000;  // binomial sigma <= 0.0025
  struct Case {
    float d, r;
  };
  for (const Case c : {Case{0.01f, kInfinity}, Case{1.0f, kInfinity}, Case{1.0f, 2.0f}, Case{0.5f, 2.0f},
                       Case{0.02f, 2.0f}, Case{3.0f, 2.0f}}) {
    SCOPED_TRACE(testing::Message() << "d = " << c.d << ", max_distance = " << c.r);
    // A one-pixel camera with a tiny field of view looks straight down at (d, 0, 0).
    const Camera camera = test::camera_looking_at({c.d, 5, 0}, {c.d, 0, 0}, 1, 1, 0.01f);
    AoOptions opt = quiet_options(ao_rays);
    opt.max_distance = c.r;
    const float value = render_ao(accel, accel, scene, camera, opt).pixels[0].x;
    const double expected = crease_ao(c.d, c.r);
    if (expected == 1.0) {
      EXPECT_EQ(value, 1.0f);  // no direction reaches the wall within max_distance
    } else {
      EXPECT_GT(value, 0.0f);
      EXPECT_LT(value, 1.0f);
      EXPECT_NEAR(value, expected, 0.01);
    }
  }
}

TEST(RenderAo, ImageDoesNotDependOnThreadsOrTiles) {
  const Scene scene = make_builtin_scene("cornell", {.size = 200});
  const BruteForce accel = test::scene_oracle(scene);
  const Camera camera = scene.camera_or_default(40, 30);
  AoOptions opt = quiet_options(8);
  opt.spp = 2;
  opt.seed = 11;
  Image one_thread, two_threads;
  {
    const ThreadLimit limit(1);
    opt.tile_size = 16;
    one_thread = render_ao(accel, accel, scene, camera, opt);
  }
  {
    const ThreadLimit limit(2);
    opt.tile_size = 5;
    two_threads = render_ao(accel, accel, scene, camera, opt);
  }
  EXPECT_EQ(one_thread.pixels, two_threads.pixels);
  std::size_t grey = 0;
  for (const Vec3f& p : one_thread.pixels) grey += p.x > 0.0f && p.x < 1.0f;
  EXPECT_GT(grey, one_thread.pixels.size() / 2);  // the room is mostly partly occluded: the test has teeth
  opt.seed = 12;
  EXPECT_NE(render_ao(accel, accel, scene, camera, opt).pixels, one_thread.pixels);
}

// AO along the lines is traced line by line over the whole image; each pixel must be what the
// per-point loop of the contract gives (render_ao's doc): one ray along each line not perpendicular
// to the normal, weighted by |cos|, summed in line order.
float lines_pixel(const BruteForce& accel, const Scene& scene, const Camera& camera, const AoOptions& opt, int x, int y,
                  std::uint64_t& rays) {
  const PinholeCamera pinhole(camera);
  const SurfaceSpawner spawner(scene);
  const DirectionLines lines(opt.psf_level);
  float value = 0.0f;
  for (int s = 0; s < opt.spp; ++s) {
    Rng rng(opt.seed, static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(camera.width) + x, static_cast<std::uint64_t>(s));
    const Ray primary = pixel_ray(pinhole, x, y, opt.spp > 1, rng);
    const Hit hit = accel.intersect(primary);
    if (!hit) {
      value += kAoBackground;
      continue;
    }
    const SurfacePoint point = spawner.surface_point(primary, hit);
    float total = 0.0f;
    Vec3f sum{0.0f};
    for (std::size_t k = 0; k < lines.size(); ++k) {
      const Vec3f& w = lines.direction(k);
      const float c = dot(point.normal, w);
      if (c == 0.0f) continue;
      total += std::fabs(c);
      ++rays;
      if (!accel.occluded(Ray{point.position, c > 0.0f ? w : -w, 0.0f, opt.max_distance})) sum += Vec3f{std::fabs(c)};
    }
    value += total > 0.0f ? sum.x / total : 1.0f;
  }
  return value / static_cast<float>(opt.spp);
}

TEST(RenderAo, AlongTheLinesEveryPixelIsThePerPointSum) {
  const Scene scene = make_builtin_scene("cornell", {.size = 300});
  const BruteForce accel = test::scene_oracle(scene);
  const Camera camera = scene.camera_or_default(24, 18);
  AoOptions opt = quiet_options(1);
  opt.psf_level = 3;
  opt.spp = 2;
  opt.max_distance = 0.4f * length(scene.bounds().extent());
  // A BeamField occluder takes the line-by-line path (it prefers line streams), any other the
  // point-by-point one; both must give the per-point sum.
  const BeamField beam = BeamField::build(scene, {.level = 3, .resolution = 16, .max_depth = 2});
  ASSERT_TRUE(QueriesOver(accel, beam).occluder_prefers_line_streams());
  ASSERT_FALSE(QueriesOver(accel, accel).occluder_prefers_line_streams());
  RenderStats stats;
  const Image image = render_ao(accel, beam, scene, camera, opt, &stats);
  EXPECT_EQ(render_ao(accel, accel, scene, camera, opt).pixels, image.pixels);
  std::size_t grey = 0;
  std::uint64_t rays = 0;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const float expected = lines_pixel(accel, scene, camera, opt, x, y, rays);
      ASSERT_EQ(image.at(x, y), Vec3f{expected}) << "pixel " << x << ", " << y;
      grey += expected > 0.0f && expected < 1.0f;
    }
  EXPECT_GT(grey, image.pixels.size() / 2);
  EXPECT_EQ(stats.by_kind.camera, 24u * 18u * 2u);
  EXPECT_EQ(stats.by_kind.ao, rays);
  EXPECT_GT(rays, 24u * 18u * 2u * 50u);
  // A region is the whole image's pixels at the same places.
  opt.region = ImageTile{5, 3, 19, 11};
  const Image region = render_ao(accel, beam, scene, camera, opt);
  for (int y = 3; y < 11; ++y)
    for (int x = 5; x < 19; ++x) ASSERT_EQ(region.at(x - 5, y - 3), image.at(x, y));
}

TEST(RenderAo, AlongTheLinesTheImageDoesNotDependOnTheStructureOrThreads) {
  const Scene scene = make_builtin_scene("boxes", {.size = 400});
  const TriangleSet set = flatten(scene);
  const BruteForce brute = BruteForce::build(set);
  const Bvh bvh = Bvh::build(set);
  const Camera camera = scene.camera_or_default(40, 30);
  AoOptions opt = quiet_options(1);
  opt.psf_level = 3;
  Image reference;
  {
    const ThreadLimit limit(1);
    reference = render_ao(bvh, brute, scene, camera, opt);
  }
  for (const int stream : {0, 1}) {
    const BeamField beam = BeamField::build(scene, set, {.level = 3, .resolution = 32, .max_depth = 3, .stream = stream});
    for (const int threads : {1, 2}) {
      const ThreadLimit limit(threads);
      EXPECT_EQ(render_ao(bvh, beam, scene, camera, opt).pixels, reference.pixels) << "stream " << stream << ", " << threads << " threads";
    }
  }
  EXPECT_EQ(render_ao(bvh, bvh, scene, camera, opt).pixels, reference.pixels);
}

TEST(RenderAo, JitterChangesNothingInUniformScenes) {
  AoOptions opt = quiet_options(8);
  for (int spp : {1, 4}) {
    opt.spp = spp;
    const Scene plane = test::plane_scene(1000.0f);
    const BruteForce plane_oracle = test::scene_oracle(plane);
    for (const Vec3f& p :
         render_ao(plane_oracle, plane_oracle, plane, test::camera_looking_at({0, 10, 0}, {0, 0, 0}, 12, 9, 60.0f), opt).pixels)
      EXPECT_EQ(p, Vec3f{1.0f});
    const Scene box = test::closed_box_scene();
    const BruteForce box_oracle = test::scene_oracle(box);
    for (const Vec3f& p :
         render_ao(box_oracle, box_oracle, box, test::camera_looking_at({0, 0, 0}, {0, -1, 0}, 12, 9, 60.0f), opt).pixels)
      EXPECT_EQ(p, Vec3f{0.0f});
  }
}

TEST(RenderAo, StatsCountEveryRayTraced) {
  // A small plane seen from far: some pixels miss (1 ray), the others hit (1 + ao_rays rays).
  const Scene scene = test::plane_scene(2.0f);
  const BruteForce accel = test::scene_oracle(scene);
  const Camera camera = test::camera_looking_at({0, 10, 0}, {0, 0, 0}, 30, 20, 60.0f);
  std::size_t hits = 0;
  for (const Ray& ray : make_primary_rays(scene, camera)) hits += accel.intersect(ray).found;
  ASSERT_GT(hits, 0u);
  ASSERT_LT(hits, 600u);
  RenderStats stats;
  const Image image = render_ao(accel, accel, scene, camera, quiet_options(5), &stats);
  EXPECT_EQ(stats.rays, 600u + 5u * hits);
  EXPECT_EQ(stats.width, 30);
  EXPECT_EQ(stats.height, 20);
  for (const Vec3f& p : image.pixels) EXPECT_EQ(p, Vec3f{kAoBackground});  // misses are sky, the plane is open

  // With jitter, on a plane that fills the view: width * height * spp * (1 + ao_rays).
  const Scene big = test::plane_scene(1000.0f);
  AoOptions opt = quiet_options(5);
  opt.spp = 3;
  const BruteForce big_oracle = test::scene_oracle(big);
  render_ao(big_oracle, big_oracle, big, camera, opt, &stats);
  EXPECT_EQ(stats.rays, 600u * 3u * (1u + 5u));
}

// An occluder that reports every ray clear, whatever the scene: what an approximate occluder that
// misses everything would answer.
struct NothingOccludes {
  bool occluded(const Ray&) const { return false; }
  AccelStats stats() const { return {}; }
  static std::string name() { return "nothing"; }
  static constexpr Exactness exactness = Exactness::approximate;
  ErrorBounds error_bounds() const { return {.occlusion_disagreement = 1.0, .image_rms = 1.0}; }
};
static_assert(OcclusionQuery<NothingOccludes> && !ClosestHitQuery<NothingOccludes>);

TEST(RenderAo, CameraRaysAndOcclusionRaysGoToTheirOwnStructures) {
  const Scene scene = make_builtin_scene("cornell", {.size = 200});
  const Camera camera = scene.camera_or_default(24, 18);
  const BruteForce oracle = test::scene_oracle(scene);
  const AoOptions opt = quiet_options(8);
  // The room occludes, but this occluder does not: every pixel whose camera ray hits is white, and
  // so are the misses.
  for (const Vec3f& p : render_ao(oracle, NothingOccludes{}, scene, camera, opt).pixels) EXPECT_EQ(p, Vec3f{1.0f});
  // An occluder that records its queries gets exactly the AO rays, from the camera hits found by the
  // closest-hit structure.
  const test::RecordingOccluder recorder(oracle);
  RenderStats stats;
  const Image recorded = render_ao(oracle, recorder, scene, camera, opt, &stats);
  std::size_t camera_hits = 0;
  for (const Ray& ray : make_primary_rays(scene, camera)) camera_hits += oracle.intersect(ray).found;
  EXPECT_EQ(recorder.queries().size(), camera_hits * 8);
  EXPECT_EQ(stats.rays, 24u * 18u + camera_hits * 8);
  EXPECT_EQ(recorded.pixels, render_ao(oracle, oracle, scene, camera, opt).pixels);
}

TEST(RenderAo, BadOptionsAreRefused) {
  const Scene scene = test::plane_scene(1.0f);
  const BruteForce accel = test::scene_oracle(scene);
  const Camera camera = test::camera_looking_at({0, 10, 0}, {0, 0, 0}, 4, 4, 60.0f);
  auto refused = [&](auto change) {
    AoOptions opt = quiet_options(4);
    change(opt);
    EXPECT_THROW(render_ao(accel, accel, scene, camera, opt), Error);
  };
  refused([](AoOptions& o) { o.spp = 0; });
  refused([](AoOptions& o) { o.ao_rays = 0; });
  refused([](AoOptions& o) { o.max_distance = 0.0f; });
  refused([](AoOptions& o) { o.max_distance = std::nanf(""); });
  refused([](AoOptions& o) { o.tile_size = 0; });
  Camera bad = camera;
  bad.width = 0;
  EXPECT_THROW(render_ao(accel, accel, scene, bad, quiet_options(4)), Error);
}

// ao_rays() draws the very rays ao_ray() draws one by one, bit for bit, and leaves the generator
// where they leave it: whole packets on lanes (16 with AVX-512, 8 with AVX2), the rest one at a time.
TEST(AoRays, PacketsAreTheRaysOfAoRayOneByOne) {
  Rng frames(5, 1);
  for (const std::size_t count : {0, 1, 3, 4, 5, 7, 8, 9, 15, 16, 17, 20, 121, 300})
    for (int f = 0; f < 6; ++f) {
      SurfacePoint point;
      point.position = Vec3f{frames.uniform(), frames.uniform(), frames.uniform()} * 100.0f - Vec3f{50.0f};
      point.normal = f == 0 ? Vec3f{0.0f, 0.0f, -1.0f} : uniform_sphere(frames.uniform(), frames.uniform());
      orthonormal_basis(point.normal, point.tangent, point.bitangent);
      Rng one(11, static_cast<std::uint64_t>(f), count), many = one;
      std::vector<Ray> rays(count);
      ao_rays(point, many, 3.5f, count, rays.data());
      for (std::size_t k = 0; k < count; ++k) {
        const Ray r = ao_ray(point, one, 3.5f);
        ASSERT_TRUE(r.org == rays[k].org && r.dir == rays[k].dir && r.tmin == rays[k].tmin && r.tmax == rays[k].tmax)
            << count << " rays, frame " << f << ", ray " << k;
      }
      EXPECT_EQ(one.next_u32(), many.next_u32()) << count;
    }
}

}  // namespace
}  // namespace vf

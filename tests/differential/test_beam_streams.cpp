// BeamField's stream path (occluded_batch with stream=1): rays that run exactly along a stored line
// are binned by tile and traced in per-tile packets. Every answer must equal brute force's and the
// ray-by-ray batch's (stream=0), on rays along the lines from anywhere, from surfaces (AO along the
// lines), short and long segments, origins on tile borders, at the sphere's rim, in empty tiles, and
// in batches that mix them with other rays.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "differential/ray_sets.hpp"
#include "differential/test_scenes.hpp"
#include "support/models.hpp"
#include "support/test_scale.hpp"
#include "visfield/accel/batch.hpp"
#include "visfield/accel/beam_field.hpp"
#include "visfield/accel/brute_force.hpp"
#include "visfield/core/direction_lines.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf::test {
namespace {

/// The bounding sphere BeamField tiles (centre of the box, half its diagonal): close enough for
/// placing rays at its rim and in its tiles.
struct Sphere {
  Vec3f centre;
  float radius;
};
Sphere sphere_of(const TriangleSet& set) { return {set.bounds.center(), 0.5f * length(set.bounds.extent())}; }

/// A direction of `lines` bit for bit, or its negation.
Vec3f line_direction(Rng& rng, const DirectionLines& lines) {
  const Vec3f& w = lines.direction(rng.next_u32() % lines.size());
  return rng.next_u32() % 2 ? w : -w;
}

/// Rays along the lines of `lines` of every kind the stream path must handle.
struct LineRays {
  std::string name;
  std::vector<Ray> rays;
};
std::vector<LineRays> rays_along_lines(const TriangleSet& set, const DirectionLines& lines, int n, std::uint64_t seed) {
  const Sphere s = sphere_of(set);
  const auto count = scaled_count(4000);
  std::vector<LineRays> out;
  // From anywhere in and around the scene, unbounded.
  out.push_back({"from anywhere", generate_rays(seed, 0x51, count, [&](Rng& rng) {
                   return Ray{point_around(rng, set.bounds, 0.3f), line_direction(rng, lines)};
                 })});
  // From surface points lifted off their triangle, on the side of the line's orientation: AO along
  // the lines (the VLF-RT workload).
  out.push_back({"from surfaces", generate_rays(seed, 0x52, count, [&](Rng& rng) {
                   const auto& t = random_triangle(rng, set);
                   const Vec3f normal = normalize(cross(t[1] - t[0], t[2] - t[0]));
                   Vec3f d = line_direction(rng, lines);
                   if (dot(d, normal) < 0.0f) d = -d;
                   return Ray{random_point_on(rng, t) + normal * (1e-4f * s.radius), d, 0.0f, std::numeric_limits<float>::infinity()};
                 })});
  // Short segments (most start and end in one leaf, some in one tile's few leaves) and segments
  // that leave the sphere.
  out.push_back({"short and long segments", generate_rays(seed, 0x53, count, [&](Rng& rng) {
                   const float length = s.radius * (rng.next_u32() % 2 ? 0.002f + 0.05f * rng.uniform() : 0.5f + 2.0f * rng.uniform());
                   return Ray{point_around(rng, set.bounds, 0.1f), line_direction(rng, lines), 0.0f, length};
                 })});
  // Origins on the borders of the tiles (in a random line's frame, the tile grid of n per side over
  // the sphere's diameter): the projection falls on a border, where the single-tile test and the
  // footprints' rounding meet.
  out.push_back({"on tile borders", generate_rays(seed, 0x54, count, [&](Rng& rng) {
                   const std::uint32_t line = rng.next_u32() % lines.size();
                   const PsfFrame& f = lines.frame(line);
                   const float size = 2.0f * s.radius / static_cast<float>(n);
                   const float a = -s.radius + size * static_cast<float>(rng.next_u32() % (n + 1));
                   const float b = -s.radius + size * (static_cast<float>(rng.next_u32() % n) + rng.uniform());
                   const float depth = s.radius * (2.0f * rng.uniform() - 1.0f);
                   const Vec3f along = rng.next_u32() % 2 ? f.u : f.v, across = along.x == f.u.x && along.y == f.u.y ? f.v : f.u;
                   const Vec3f org = s.centre + along * a + across * b + f.w * depth;
                   return Ray{org, rng.next_u32() % 2 ? lines.direction(line) : -lines.direction(line)};
                 })});
  // At the sphere's rim: projections close to the edge of the tiled disc (rim tiles, partly outside).
  out.push_back({"at the rim", generate_rays(seed, 0x55, count, [&](Rng& rng) {
                   const std::uint32_t line = rng.next_u32() % lines.size();
                   const PsfFrame& f = lines.frame(line);
                   const float angle = 6.2831853f * rng.uniform(), r = s.radius * (0.95f + 0.1f * rng.uniform());
                   const Vec3f org = s.centre + f.u * (r * std::cos(angle)) + f.v * (r * std::sin(angle)) - f.w * (1.5f * s.radius);
                   return Ray{org, lines.direction(line)};
                 })});
  return out;
}

/// A batch mixing `along` with random directions, rays along other lines than the field's (a finer
/// set), and invalid rays.
std::vector<Ray> mixed_batch(const TriangleSet& set, const std::vector<Ray>& along, std::uint64_t seed) {
  const DirectionLines finer(5);
  std::vector<Ray> rays;
  Rng rng(seed, 0x56);
  for (std::size_t i = 0; i < along.size(); ++i) {
    rays.push_back(along[i]);
    switch (i % 5) {
      case 0: rays.push_back(Ray{point_around(rng, set.bounds, 0.3f), random_direction(rng)}); break;
      case 1: rays.push_back(Ray{point_around(rng, set.bounds, 0.3f), finer.direction(rng.next_u32() % finer.size())}); break;
      case 2: rays.push_back(Ray{along[i].org, along[i].dir, 1.0f, 0.5f}); break;  // empty range
      default: break;
    }
  }
  return rays;
}

/// occluded_batch's answers.
std::vector<std::uint8_t> batch_answers(const BeamField& field, const std::vector<Ray>& rays) {
  std::vector<std::uint8_t> answers(rays.size());
  occluded_batch(field, std::span<const Ray>(rays), std::span<std::uint8_t>(answers));
  return answers;
}

/// Checks the stream path on `set`'s scene with a field of `config` against brute force, the
/// ray-by-ray batch and single queries.
void check_streams(const std::string& name, const Scene& scene, BeamFieldConfig config, std::uint64_t seed) {
  const TriangleSet set = flatten(scene);
  ASSERT_GT(set.size(), 0u);
  config.stream = 1;
  const BeamField streams = BeamField::build(scene, set, config);
  config.stream = 0;
  const BeamField one_by_one = BeamField::build(scene, set, config);
  const BruteForce oracle = BruteForce::build(set);
  std::size_t occluded_total = 0, total = 0;
  for (const LineRays& set_rays : rays_along_lines(set, streams.lines(), config.resolution, seed)) {
    for (const bool mixed : {false, true}) {
      const std::vector<Ray> rays = mixed ? mixed_batch(set, set_rays.rays, seed) : set_rays.rays;
      const std::string label = name + ", " + set_rays.name + (mixed ? ", mixed batch" : "");
      const std::vector<std::uint8_t> got = batch_answers(streams, rays), ray_by_ray = batch_answers(one_by_one, rays);
      std::vector<std::uint8_t> on_this_thread(rays.size());
      occluded_block(streams, std::span<const Ray>(rays), std::span<std::uint8_t>(on_this_thread));
      EXPECT_EQ(on_this_thread, got) << label << ": occluded_block and occluded_batch differ";
      std::size_t wrong = 0, differ = 0, single = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const bool expected = oracle.occluded(rays[i]);
        if ((got[i] != 0) != expected && wrong++ < 5)
          ADD_FAILURE() << label << ": ray " << i << " org (" << rays[i].org.x << ", " << rays[i].org.y << ", " << rays[i].org.z
                        << ") dir (" << rays[i].dir.x << ", " << rays[i].dir.y << ", " << rays[i].dir.z << ") t (" << rays[i].tmin
                        << ", " << rays[i].tmax << "]: stream " << int(got[i]) << ", brute force " << expected;
        differ += got[i] != ray_by_ray[i];
        single += (got[i] != 0) != streams.occluded(rays[i]);
        occluded_total += expected;
      }
      total += rays.size();
      EXPECT_EQ(wrong, 0u) << label;
      EXPECT_EQ(differ, 0u) << label << ": stream and ray-by-ray batches differ";
      EXPECT_EQ(single, 0u) << label << ": stream batch and single queries differ";
    }
  }
  // The rays must meet the geometry often and miss it often, or the comparison says little.
  EXPECT_GT(occluded_total, total / 20) << name;
  EXPECT_LT(occluded_total, total - total / 20) << name;
}

// Small fields keep the oracle cheap; the stream path does not depend on the sizes beyond the
// number of leaves, which the depths vary.
TEST(BeamStreams, RandomSoupAnswersAsBruteForce) {
  check_streams("random soup", scene_from_triangles(random_soup(7, 3000, 0.01f, 0.1f)),
                {.level = 3, .resolution = 32, .max_depth = 4, .leaf_size = 4}, 1);
}

TEST(BeamStreams, HeightFieldOfSharedEdgesAnswersAsBruteForce) {
  check_streams("height field", scene_from_triangles(height_field(3, 40)), {.level = 2, .resolution = 16, .max_depth = 6, .leaf_size = 2}, 2);
}

TEST(BeamStreams, BuiltinScenesWithLargePolygonsAnswerAsBruteForce) {
  for (const char* name : {"cornell", "boxes"})
    check_streams(name, make_builtin_scene(name, {.size = 2000}), {.level = 3, .resolution = 64, .max_depth = 3, .leaf_size = 8}, 3);
}

TEST(BeamStreams, CopiesWithEmptyTilesBetweenAnswerAsBruteForce) {
  // A few far-apart objects: most tiles of most lines are empty.
  check_streams("scattered copies", scattered_copies({mesh_from_triangles(random_soup(4, 300, 0.05f, 0.2f))}, 6, 8.0f, 5),
                {.level = 3, .resolution = 32, .max_depth = 0, .leaf_size = 4}, 4);
}

TEST(BeamStreams, BunnyAnswersAsBruteForce) {
  const std::filesystem::path path = models_dir() / "bun_zipper.ply";
  VF_SKIP_WITHOUT_MODELS(std::filesystem::exists(path), "bun_zipper.ply");
  check_streams("bunny", load_scene(path.string()), {.level = 3, .resolution = 64, .max_depth = 4, .leaf_size = 4}, 6);
}

}  // namespace
}  // namespace vf::test

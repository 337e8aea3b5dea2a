// visfield-bench's pieces: option parsing, ray-count scaling, timing, agreement, report, Embree adapter.
#include <gtest/gtest.h>

#include <cmath>
#include <chrono>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <xmmintrin.h>

#include "agreement.hpp"
#include "bench_accel.hpp"
#include "bench_options.hpp"
#include "visfield/render/ray_sets.hpp"
#include "report.hpp"
#include "timing.hpp"
#include "visfield/accel/brute_force.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf::bench {
namespace {

std::optional<BenchOptions> parse(std::vector<std::string> args, std::ostream& help = std::cout) {
  args.insert(args.begin(), "visfield-bench");
  std::vector<const char*> argv;
  for (const std::string& arg : args) argv.push_back(arg.c_str());
  return parse_bench_options(static_cast<int>(argv.size()), argv.data(), help);
}

TEST(BenchOptions, DefaultsAndCommaSeparatedStructures) {
  const auto options = parse({"--scene", "builtin:soup", "--rays", "ao", "--accel", "bvh,brute"});
  ASSERT_TRUE(options);
  EXPECT_EQ(options->scene, "builtin:soup");
  EXPECT_EQ(options->kind, RayKind::ao);
  EXPECT_EQ(options->accels, (std::vector<std::string>{"bvh", "brute"}));
  const auto with_params = parse({"--scene", "s.obj", "--rays", "ao", "--accel", "bvh:leaf=4,levels=2,grid"});
  ASSERT_TRUE(with_params);
  EXPECT_EQ(with_params->accels, (std::vector<std::string>{"bvh:leaf=4,levels=2", "grid"}));
  EXPECT_FALSE(options->count);
  EXPECT_EQ(options->threads, 0);
  EXPECT_EQ(options->reps, 5);
  EXPECT_EQ(options->warmup, 1);
  EXPECT_EQ(options->ao_rays, 4);
  EXPECT_FALSE(options->json);
  EXPECT_TRUE(std::isinf(options->max_distance));
}

TEST(BenchOptions, EveryValueIsRead) {
  const auto options =
      parse({"--scene",   "a.ply",  "--rays", "random",  "--accel", "brute",    "--count", "123",
             "--threads", "3",      "--json", "--width", "64",      "--height", "48",      "--ao-rays",
             "7",         "--seed", "99",     "--reps",  "9",       "--warmup", "0",       "--max-distance",
             "2.5"});
  ASSERT_TRUE(options);
  EXPECT_EQ(options->kind, RayKind::random);
  EXPECT_EQ(options->count, 123u);
  EXPECT_EQ(options->threads, 3);
  EXPECT_TRUE(options->json);
  EXPECT_EQ(options->width, 64);
  EXPECT_EQ(options->height, 48);
  EXPECT_EQ(options->ao_rays, 7);
  EXPECT_EQ(options->seed, 99u);
  EXPECT_EQ(options->reps, 9);
  EXPECT_EQ(options->warmup, 0);
  EXPECT_FLOAT_EQ(options->max_distance, 2.5f);
}

TEST(BenchOptions, HelpReturnsNothingAndPrintsTheOptions) {
  std::ostringstream help;
  EXPECT_FALSE(parse({"--help"}, help));
  EXPECT_NE(help.str().find("--accel"), std::string::npos);
}

TEST(BenchOptions, BadValuesAreUsageErrors) {
  const std::vector<std::string> base{"--scene", "s.obj", "--rays", "primary"};
  const auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = base;
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  };
  EXPECT_THROW(parse(with({"--accel", "bvh", "--count", "0"})), UsageError);
  EXPECT_THROW(parse(with({"--accel", "bvh", "--threads", "-2"})), UsageError);
  EXPECT_THROW(parse(with({"--accel", "bvh", "--threads", "5000"})), UsageError);
  EXPECT_THROW(parse(with({"--accel", "bvh,kdtree9"})), UsageError);
  EXPECT_THROW(parse(with({"--accel", "brute,bvh,brute"})), UsageError);
  EXPECT_THROW(parse(with({"--accel", "bvh", "--warmup", "-1"})), UsageError);
  EXPECT_THROW(parse(with({"--accel", "bvh", "--max-distance", "0"})), UsageError);
  EXPECT_THROW(parse(with({})), UsageError);
  // Line order needs AO rays along lines.
  EXPECT_THROW(parse(with({"--accel", "bvh", "--ray-order", "line"})), UsageError);
  EXPECT_THROW(parse(with({"--accel", "bvh", "--ray-order", "diagonal"})), UsageError);
  EXPECT_THROW(parse(with({"--accel", "bvh:call=2"})), UsageError);
  EXPECT_THROW(parse(with({"--accel", "kdtree:call=16"})), UsageError);
  EXPECT_TRUE(parse(with({"--accel", "bvh:call=1,leaf=4,kdtree:call=batch"})));
  if (kHaveEmbree) {
    EXPECT_THROW(parse(with({"--accel", "embree:call=8"})), UsageError);
    EXPECT_THROW(parse(with({"--accel", "embree:quality=low"})), UsageError);
  }
  if (kHaveEmbree) {
    EXPECT_TRUE(parse(with({"--accel", "embree,bvh"})));
  } else {
    EXPECT_THROW(parse(with({"--accel", "embree"})), UsageError);
  }
}

TEST(BenchOptions, RayMemoryBeyondThisMachineIsRefused) {
  EXPECT_NO_THROW(check_ray_memory(1000, 3));
  EXPECT_THROW(check_ray_memory(std::size_t{1} << 40, 3), Error);
}

// A camera "image" whose rays are numbered by pixel in org.x, one ray per pixel.
std::vector<Ray> numbered_rays(const Camera& camera) {
  std::vector<Ray> rays(static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height));
  for (std::size_t i = 0; i < rays.size(); ++i) rays[i].org.x = static_cast<float>(i);
  return rays;
}

TEST(BenchRays, TakeEvenlySpreadsThePickOverTheWholeSet) {
  Camera camera;
  camera.width = 10;
  camera.height = 10;
  const std::vector<Ray> all = numbered_rays(camera);
  const std::vector<Ray> half = take_evenly(all, 50);
  ASSERT_EQ(half.size(), 50u);
  for (std::size_t i = 0; i < half.size(); ++i) EXPECT_EQ(half[i].org.x, static_cast<float>(2 * i));
  const std::vector<Ray> same = take_evenly(all, all.size());
  for (std::size_t i = 0; i < all.size(); ++i) EXPECT_EQ(same[i].org.x, all[i].org.x);
}

TEST(BenchRays, CountScalesTheImageUpUntilThereAreEnoughRays) {
  Camera camera;
  camera.width = 8;
  camera.height = 6;
  int largest_width = 0;
  const auto generate = [&](const Camera& c) {
    EXPECT_NEAR(static_cast<double>(c.width) / c.height, 8.0 / 6.0, 0.1);  // Resized, same aspect.
    largest_width = std::max(largest_width, c.width);
    return numbered_rays(c);
  };
  EXPECT_EQ(rays_for_count(camera, std::nullopt, generate).size(), 48u);
  EXPECT_EQ(rays_for_count(camera, 20, generate).size(), 20u);
  const std::vector<Ray> many = rays_for_count(camera, 1001, generate);
  EXPECT_EQ(many.size(), 1001u);
  EXPECT_GT(largest_width, 8);
  // Deterministic: the same request gives the same rays.
  const std::vector<Ray> again = rays_for_count(camera, 1001, generate);
  for (std::size_t i = 0; i < many.size(); ++i) ASSERT_EQ(many[i].org.x, again[i].org.x);
}

TEST(BenchRays, CountScalesAnImageWithFarTooManyRaysDown) {
  Camera camera;
  camera.width = 64;
  camera.height = 48;
  std::vector<int> widths;
  // Ten rays per pixel: 100 rays need about ten pixels, not 3072.
  const auto generate = [&](const Camera& c) {
    widths.push_back(c.width);
    std::vector<Ray> rays;
    for (const Ray& r : numbered_rays(c)) rays.insert(rays.end(), 10, r);
    return rays;
  };
  EXPECT_EQ(rays_for_count(camera, 100, generate, 10).size(), 100u);
  ASSERT_FALSE(widths.empty());
  EXPECT_LE(widths.front(), 8);
  EXPECT_LE(widths.back(), 8);
}

TEST(BenchRays, AnImageWithoutRaysIsAnError) {
  Camera camera;
  EXPECT_THROW(rays_for_count(camera, 10, [](const Camera&) { return std::vector<Ray>{}; }), Error);
}

TEST(BenchTiming, RunsWarmupPlusRepetitionsAndTimesOnlyTheRepetitions) {
  int calls = 0;
  // Each call sleeps 5 ms: every timed run measures at least that.
  const Timings timings = time_runs({2, 3}, [&] {
    ++calls;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  });
  EXPECT_EQ(calls, 5);
  EXPECT_EQ(timings.run_ms.size(), 3u);
  for (double ms : timings.run_ms) EXPECT_GE(ms, 5.0);
  EXPECT_GE(timings.median_ms(), 5.0);
}

TEST(BenchTiming, InterleavesTheRepetitionsOfSeveralJobs) {
  std::string order;
  const std::vector<std::function<void()>> jobs{[&] { order += 'a'; }, [&] { order += 'b'; }};
  const std::vector<Timings> timings = time_interleaved({2, 3}, jobs);
  EXPECT_EQ(order, "aabbababab");
  ASSERT_EQ(timings.size(), 2u);
  EXPECT_EQ(timings[0].run_ms.size(), 3u);
  EXPECT_EQ(timings[1].run_ms.size(), 3u);
}

Hit hit_at(float t) { return Hit::triangle(t, 0.0f, 0.0f, 1, 0, Vec3f{0, 0, 1}); }

TEST(BenchAgreement, ClosestHitsAgreeOnStatusAndOnTWithinTolerance) {
  EXPECT_TRUE(same_closest_hit(Hit{}, Hit{}));
  EXPECT_FALSE(same_closest_hit(hit_at(1.0f), Hit{}));
  EXPECT_FALSE(same_closest_hit(Hit{}, hit_at(1.0f)));
  EXPECT_TRUE(same_closest_hit(hit_at(100.0f), hit_at(100.0f * (1.0f + 0.5e-5f))));
  EXPECT_FALSE(same_closest_hit(hit_at(100.0f), hit_at(100.0f * (1.0f + 3e-5f))));
  // Near t = 0 the absolute tolerance applies.
  EXPECT_TRUE(same_closest_hit(hit_at(1e-8f), hit_at(5e-7f)));
  EXPECT_FALSE(same_closest_hit(hit_at(1e-8f), hit_at(5e-6f)));
  // A different triangle at the same t (shared edge) is not a mismatch.
  Hit other = hit_at(2.0f);
  other.prim = 7;
  EXPECT_TRUE(same_closest_hit(hit_at(2.0f), other));
}

TEST(BenchAgreement, CountsMismatchingRays) {
  const std::vector<Hit> a{hit_at(1.0f), Hit{}, hit_at(3.0f), hit_at(4.0f)};
  const std::vector<Hit> b{hit_at(1.0f), hit_at(2.0f), hit_at(3.5f), hit_at(4.0f)};
  EXPECT_EQ(count_hit_mismatches(a, b), 2u);
  const std::vector<std::uint8_t> x{0, 1, 1, 0, 1}, y{0, 1, 0, 1, 1};
  EXPECT_EQ(count_occlusion_mismatches(x, y), 2u);
  QueryResults p, q;
  p.occluded = x;
  q.occluded = y;
  p.hits = a;
  q.hits = a;
  EXPECT_EQ(count_mismatches(p, q, RayKind::shadow), 2u);
  EXPECT_EQ(count_mismatches(p, q, RayKind::random), 0u);
}

BenchReport sample_report(bool with_embree) {
  BenchReport report;
  report.scene = "bunny";
  report.triangles = 69451;
  report.kind = RayKind::ao;
  report.rays = 1000000;
  report.threads = 2;
  report.reference = with_embree ? "embree" : "bvh";
  if (with_embree) report.embree = "Embree 3.13.5";
  const auto ratio = [&](double r) { return with_embree ? std::optional<double>(r) : std::nullopt; };
  report.rows.push_back({"bvh", 12.5, 4096, 100.0, 10.0, ratio(0.5), 3, {}, {}, BvhWork{6.5, 1.75, 2.0, 13.25}, ratio(0.5), false});
  if (with_embree) report.rows.push_back({"embree", 8.0, 8192, 50.0, 20.0, 1.0, 0, {}, {}, {}, 1.0, true});
  report.rows.push_back({"beam", 900.0, 1 << 20, 25.0, 40.0, ratio(2.0), 0, std::nullopt, BeamWork{0.75, 1.5, 2.25, 4.5}, {}, ratio(2.0), false});
  return report;
}

TEST(BenchReport, JsonHasTheDocumentedFields) {
  const nlohmann::ordered_json doc = report_json(sample_report(true));
  EXPECT_EQ(doc.at("scene"), "bunny");
  EXPECT_EQ(doc.at("triangles"), 69451);
  EXPECT_EQ(doc.at("rays"), 1000000);
  EXPECT_EQ(doc.at("kind"), "ao");
  EXPECT_EQ(doc.at("threads"), 2);
  ASSERT_EQ(doc.at("results").size(), 3u);
  const nlohmann::ordered_json& bvh = doc.at("results")[0];
  EXPECT_EQ(bvh.at("accel"), "bvh");
  EXPECT_DOUBLE_EQ(bvh.at("build_ms").get<double>(), 12.5);
  EXPECT_EQ(bvh.at("bytes"), 4096);
  EXPECT_DOUBLE_EQ(bvh.at("mrays_per_s").get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(bvh.at("ratio_to_embree").get<double>(), 0.5);
  EXPECT_EQ(bvh.at("mismatches"), 3);
  EXPECT_FALSE(bvh.contains("beam_work"));
  const nlohmann::ordered_json& bvh_work = bvh.at("bvh_work");
  EXPECT_DOUBLE_EQ(bvh_work.at("nodes").get<double>(), 6.5);
  EXPECT_DOUBLE_EQ(bvh_work.at("leaves").get<double>(), 1.75);
  EXPECT_DOUBLE_EQ(bvh_work.at("blocks").get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(bvh_work.at("triangle_tests").get<double>(), 13.25);
  EXPECT_FALSE(doc.at("results")[2].contains("bvh_work"));
  const nlohmann::ordered_json& work = doc.at("results")[2].at("beam_work");
  EXPECT_DOUBLE_EQ(work.at("single_tile_fraction").get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(work.at("tiles").get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(work.at("leaves").get<double>(), 2.25);
  EXPECT_DOUBLE_EQ(work.at("triangle_tests").get<double>(), 4.5);
  EXPECT_TRUE(report_json(sample_report(false)).at("results")[0].at("ratio_to_embree").is_null());
}

TEST(BenchReport, TableHasOneRowPerStructure) {
  std::ostringstream out;
  print_table(out, sample_report(true));
  const std::string text = out.str();
  EXPECT_NE(text.find("69,451 triangles"), std::string::npos) << text;
  EXPECT_NE(text.find("0.50x"), std::string::npos) << text;
  EXPECT_NE(text.find("\nembree "), std::string::npos) << text;
  EXPECT_NE(text.find("mismatches vs embree"), std::string::npos) << text;
  EXPECT_NE(text.find("beam work per ray: 75.0% single-tile, 1.50 tiles, 2.25 leaves, 4.50 triangle tests"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("bvh work per ray: 6.50 nodes, 1.75 leaves, 2.00 blocks, 13.25 triangle tests"), std::string::npos) << text;
  EXPECT_EQ(text.find("embree work per ray"), std::string::npos) << text;
}

TEST(BenchReport, MraysPerSecond) {
  EXPECT_DOUBLE_EQ(mrays_per_second(2'000'000, 1000.0), 2.0);
  EXPECT_DOUBLE_EQ(mrays_per_second(10, 0.0), 0.0);
}

#if VISFIELD_HAVE_EMBREE
// Embree through the adapter answers like the brute-force oracle and maps hits back to (prim, instance).
TEST(BenchEmbreeScene, AgreesWithBruteForceOnRandomRays) {
  BuiltinParams params;
  params.size = 3000;
  params.seed = 5;
  const TriangleSet set = flatten(make_builtin_scene("soup", params));
  const EmbreeScene embree = EmbreeScene::build(set, 2);
  const BruteForce brute = BruteForce::build(set);
  EXPECT_GT(embree.stats().memory_bytes, set.size() * 9 * sizeof(float));
  EXPECT_EQ(EmbreeScene::name(), "embree");

  Rng rng(11);
  const Vec3f lo = set.bounds.lo, extent = set.bounds.extent();
  int hits = 0, status_mismatches = 0, t_mismatches = 0, id_mismatches = 0, occlusion_mismatches = 0;
  for (int i = 0; i < 4000; ++i) {
    Ray ray;
    ray.org = lo + Vec3f{rng.uniform(), rng.uniform(), rng.uniform()} * extent;
    ray.dir = uniform_sphere(rng.uniform(), rng.uniform());
    ray.tmin = 1e-4f;
    ray.tmax = i % 3 == 0 ? 0.05f * length(extent) : std::numeric_limits<float>::infinity();
    const Hit expected = brute.intersect(ray);
    const Hit got = embree.intersect(ray);
    if (expected.found != got.found) {
      ++status_mismatches;
    } else if (expected) {
      ++hits;
      if (!same_closest_hit(expected, got)) ++t_mismatches;
      if (expected.prim != got.prim || expected.instance != got.instance) ++id_mismatches;
      EXPECT_GE(got.u, 0.0f);
      EXPECT_GE(got.v, 0.0f);
      EXPECT_LE(got.u + got.v, 1.0f + 1e-5f);
    }
    if (embree.occluded(ray) != brute.occluded(ray)) ++occlusion_mismatches;
  }
  EXPECT_GT(hits, 1000);
  // Random rays essentially never graze an edge; Embree's test and ours then agree exactly.
  EXPECT_EQ(status_mismatches, 0);
  EXPECT_EQ(t_mismatches, 0);
  EXPECT_EQ(id_mismatches, 0);
  EXPECT_EQ(occlusion_mismatches, 0);
}

// Embree's packets (rtcIntersect16, rtcOccluded16) and streams (rtcIntersect1M, rtcOccluded1M), with
// the rays copied in by vector stores and flush-to-zero on, answer as its single rays, at both build
// qualities, on random rays and rays along one direction (what packets suit), batches of any length;
// and the callers' floating-point mode is what it was.
TEST(BenchEmbreeScene, PacketsAndStreamsAnswerAsSingleRays) {
  const TriangleSet set = flatten(make_builtin_scene("soup", {.seed = 3, .size = 2000}));
  Rng rng(5);
  std::vector<Ray> rays;
  const Vec3f lo = set.bounds.lo, extent = set.bounds.extent(), along = normalize(Vec3f{0.3f, -1.0f, 0.2f});
  for (int i = 0; i < 5003; ++i)
    rays.push_back(Ray{lo + Vec3f{rng.uniform(), rng.uniform(), rng.uniform()} * extent,
                       i % 2 ? along : uniform_sphere(rng.uniform(), rng.uniform()), i % 5 ? 0.0f : 0.01f,
                       i % 3 ? std::numeric_limits<float>::infinity() : 0.1f * length(extent)});
  const EmbreeScene reference = EmbreeScene::build(set, 2);
  std::vector<std::uint8_t> single(rays.size());
  std::vector<Hit> single_hits(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    single[i] = reference.occluded(rays[i]) ? 1 : 0;
    single_hits[i] = reference.intersect(rays[i]);
  }
  std::size_t blocked = 0;
  for (const std::uint8_t b : single) blocked += b;
  EXPECT_GT(blocked, rays.size() / 10);
  EXPECT_LT(blocked, rays.size() - rays.size() / 10);
  const unsigned mode = _mm_getcsr();
  for (const bool high : {false, true}) {
    const EmbreeScene built = EmbreeScene::build(set, 2, {EmbreeCall::one, high});
    for (const EmbreeCall call : {EmbreeCall::one, EmbreeCall::packet16, EmbreeCall::stream}) {
      const EmbreeScene embree = built.with_call(call);
      EXPECT_EQ(embree.settings().call, call);
      EXPECT_EQ(embree.settings().high_quality, high);
      std::vector<std::uint8_t> occluded(rays.size());
      std::vector<Hit> hits(rays.size());
      occluded_batch(embree, std::span<const Ray>(rays), std::span<std::uint8_t>(occluded));
      intersect_batch(embree, std::span<const Ray>(rays), std::span<Hit>(hits));
      EXPECT_EQ(occluded, single) << embree_call_name(call) << ", high quality " << high;
      std::size_t differ = 0;
      for (std::size_t i = 0; i < rays.size(); ++i)
        differ += hits[i].found != single_hits[i].found || hits[i].t != single_hits[i].t || hits[i].prim != single_hits[i].prim;
      EXPECT_EQ(differ, 0u) << embree_call_name(call) << ", high quality " << high;
      EXPECT_EQ(_mm_getcsr(), mode) << "the caller's floating-point mode changed";
    }
  }
}

// Embree's instancing and our instance layer agree on rotated, scaled copies of a mesh: the same
// object hit at the same distance.
TEST(BenchEmbreeScene, InstancingMapsHitsToObjectsAndTriangles) {
  Scene scene = make_builtin_scene("sphere", {.size = 400});
  std::vector<ObjectId> ids;
  for (int i = 0; i < 6; ++i) {
    Transform t;
    t.rotation = Mat3::rotation({1, 0, 1}, 30.0f * static_cast<float>(i));
    t.translation = {3.0f * static_cast<float>(i), 1.0f, -2.0f};
    t.scale = 0.5f + 0.1f * static_cast<float>(i);
    ids.push_back(scene.add_instance(1, t));
  }
  const EmbreeScene embree = EmbreeScene::build_instanced(scene, 2);
  SceneGeometry geometry(scene);
  const BuiltStructure ours = build_structure("bvh:levels=2", geometry);
  const auto& layer = std::get<InstanceLayer>(ours.structure);
  Rng rng(12);
  const Bounds3f b = scene.bounds();
  int hits = 0, disagreements = 0;
  for (int i = 0; i < 4000; ++i) {
    const Ray ray{b.lo + Vec3f{rng.uniform(), rng.uniform(), rng.uniform()} * b.extent(),
                  uniform_sphere(rng.uniform(), rng.uniform())};
    const Hit expected = layer.intersect(ray), got = embree.intersect(ray);
    hits += expected ? 1 : 0;
    // The two compute t in different spaces and orders, so t is compared to the scene's size (rays
    // starting near the large ground see errors of its coordinates' magnitude).
    const bool same = expected.found == got.found &&
                      (!expected || (expected.instance == got.instance &&
                                     std::fabs(expected.t - got.t) <= 1e-5f * length(b.extent())));
    disagreements += same ? 0 : 1;
    disagreements += layer.occluded(ray) == embree.occluded(ray) ? 0 : 1;
  }
  EXPECT_GT(hits, 1000);
  EXPECT_EQ(disagreements, 0);
}

TEST(BenchEmbreeScene, EmptySetHitsNothingAndMovesSafely) {
  EmbreeScene embree = EmbreeScene::build(TriangleSet{}, 1);
  EmbreeScene moved = std::move(embree);
  Ray ray;
  ray.dir = {0.0f, 0.0f, 1.0f};
  EXPECT_FALSE(moved.intersect(ray));
  EXPECT_FALSE(moved.occluded(ray));
}

// The ISA is the one Embree's own verbose report says it runs: one of its targets, never "unknown".
TEST(BenchEmbreeScene, DescriptionNamesVersionIsaAndTasking) {
  const std::string text = embree_description();
  EXPECT_EQ(text.rfind("Embree 3.", 0), 0u) << text;
  bool known = false;
  for (const char* isa : {"ISA AVX512,", "ISA AVX2,", "ISA AVX,", "ISA SSE4.2,", "ISA SSE2,"}) known = known || text.find(isa) != std::string::npos;
  EXPECT_TRUE(known) << text;
  EXPECT_NE(text.find("tasking"), std::string::npos) << text;
}
#endif

}  // namespace
}  // namespace vf::bench

// The soak: the structures that take edits (the instance layer, BeamField) driven through random
// inserts, moves and removals, each round committed and then checked on a batch of rays against
// fresh builds of the edited scene, bit for bit, for as long as asked; resident memory is sampled
// every round. Exit 0 when no answer differed and, after the warm-up (the first third of the run),
// resident memory did not drift (the last tenth of its samples' mean within the tolerance of the
// first tenth's); one JSON line of counts either way.
//
// Usage: visfield_soak [--seconds S] [--seed N] [--rays R] [--rss-tolerance F] [--json FILE]

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <span>
#include <string>
#include <vector>

#include "differential/ray_sets.hpp"
#include "differential/test_scenes.hpp"
#include "differential/update_probes.hpp"
#include "support/same_hit.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/registry/scene_geometry.hpp"
#include "visfield/registry/structure_queries.hpp"

namespace {

using namespace vf;

struct Options {
  double seconds = 60.0;
  std::uint64_t seed = 1;
  std::size_t rays = 8192;
  double rss_tolerance = 0.05;
  std::string json;
};

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr, "visfield_soak: %s\nusage: visfield_soak [--seconds S] [--seed N] [--rays R] [--rss-tolerance F] [--json FILE]\n",
               why.c_str());
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i + 1 >= argc) usage("missing a value after " + arg);
    const std::string value = argv[++i];
    char* end = nullptr;
    if (arg == "--seconds") o.seconds = std::strtod(value.c_str(), &end);
    else if (arg == "--seed") o.seed = std::strtoull(value.c_str(), &end, 10);
    else if (arg == "--rays") o.rays = std::strtoull(value.c_str(), &end, 10);
    else if (arg == "--rss-tolerance") o.rss_tolerance = std::strtod(value.c_str(), &end);
    else if (arg == "--json") o.json = value, end = const_cast<char*>(value.c_str() + value.size());
    else usage("unknown option " + arg);
    if (end == nullptr || *end != '\0' || value.empty()) usage("bad value for " + arg + ": " + value);
  }
  if (!(o.seconds > 0.0) || o.rays == 0 || !(o.rss_tolerance >= 0.0)) usage("--seconds, --rays and --rss-tolerance must be positive");
  return o;
}

// Resident memory of this process in bytes (/proc/self/statm).
double resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  double pages = 0.0, resident = 0.0;
  statm >> pages >> resident;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE));
}

// A random rigid placement with a uniform scale in a box of side `spread`.
Transform random_placement(Rng& rng, float spread) {
  Transform t;
  const Vec3f axis{rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f};
  t.rotation = Mat3::rotation(length(axis) > 1e-3f ? axis : Vec3f{0, 1, 0}, 360.0f * rng.uniform());
  t.scale = std::exp2(rng.uniform() - 0.5f);
  t.translation = Vec3f{rng.uniform(), rng.uniform(), rng.uniform()} * spread;
  return t;
}

// One structure under the soak: the one edited since its build, checked against fresh builds.
struct Soaked {
  std::string spec;
  BuiltStructure edited;
  std::uint64_t mismatches = 0;
};

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  Rng rng(o.seed, 0x50a4u);
  // Three meshes (a height field, a soup of small triangles, a soup of slivers), 21 objects each to
  // start; inserts and removals keep between 56 and 72 objects, so that memory has a level to keep.
  Scene scene = test::scattered_copies({test::mesh_from_triangles(test::height_field(o.seed, 8)),
                                        test::mesh_from_triangles(test::random_soup(o.seed + 1, 120, 0.05f, 0.2f)),
                                        test::mesh_from_triangles(test::random_soup(o.seed + 2, 60, 0.01f, 0.6f))},
                                       21, 3.0f, o.seed);
  constexpr float kSpread = 3.0f;
  constexpr std::size_t kMinObjects = 56, kMaxObjects = 72;
  std::vector<Soaked> soaked;
  for (const char* spec : {"bvh:levels=2", "beam:dirs=33,n=16"}) {
    SceneGeometry geometry(scene);
    soaked.push_back(Soaked{spec, build_structure(spec, geometry), 0});
  }

  std::uint64_t edits = 0, commits = 0, rounds = 0, answers_checked = 0;
  std::vector<double> rss;  // resident bytes after each round past the warm-up
  const Stopwatch clock;
  std::vector<Hit> got, expected;
  std::vector<std::uint8_t> got_occluded, expected_occluded;
  while (clock.elapsed_s() < o.seconds) {
    // A round of 1-64 edits, the same on the scene and on every structure, then one commit.
    const int count = 1 + static_cast<int>(rng.uniform() * 64.0f);
    for (int k = 0; k < count; ++k) {
      const std::vector<Instance>& objects = scene.instances();
      const float pick = rng.uniform();
      const Instance& some = objects[static_cast<std::size_t>(rng.uniform() * static_cast<float>(objects.size())) % objects.size()];
      if ((pick < 0.35f && objects.size() < kMaxObjects) || objects.size() <= kMinObjects) {
        const auto mesh = static_cast<std::uint32_t>(rng.uniform() * 3.0f) % 3;
        const ObjectId id = scene.add_instance(mesh, random_placement(rng, kSpread));
        for (Soaked& s : soaked) insert_object(s.edited.structure, scene, id);
      } else if (pick < 0.7f) {
        const ObjectId id = some.id;
        scene.remove_instance(id);
        for (Soaked& s : soaked) remove_object(s.edited.structure, id);
      } else {
        const Transform t = random_placement(rng, kSpread);
        const ObjectId id = some.id;
        scene.set_transform(id, t);
        for (Soaked& s : soaked) move_object(s.edited.structure, id, t);
      }
      ++edits;
    }
    for (Soaked& s : soaked) commit_objects(s.edited.structure);
    ++commits;

    // Rays around the scene and from its surfaces, through the edited structures and fresh builds.
    const TriangleSet world = flatten(scene);
    const std::vector<Ray> rays = test::probe_rays(world, o.seed + rounds, o.rays / 2);
    got.resize(rays.size()), expected.resize(rays.size());
    got_occluded.resize(rays.size()), expected_occluded.resize(rays.size());
    for (Soaked& s : soaked) {
      SceneGeometry geometry(scene);
      const BuiltStructure fresh = build_structure(s.spec, geometry);
      intersect_batch(s.edited.structure, rays, got);
      intersect_batch(fresh.structure, rays, expected);
      occluded_batch(s.edited.structure, rays, got_occluded);
      occluded_batch(fresh.structure, rays, expected_occluded);
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const bool same = test::same_bits(got[i], expected[i]) && got_occluded[i] == expected_occluded[i];
        if (!same && s.mismatches++ < 5)
          std::fprintf(stderr, "visfield_soak: %s, round %llu, ray %zu: the edited structure's answer differs from a fresh build's\n",
                       s.spec.c_str(), static_cast<unsigned long long>(rounds), i);
      }
      answers_checked += 2 * rays.size();  // closest hit and occlusion
    }
    ++rounds;

    if (clock.elapsed_s() >= o.seconds / 3.0) rss.push_back(resident_bytes());  // after the warm-up
  }

  std::uint64_t mismatches = 0;
  for (const Soaked& s : soaked) mismatches += s.mismatches;
  // Flat: the mean of the last tenth of the samples within the tolerance of the first tenth's (the
  // scene's size moves between 56 and 72 objects, so single samples move too; a leak moves the mean).
  const std::size_t tenth = std::max<std::size_t>(1, rss.size() / 10);
  const auto mean = [&](std::size_t first) {
    double sum = 0.0;
    for (std::size_t i = first; i < first + tenth; ++i) sum += rss[i];
    return sum / static_cast<double>(tenth);
  };
  const double rss_start = rss.empty() ? 0.0 : mean(0), rss_end = rss.empty() ? 0.0 : mean(rss.size() - tenth);
  const double rss_low = rss.empty() ? 0.0 : *std::min_element(rss.begin(), rss.end());
  const double rss_high = rss.empty() ? 0.0 : *std::max_element(rss.begin(), rss.end());
  const double drift = rss_start > 0.0 ? rss_end / rss_start - 1.0 : 0.0;
  const bool memory_flat = rss.size() >= 2 && std::abs(drift) <= o.rss_tolerance;
  char line[768];
  std::snprintf(line, sizeof line,
                "{\"seconds\": %.1f, \"seed\": %llu, \"structures\": [\"%s\", \"%s\"], \"edits\": %llu, \"commits\": %llu, \"rounds\": %llu, "
                "\"rays_per_round\": %zu, \"answers_checked\": %llu, \"mismatches\": %llu, \"objects_now\": %zu, "
                "\"rss_samples\": %zu, \"rss_first_tenth_mean_bytes\": %.0f, \"rss_last_tenth_mean_bytes\": %.0f, \"rss_drift\": %.4f, "
                "\"rss_low_bytes\": %.0f, \"rss_high_bytes\": %.0f, \"rss_tolerance\": %.3f, \"memory_flat\": %s}",
                clock.elapsed_s(), static_cast<unsigned long long>(o.seed), soaked[0].spec.c_str(), soaked[1].spec.c_str(),
                static_cast<unsigned long long>(edits), static_cast<unsigned long long>(commits), static_cast<unsigned long long>(rounds),
                2 * (o.rays / 2), static_cast<unsigned long long>(answers_checked), static_cast<unsigned long long>(mismatches),
                scene.instances().size(), rss.size(), rss_start, rss_end, drift, rss_low, rss_high, o.rss_tolerance,
                memory_flat ? "true" : "false");
  std::printf("%s\n", line);
  if (!o.json.empty()) std::ofstream(o.json) << line << "\n";
  if (mismatches > 0) std::fprintf(stderr, "visfield_soak: %llu answers differed from fresh builds\n", static_cast<unsigned long long>(mismatches));
  if (!memory_flat)
    std::fprintf(stderr, "visfield_soak: resident memory drifted %.1f%% after the warm-up (%.0f to %.0f bytes), more than %.0f%%\n",
                 100.0 * drift, rss_start, rss_end, 100.0 * o.rss_tolerance);
  return mismatches == 0 && memory_flat ? 0 : 1;
}

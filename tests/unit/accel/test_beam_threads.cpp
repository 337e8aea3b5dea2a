// BeamField's parallel parts (the build over directions, commit's per-direction updates and the
// line-grouped batch queries) give the same field and bit-identical answers with 1 and 2 threads.
// In test_accel so that the ThreadSanitizer step of .ci/run (which builds it) runs it.

#include <gtest/gtest.h>

#include <cstdint>
#include <utility>
#include <vector>

#include "differential/test_scenes.hpp"
#include "differential/update_probes.hpp"
#include "support/same_hit.hpp"
#include "visfield/accel/beam_field.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/rng.hpp"

namespace vf::test {
namespace {

TEST(BeamThreads, BuildUpdatesAndBatchQueriesDoNotDependOnTheThreadCount) {
  const auto run = [](int threads, AccelStats& stats) {
    const ThreadLimit limit(threads);
    Scene scene = scattered_copies({mesh_from_triangles(height_field(2, 10)), mesh_from_triangles(random_soup(4, 200, 0.05f, 0.2f))},
                                   8, 2.0f, 21);
    BeamField field = BeamField::build(scene, {.level = 2, .resolution = 16, .max_depth = 3, .leaf_size = 4});
    Rng rng(5, 0x7a);
    const float extent = max_component(scene.bounds().extent());
    for (const Instance& object : std::vector<Instance>(scene.instances())) {
      Transform t = object.transform;
      t.translation += Vec3f{rng.uniform(), rng.uniform(), rng.uniform()} * (0.02f * extent);
      scene.set_transform(object.id, t);
      field.move(object.id, t);
    }
    field.commit();
    stats = field.stats();
    const std::vector<Ray> rays = probe_rays(flatten(scene), 77, 500);
    std::vector<Hit> hits(rays.size());
    std::vector<std::uint8_t> occluded(rays.size());
    intersect_batch(field, rays, hits);
    occluded_batch(field, rays, occluded);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      EXPECT_TRUE(same_bits(hits[i], field.intersect(rays[i]))) << "ray " << i;
      EXPECT_EQ(occluded[i] != 0, field.occluded(rays[i])) << "ray " << i;
    }
    return std::pair{hits, occluded};
  };
  AccelStats one{}, two{};
  const auto [hits_one, occluded_one] = run(1, one);
  const auto [hits_two, occluded_two] = run(2, two);
  EXPECT_EQ(one.node_count, two.node_count);
  EXPECT_EQ(one.leaf_count, two.leaf_count);
  EXPECT_EQ(one.reference_count, two.reference_count);
  ASSERT_EQ(hits_one.size(), hits_two.size());
  for (std::size_t i = 0; i < hits_one.size(); ++i) ASSERT_TRUE(same_bits(hits_one[i], hits_two[i])) << "ray " << i;
  EXPECT_EQ(occluded_one, occluded_two);
}

}  // namespace
}  // namespace vf::test

// The update lifecycle of the instance layer: after removing, inserting and moving objects and a
// commit, every answer equals a fresh build's over the edited scene; before the commit, the old one's.

#include <gtest/gtest.h>

#include "differential/harness.hpp"
#include "differential/ray_sets.hpp"
#include "differential/structure_specs.hpp"
#include "differential/test_scenes.hpp"
#include "differential/update_probes.hpp"
#include "visfield/core/error.hpp"

namespace vf::test {
namespace {

static_assert(UpdatableStructure<InstanceLayer>);
static_assert(!UpdatableStructure<Bvh> && !UpdatableStructure<KdTree> && !UpdatableStructure<UniformGrid>);

InstanceLayer build_layer(const std::string& spec, const Scene& scene) {
  SceneGeometry geometry(scene);
  BuiltStructure built = build_structure(spec, geometry);
  return std::move(std::get<InstanceLayer>(built.structure));
}

/// Rays of both scenes' kinds: random ones around `set` and AO-like ones from its surfaces.
std::vector<Ray> probe_rays(const TriangleSet& set) { return test::probe_rays(set, 3, 3000); }

class InstanceUpdates : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    scene_ = scattered_copies({mesh_from_triangles(height_field(2, 10)), mesh_from_triangles(random_soup(4, 200, 0.05f, 0.2f))},
                              10, 2.0f, 21);
  }
  // Removes three objects, moves four, adds three (one of a mesh no object used before), on both the
  // scene and `layer`.
  void edit(InstanceLayer& layer) {
    const std::vector<Instance> objects = scene_.instances();
    for (std::size_t i : {1u, 7u, 15u}) {
      scene_.remove_instance(objects[i].id);
      layer.remove(objects[i].id);
    }
    for (std::size_t i : {0u, 4u, 12u, 19u}) {
      Transform t = objects[i].transform;
      t.translation += Vec3f{0.3f, -0.2f, 0.1f};
      t.rotation = Mat3::rotation({1, 1, 0}, 33.0f) * t.rotation;
      t.scale *= 1.25f;
      scene_.set_transform(objects[i].id, t);
      layer.move(objects[i].id, t);
    }
    scene_.meshes.push_back(mesh_from_triangles(coplanar_soup(5, 50, {0, 0, 0}, {1, 0, 0}, {0, 1, 0})));
    Transform placed;
    placed.translation = {0.5f, 0.5f, 0.5f};
    for (std::uint32_t mesh : {0u, 1u, 2u}) {
      placed.translation.x += 0.4f;
      const ObjectId id = scene_.add_instance(mesh, placed);
      layer.insert(scene_, id);
    }
  }
  Scene scene_;
};

TEST_P(InstanceUpdates, EditsThenCommitAnswerAsAFreshBuild) {
  InstanceLayer layer = build_layer(GetParam(), scene_);
  edit(layer);
  EXPECT_TRUE(layer.has_staged_edits());
  layer.commit();
  EXPECT_FALSE(layer.has_staged_edits());
  EXPECT_EQ(layer.object_count(), scene_.instances().size());
  const InstanceLayer fresh = build_layer(GetParam(), scene_);
  const std::vector<Ray> rays = probe_rays(flatten(scene_));
  EXPECT_EQ(differences(layer, fresh, rays), 0u);
  // And both are exact.
  const OracleAnswers answers = oracle_answers(InstancedOracle(scene_), rays, false);
  const DiffReport r = compare_answers(layer, GetParam() + " after edits", rays, answers, {.label = "edited scene"});
  EXPECT_GT(r.oracle_hits, rays.size() / 10);
  EXPECT_EQ(r.closest_mismatches, 0u);
  EXPECT_EQ(r.occluded_mismatches, 0u);
  EXPECT_EQ(layer.stats().memory_bytes, fresh.stats().memory_bytes);
}

TEST_P(InstanceUpdates, StagedEditsAreInvisibleUntilCommit) {
  const Scene before = scene_;
  InstanceLayer layer = build_layer(GetParam(), scene_);
  const InstanceLayer original = build_layer(GetParam(), before);
  edit(layer);
  const std::vector<Ray> rays = probe_rays(flatten(before));
  EXPECT_EQ(differences(layer, original, rays), 0u);
  layer.commit();
  EXPECT_GT(differences(layer, original, rays), rays.size() / 100);  // the edits changed answers
}

TEST_P(InstanceUpdates, BadEditsAreRefusedAndChangeNothing) {
  InstanceLayer layer = build_layer(GetParam(), scene_);
  const ObjectId present = scene_.instances()[3].id;
  EXPECT_THROW(layer.remove(9999), Error);
  EXPECT_THROW(layer.insert(scene_, present), Error);  // already in the structure
  EXPECT_THROW(layer.insert(scene_, 9999), Error);     // not in the scene
  EXPECT_THROW(layer.move(9999, Transform{}), Error);
  Transform flat;
  flat.scale = 0.0f;
  EXPECT_THROW(layer.move(present, flat), Error);
  EXPECT_FALSE(layer.has_staged_edits());
  layer.remove(present);
  EXPECT_THROW(layer.remove(present), Error);  // removed twice
}

TEST_P(InstanceUpdates, RemovingEveryObjectLeavesAnEmptyStructure) {
  InstanceLayer layer = build_layer(GetParam(), scene_);
  for (const Instance& o : scene_.instances()) layer.remove(o.id);
  layer.commit();
  EXPECT_EQ(layer.object_count(), 0u);
  for (const Ray& ray : probe_rays(flatten(scene_))) {
    EXPECT_FALSE(layer.intersect(ray));
    EXPECT_FALSE(layer.occluded(ray));
  }
}

INSTANTIATE_TEST_SUITE_P(Registry, InstanceUpdates, ::testing::ValuesIn(two_level_specs()),
                         [](const auto& info) { return spec_test_name(info.param); });

}  // namespace
}  // namespace vf::test

// BeamField's dynamic objects (VLF-RT §8): after any sequence of removes, inserts and moves and a
// commit, every answer equals a fresh build's over the edited scene and brute force's; staged edits
// stay invisible until the commit; bad edits are refused.

#include <gtest/gtest.h>

#include <string>

#include "differential/harness.hpp"
#include "differential/ray_sets.hpp"
#include "differential/test_scenes.hpp"
#include "differential/update_probes.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/rng.hpp"

namespace vf::test {
namespace {

static_assert(UpdatableStructure<BeamField>);

// Small fields keep the test fast; the update path does not depend on the sizes.
const BeamFieldConfig kConfig{.level = 3, .resolution = 32, .max_depth = 3, .leaf_size = 4};

std::vector<Ray> probe_rays(const TriangleSet& set, std::uint64_t seed) { return test::probe_rays(set, seed, 1500); }

Scene make_scene() {
  return scattered_copies({mesh_from_triangles(height_field(2, 10)), mesh_from_triangles(random_soup(4, 200, 0.05f, 0.2f))}, 10,
                          2.0f, 21);
}

/// A random rigid placement inside the scene's box (so that most moves stay in the field's sphere).
Transform random_placement(Rng& rng, float extent) {
  Transform t;
  const Vec3f axis{rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f};
  t.rotation = Mat3::rotation(length(axis) > 1e-3f ? axis : Vec3f{0, 0, 1}, 360.0f * rng.uniform());
  t.scale = 0.5f + rng.uniform();
  t.translation = Vec3f{rng.uniform(), rng.uniform(), rng.uniform()} * (0.8f * extent);
  return t;
}

// Probe rays through the edited `field` answer as a fresh build over `scene` and as brute force;
// the field holds the scene's triangles. Returns the fresh build.
BeamField expect_fresh_and_oracle_answers(const BeamField& field, const Scene& scene, std::uint64_t seed) {
  const TriangleSet set = flatten(scene);
  const std::vector<Ray> rays = probe_rays(set, seed);
  BeamField fresh = BeamField::build(scene, set, kConfig);
  EXPECT_EQ(differences(field, fresh, rays), 0u);
  const OracleAnswers answers = oracle_answers(BruteForce::build(set), rays, false);
  const DiffReport r = compare_answers(field, "beam after edits", rays, answers, {.label = "edited scene"});
  EXPECT_GT(r.oracle_hits, rays.size() / 20);
  EXPECT_EQ(r.closest_mismatches, 0u);
  EXPECT_EQ(r.occluded_mismatches, 0u);
  EXPECT_EQ(field.beam_stats().triangles, set.size());
  return fresh;
}

TEST(BeamUpdates, RandomEditSequencesAnswerAsAFreshBuildAndAsBruteForce) {
  Scene scene = make_scene();
  const float extent = max_component(scene.bounds().extent());
  BeamField field = BeamField::build(scene, kConfig);
  Rng rng(7, 0xbea);
  bool some_rebuilt = false, some_in_place = false;
  for (int round = 0; round < 24; ++round) {
    // One to three edits per round: mostly moves, some removes and inserts.
    const int edits = 1 + static_cast<int>(rng.next_u32() % 3);
    for (int e = 0; e < edits; ++e) {
      const std::vector<Instance>& objects = scene.instances();
      const float pick = rng.uniform();
      if (pick < 0.7f && !objects.empty()) {
        const ObjectId id = objects[rng.next_u32() % objects.size()].id;
        const Transform t = random_placement(rng, extent);
        scene.set_transform(id, t);
        field.move(id, t);
      } else if (pick < 0.85f && objects.size() > 2) {
        const ObjectId id = objects[rng.next_u32() % objects.size()].id;
        scene.remove_instance(id);
        field.remove(id);
      } else {
        const ObjectId id = scene.add_instance(rng.next_u32() % 2, random_placement(rng, extent));
        field.insert(scene, id);
      }
    }
    field.commit();
    some_rebuilt = some_rebuilt || field.beam_stats().last_commit_rebuilt;
    some_in_place = some_in_place || !field.beam_stats().last_commit_rebuilt;
    if (round % 6 != 5) continue;
    SCOPED_TRACE("round " + std::to_string(round));
    expect_fresh_and_oracle_answers(field, scene, 100 + static_cast<std::uint64_t>(round));
  }
  EXPECT_TRUE(some_in_place);  // the sequence exercised the per-tile update, not only rebuilds
}

// An animation: objects drift a little each frame (the tiles' leaf planes are mostly kept
// and only the edited references change); every few frames the field still answers as a fresh
// build and as brute force, and its references match a fresh build's within the end-leaf slack.
TEST(BeamUpdates, SmallMovesFrameAfterFrameStayExact) {
  Scene scene = make_scene();
  const float extent = max_component(scene.bounds().extent());
  BeamField field = BeamField::build(scene, kConfig);
  Rng rng(11, 0xd1f7);
  for (int frame = 0; frame < 30; ++frame) {
    const std::vector<Instance> objects = scene.instances();
    for (std::size_t i = 0; i < objects.size(); ++i) {
      if ((i + static_cast<std::size_t>(frame)) % 5 != 2) continue;  // 2 of the 10: under a third of the triangles, in place
      const Instance& object = objects[i];
      Transform t = object.transform;
      t.translation += Vec3f{rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f} * (0.01f * extent);
      scene.set_transform(object.id, t);
      field.move(object.id, t);
    }
    field.commit();
    ASSERT_FALSE(field.beam_stats().last_commit_rebuilt) << "frame " << frame;
    if (frame % 10 != 9) continue;
    SCOPED_TRACE("frame " + std::to_string(frame));
    const BeamField fresh = expect_fresh_and_oracle_answers(field, scene, 300 + static_cast<std::uint64_t>(frame));
    // Kept leaves may hold a straddler in one more leaf than a fresh build would: a few percent.
    const double refs = static_cast<double>(field.stats().reference_count), fresh_refs = static_cast<double>(fresh.stats().reference_count);
    EXPECT_LT(refs, 1.1 * fresh_refs);
    EXPECT_GT(refs, 0.9 * fresh_refs);
  }
}

TEST(BeamUpdates, AnObjectLeavingTheSphereRebuildsAndStaysExact) {
  Scene scene = make_scene();
  BeamField field = BeamField::build(scene, kConfig);
  const ObjectId id = scene.instances()[2].id;
  Transform far = scene.instances()[2].transform;
  far.translation += Vec3f{50.0f, 0.0f, 0.0f};
  scene.set_transform(id, far);
  field.move(id, far);
  field.commit();
  EXPECT_TRUE(field.beam_stats().last_commit_rebuilt);
  const TriangleSet set = flatten(scene);
  const std::vector<Ray> rays = probe_rays(set, 9);
  EXPECT_EQ(differences(field, BeamField::build(scene, set, kConfig), rays), 0u);
}

TEST(BeamUpdates, AMoveInsideTheSphereUpdatesInPlace) {
  Scene scene = make_scene();
  BeamField field = BeamField::build(scene, kConfig);
  const ObjectId id = scene.instances()[5].id;
  Transform t = scene.instances()[5].transform;
  t.translation += Vec3f{0.05f, 0.02f, -0.03f};
  scene.set_transform(id, t);
  field.move(id, t);
  field.commit();
  EXPECT_FALSE(field.beam_stats().last_commit_rebuilt);
  const TriangleSet set = flatten(scene);
  EXPECT_EQ(differences(field, BeamField::build(scene, set, kConfig), probe_rays(set, 10)), 0u);
}

// Moving most of the scene costs more in place than a build (three builds' worth per triangle
// edited), so commit() rebuilds; the answers are a fresh build's either way.
TEST(BeamUpdates, MovingMostOfTheSceneRebuildsAndStaysExact) {
  Scene scene = make_scene();
  BeamField field = BeamField::build(scene, kConfig);
  const Vec3f centre = scene.bounds().center();
  for (const Instance& object : std::vector<Instance>(scene.instances())) {
    Transform t = object.transform;
    t.translation += (centre - t.translation) * 0.02f;  // inwards: no object leaves the sphere
    scene.set_transform(object.id, t);
    field.move(object.id, t);
  }
  field.commit();
  EXPECT_TRUE(field.beam_stats().last_commit_rebuilt);
  const TriangleSet set = flatten(scene);
  EXPECT_EQ(differences(field, BeamField::build(scene, set, kConfig), probe_rays(set, 11)), 0u);
}

TEST(BeamUpdates, StagedEditsAreInvisibleUntilCommit) {
  Scene scene = make_scene();
  const Scene before = scene;
  BeamField field = BeamField::build(scene, kConfig);
  const BeamField original = BeamField::build(before, kConfig);
  const std::vector<Instance> objects = scene.instances();
  field.remove(objects[1].id);
  Transform t = objects[4].transform;
  t.translation += Vec3f{0.3f, -0.2f, 0.1f};
  field.move(objects[4].id, t);
  EXPECT_TRUE(field.has_staged_edits());
  const std::vector<Ray> rays = probe_rays(flatten(before), 11);
  EXPECT_EQ(differences(field, original, rays), 0u);
  field.commit();
  EXPECT_FALSE(field.has_staged_edits());
  EXPECT_GT(differences(field, original, rays), rays.size() / 200);
}

TEST(BeamUpdates, BadEditsAreRefused) {
  Scene scene = make_scene();
  BeamField field = BeamField::build(scene, kConfig);
  const ObjectId present = scene.instances()[3].id;
  EXPECT_THROW(field.remove(9999), Error);
  EXPECT_THROW(field.insert(scene, present), Error);
  EXPECT_THROW(field.insert(scene, 9999), Error);
  EXPECT_THROW(field.move(9999, Transform{}), Error);
  Transform flat;
  flat.scale = 0.0f;
  EXPECT_THROW(field.move(present, flat), Error);
  EXPECT_FALSE(field.has_staged_edits());
  field.remove(present);
  EXPECT_THROW(field.remove(present), Error);
}

TEST(BeamUpdates, RemovingEveryObjectLeavesAnEmptyField) {
  Scene scene = make_scene();
  BeamField field = BeamField::build(scene, kConfig);
  for (const Instance& o : scene.instances()) field.remove(o.id);
  field.commit();
  EXPECT_EQ(field.beam_stats().triangles, 0u);
  EXPECT_EQ(field.stats().reference_count, 0u);
  for (const Ray& ray : probe_rays(flatten(scene), 12)) {
    EXPECT_FALSE(field.intersect(ray));
    EXPECT_FALSE(field.occluded(ray));
  }
}

}  // namespace
}  // namespace vf::test

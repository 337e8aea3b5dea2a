// A FieldScene packed for a GPU (one buffer of tables, objects with inverse transforms, exact meshes
// in the GPU BVH layout) and queried on the host by the device's code answers as FieldScene does,
// bit for bit: closest hits (t, object, normal field) and occlusion, with instances (rotated,
// scaled, sharing one field), an exact ground, every cell storage, normal fields and both lookups.

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "differential/ray_sets.hpp"
#include "support/same_hit.hpp"
#include "support/turned_boxes.hpp"
#include "visfield/field/field_scene.hpp"
#include "visfield/gpu/packed_scene.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf::test {
namespace {

/// Random rays, AO-like rays leaving the surfaces (tmin past the start surface), and rays from
/// inside the objects' spheres (the intra-object query).
std::vector<Ray> probe_rays(const Scene& scene, std::uint64_t seed) {
  const TriangleSet set = flatten(scene);
  std::vector<Ray> rays = random_rays(set, seed, 3000);
  std::vector<Ray> surface = surface_origin_rays(set, seed, 3000);
  const float diameter = length(set.bounds.extent());
  for (Ray& r : surface) r.tmin = 1e-4f * diameter;
  rays.insert(rays.end(), surface.begin(), surface.end());
  const std::vector<Ray> model = model_rays(set, seed, 3000);
  rays.insert(rays.end(), model.begin(), model.end());
  return rays;
}

/// Boxes on a ground, every third box rotated and scaled: instances of one mesh, an exact part.
Scene boxes_scene() { return turned_boxes(27); }

void expect_same_answers(const Scene& scene, const field::ObjectFieldConfig& config, const std::string& label) {
  const field::FieldScene fields = field::FieldScene::build(scene, config);
  const gpu::PackedFieldScene packed = gpu::PackedFieldScene::pack(scene, fields);
  std::size_t closest = 0, occluded = 0, field_hits = 0, exact_hits = 0;
  for (const Ray& ray : probe_rays(scene, 31)) {
    const Hit expected = fields.intersect(ray);
    field_hits += expected.found && !expected.has_triangle();
    exact_hits += expected.has_triangle();
    if (!same_bits(packed.intersect(ray), expected) && closest++ == 0)
      ADD_FAILURE() << label << ": first closest-hit mismatch, t " << packed.intersect(ray).t << " vs " << expected.t;
    if (packed.occluded(ray) != fields.occluded(ray)) ++occluded;
  }
  EXPECT_EQ(closest, 0u) << label;
  EXPECT_EQ(occluded, 0u) << label;
  EXPECT_GT(field_hits, 100u) << label;
  EXPECT_GT(exact_hits, 100u) << label;
}

TEST(PackedFieldScene, OneBufferOffsetsAlignedAndFieldsSharedByTheirInstances) {
  const Scene scene = boxes_scene();
  const field::FieldScene fields = field::FieldScene::build(scene, {.positions = 290, .directions = 16, .normals = field::NormalStorage::oct16});
  const gpu::PackedFieldScene packed = gpu::PackedFieldScene::pack(scene, fields);
  EXPECT_EQ(packed.slots().size(), fields.stats().node_count);
  EXPECT_EQ(packed.objects().size(), fields.stats().leaf_count);
  for (const gpu::FieldSlot& slot : packed.slots()) {
    for (unsigned long long offset : {slot.upper, slot.quadrant, slot.cells, slot.normal_cells}) {
      ASSERT_NE(offset, gpu::kNoTable);
      EXPECT_EQ(offset % gpu::kTableAlignment, 0u);
      EXPECT_LT(offset, packed.buffer().size());
    }
    EXPECT_EQ(slot.averages, gpu::kNoTable);  // u8 cells keep no averages
    EXPECT_EQ(slot.cell_centres, gpu::kNoTable);  // nor nearest lookups the cells' directions
    EXPECT_EQ(slot.tables.cells, nullptr);    // pointers live only in rebased copies
  }
  // Rebasing a copy of the buffer elsewhere points into that copy, at the same offsets.
  const std::vector<unsigned char> copy = packed.buffer();
  const std::vector<field::FieldTables> moved = packed.tables_at(copy.data());
  EXPECT_EQ(moved[0].cells, copy.data() + packed.slots()[0].cells);
  EXPECT_GT(packed.exact().triangles().size(), 0u);  // the ground
  EXPECT_GE(packed.device_bytes(), packed.buffer().size());
}

TEST(PackedFieldScene, AnswersAsFieldSceneBitForBit) {
  const Scene boxes = boxes_scene();
  expect_same_answers(boxes, {.positions = 290, .directions = 16}, "boxes u8");
  expect_same_answers(boxes, {.positions = 1090, .directions = 16, .storage = field::CellStorage::u16,
                              .normals = field::NormalStorage::oct16},
                      "boxes u16 oct16");
  expect_same_answers(boxes, {.positions = 290, .directions = 16, .storage = field::CellStorage::f32,
                              .normals = field::NormalStorage::oct32, .direction_lookup = field::DirectionLookup::bilinear},
                      "boxes f32 oct32 bilinear");
  expect_same_answers(boxes, {.positions = 290, .directions = 16, .mapping = field::HemisphereMapping::polar,
                              .storage = field::CellStorage::bit, .position_lookup = field::PositionLookup::blend},
                      "boxes bit polar blend");
  const Scene sphere = make_builtin_scene("sphere", {.size = 2000});
  expect_same_answers(sphere, {.positions = 1090, .directions = 32, .normals = field::NormalStorage::oct16}, "sphere u8 oct16");
  expect_same_answers(sphere, {.positions = 290, .directions = 16, .mapping = field::HemisphereMapping::rejection_malley,
                               .direction_lookup = field::DirectionLookup::bilinear, .position_lookup = field::PositionLookup::blend},
                      "sphere rejection bilinear blend");
  // The chord lines read the cells' directions from the buffer too.
  expect_same_answers(boxes, {.positions = 290, .directions = 16, .position_lookup = field::PositionLookup::lines}, "boxes u8 lines");
  expect_same_answers(sphere, {.positions = 1090, .directions = 16, .mapping = field::HemisphereMapping::polar,
                               .normals = field::NormalStorage::oct16, .position_lookup = field::PositionLookup::lines},
                      "sphere polar oct16 lines");
}

TEST(PackedFieldScene, KnowsTheFormItsQueriesAreCompiledFor) {
  // The default choices are FieldForm::defaults, whose queries (the host's here, the kernels on a
  // device) fold every switch on them: AnswersAsFieldSceneBitForBit's "boxes u8" goes through them.
  // One other choice anywhere takes the queries that read them all.
  const Scene boxes = boxes_scene();
  const auto form_of = [&](const field::ObjectFieldConfig& config) {
    return gpu::PackedFieldScene::pack(boxes, field::FieldScene::build(boxes, config)).form();
  };
  EXPECT_EQ(form_of({.positions = 290, .directions = 16}), gpu::FieldForm::defaults);
  EXPECT_EQ(form_of({.positions = 290, .directions = 16, .storage = field::CellStorage::u16}), gpu::FieldForm::any);
  EXPECT_EQ(form_of({.positions = 290, .directions = 16, .mapping = field::HemisphereMapping::polar}), gpu::FieldForm::any);
  EXPECT_EQ(form_of({.positions = 290, .directions = 16, .normals = field::NormalStorage::oct16}), gpu::FieldForm::any);
  EXPECT_EQ(form_of({.positions = 290, .directions = 16, .direction_lookup = field::DirectionLookup::bilinear}), gpu::FieldForm::any);
  EXPECT_EQ(form_of({.positions = 290, .directions = 16, .position_lookup = field::PositionLookup::blend}), gpu::FieldForm::any);
  EXPECT_EQ(form_of({.positions = 290, .directions = 16, .sample_line = field::SampleLine::parallel}), gpu::FieldForm::any);

  // The fitted queries and the generic ones give the same bits on the same tables.
  const field::FieldScene fields = field::FieldScene::build(boxes, {.positions = 290, .directions = 16});
  const gpu::PackedFieldScene packed = gpu::PackedFieldScene::pack(boxes, fields);
  const std::vector<field::FieldTables> tables = packed.tables_at(packed.buffer().data());
  gpu::FieldSceneView generic = packed.view(tables);
  ASSERT_EQ(generic.form, gpu::FieldForm::defaults);
  generic.form = gpu::FieldForm::any;
  std::size_t hits = 0;
  for (const Ray& ray : probe_rays(boxes, 41)) {
    const Hit fitted = packed.intersect(ray);
    hits += fitted.found;
    ASSERT_TRUE(same_bits(fitted, gpu::intersect(generic, ray)));
    ASSERT_EQ(packed.occluded(ray), gpu::occluded(generic, ray));
  }
  EXPECT_GT(hits, 1000u);
}

/// Every query of `packed` through its tree over the objects and with the tree left out (each sphere in
/// turn) gives the same bits, and FieldScene's; returns how many rays hit a field object.
std::size_t expect_tree_answers_as_every_sphere(const gpu::PackedFieldScene& packed, const field::FieldScene& fields,
                                                const std::vector<Ray>& rays) {
  const std::vector<field::FieldTables> tables = packed.tables_at(packed.buffer().data());
  const gpu::FieldSceneView with_tree = packed.view(tables);
  gpu::FieldSceneView each = with_tree;
  each.tree = {};
  std::size_t field_hits = 0;
  for (const Ray& ray : rays) {
    const Hit expected = fields.intersect(ray);
    field_hits += expected.found && !expected.has_triangle();
    EXPECT_TRUE(same_bits(gpu::intersect(with_tree, ray), expected));
    EXPECT_TRUE(same_bits(gpu::intersect(each, ray), expected));
    const bool occluded = fields.occluded(ray);
    EXPECT_EQ(gpu::occluded(with_tree, ray), occluded);
    EXPECT_EQ(gpu::occluded(each, ray), occluded);
  }
  return field_hits;
}

TEST(PackedFieldScene, TreeOverManyObjectsAnswersAsTestingEverySphere) {
  // The packed copy walks a tree where FieldScene does: 27 boxes, not 8, and not with ObjectCull::each.
  const auto tree_nodes = [](const Scene& scene, field::ObjectCull cull) {
    const field::FieldScene fields = field::FieldScene::build(scene, {.positions = 290, .directions = 16}, {}, "", field::FieldMeshes::all, cull);
    EXPECT_EQ(fields.uses_tree(), !gpu::PackedFieldScene::pack(scene, fields).tree_nodes().empty());
    return gpu::PackedFieldScene::pack(scene, fields).tree_nodes().size();
  };
  EXPECT_EQ(tree_nodes(turned_boxes(8), field::ObjectCull::tree), 0u);
  EXPECT_EQ(tree_nodes(boxes_scene(), field::ObjectCull::each), 0u);
  const Scene boxes = boxes_scene();
  const field::FieldScene fields = field::FieldScene::build(boxes, {.positions = 290, .directions = 16});
  const gpu::PackedFieldScene packed = gpu::PackedFieldScene::pack(boxes, fields);
  ASSERT_GT(packed.tree_nodes().size(), 1u);
  // Every object in exactly one leaf; every leaf's box holds its objects' widened spheres.
  std::vector<int> seen(packed.objects().size(), 0);
  for (const gpu::ObjectNode& n : packed.tree_nodes()) {
    EXPECT_TRUE(gpu::is_leaf(n) ? n.count >= 1 && n.count <= gpu::kObjectLeafSize : n.count < gpu::kInteriorNode + 3);
    for (unsigned int k = n.first; gpu::is_leaf(n) && k < n.first + n.count; ++k) {
      const gpu::FieldObject& o = packed.objects()[packed.tree_items()[k]];
      ++seen[packed.tree_items()[k]];
      for (int a = 0; a < 3; ++a) {
        EXPECT_LE(n.lo[a], o.centre[a] - o.radius * 1.001f);
        EXPECT_GE(n.hi[a], o.centre[a] + o.radius * 1.001f);
      }
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<std::ptrdiff_t>(seen.size()));
  EXPECT_GT(expect_tree_answers_as_every_sphere(packed, fields, probe_rays(boxes, 43)), 500u);
}

TEST(PackedFieldScene, RaysMeetingDozensOfObjectsAnswerWithTheFirstNearest) {
  // 80 overlapping boxes in a row: rays along it may meet them all (more than 32: a walk that sorted
  // the objects it meets on its stack would overflow), and the walk, taking them in its own order,
  // answers with the first nearest object, as FieldScene does.
  Bounds3f b;
  const Scene scene = boxes_in_a_row(80, b);
  const field::FieldScene fields = field::FieldScene::build(scene, {.positions = 290, .directions = 16});
  const gpu::PackedFieldScene packed = gpu::PackedFieldScene::pack(scene, fields);
  ASSERT_FALSE(packed.tree_nodes().empty());
  std::vector<Ray> rays = probe_rays(scene, 47);
  const std::vector<Ray> row = rays_along_the_row(scene, b, 2000, 3);
  rays.insert(rays.end(), row.begin(), row.end());
  std::size_t along = 0;
  for (const Ray& ray : row) {
    std::size_t met = 0;
    for (const gpu::FieldObject& o : packed.objects()) met += gpu::may_meet(o, ray);
    along += met > 32;
  }
  EXPECT_GT(along, 1000u);
  EXPECT_GT(expect_tree_answers_as_every_sphere(packed, fields, rays), 1000u);
}

TEST(PackedFieldScene, CoincidentObjectsAnswerAsFieldScene) {
  // Each box twice in one place: equal answers, of which FieldScene keeps the first object's; the
  // walk meets them in its own order and keeps the same one.
  Scene scene = boxes_scene();
  for (const Instance& object : std::vector<Instance>(scene.instances().begin(), scene.instances().end()))
    if (scene.meshes[object.mesh].occluder != MeshOccluder::exact) scene.add_instance(object.mesh, object.transform);
  const field::FieldScene fields = field::FieldScene::build(scene, {.positions = 290, .directions = 16});
  const gpu::PackedFieldScene packed = gpu::PackedFieldScene::pack(scene, fields);
  ASSERT_FALSE(packed.tree_nodes().empty());
  EXPECT_GT(expect_tree_answers_as_every_sphere(packed, fields, probe_rays(scene, 53)), 500u);
}

TEST(PackedFieldScene, AllExactOrAllFields) {
  // A scene without field meshes packs to no slots and answers exactly; one without exact meshes
  // has an empty BVH.
  Scene scene = make_builtin_scene("boxes", {.size = 8});
  const field::FieldScene all_exact = field::FieldScene::build(scene, {.positions = 290, .directions = 16}, {}, "",
                                                               field::FieldMeshes::marked);
  const gpu::PackedFieldScene packed = gpu::PackedFieldScene::pack(scene, all_exact);
  EXPECT_TRUE(packed.slots().empty());
  for (const Ray& ray : probe_rays(scene, 5)) ASSERT_TRUE(same_bits(packed.intersect(ray), all_exact.intersect(ray)));
  for (TriangleMesh& mesh : scene.meshes) mesh.occluder = MeshOccluder::automatic;
  const field::FieldScene all_fields = field::FieldScene::build(scene, {.positions = 290, .directions = 16});
  const gpu::PackedFieldScene only_fields = gpu::PackedFieldScene::pack(scene, all_fields);
  EXPECT_TRUE(only_fields.exact().nodes().empty());
  for (const Ray& ray : probe_rays(scene, 6)) {
    ASSERT_TRUE(same_bits(only_fields.intersect(ray), all_fields.intersect(ray)));
    ASSERT_EQ(only_fields.occluded(ray), all_fields.occluded(ray));
  }
}

}  // namespace
}  // namespace vf::test

// A FieldScene packed for a GPU (one buffer of tables, objects with inverse transforms, exact meshes
// in the GPU BVH layout) and queried on the host by the device's code answers as FieldScene does,
// bit for bit: closest hits (t, object, normal field) and occlusion, with instances (rotated,
// scaled, sharing one field), an exact ground, every cell storage, normal fields and both lookups.

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

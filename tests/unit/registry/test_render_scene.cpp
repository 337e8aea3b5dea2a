// render_scene(): the library form of `visfield render`. A region of the image equals the same
// pixels of the whole render bit for bit, for every integrator (what distributed tile renders rely
// on); the occluder choice follows the CLI's rules; bad settings are refused with one line. And the
// array queries over any structure (structure_queries.hpp) equal its batch queries.

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/registry/render_scene.hpp"
#include "visfield/registry/scene_geometry.hpp"
#include "visfield/registry/structure_queries.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

TEST(RenderSettingsTable, DefaultsAreRenderSettingsOwnAndEveryKeyReachesItsField) {
  const RenderSettings defaults{};
  ASSERT_GE(render_setting_specs().size(), 10u);
  for (const RenderSettingSpec& spec : render_setting_specs()) {
    EXPECT_EQ(render_setting_text(defaults, spec.param.key), spec.param.default_value) << spec.param.key << ": the table and RenderSettings{} drifted";
    // The default reads back as itself.
    EXPECT_EQ(render_setting_text(with_render_settings({}, std::string(spec.param.key) + "=" + std::string(spec.param.default_value), "t"),
                                  spec.param.key),
              spec.param.default_value)
        << spec.param.key;
  }
  const RenderSettings s =
      with_render_settings({}, "integrator=path,spp=3,ao_rays=7,ao_directions=513,max_distance=2.5,depth=9,shadow_rays=11,"
                               "glossy_rays=13,ambient=0.25,seed=77",
                           "t");
  EXPECT_EQ(s.integrator, Integrator::path);
  EXPECT_EQ(s.spp, 3);
  EXPECT_EQ(s.ao_rays, 7);
  EXPECT_EQ(s.psf_level, 4);  // 513 = 2 * 4^4 + 1 lines: level 4 of the octahedral set
  EXPECT_EQ(s.max_distance, 2.5f);
  EXPECT_EQ(s.depth, 9);
  EXPECT_EQ(s.shadow_rays, 11);
  EXPECT_EQ(s.glossy_rays, 13);
  EXPECT_EQ(s.ambient, 0.25f);
  EXPECT_EQ(s.seed, 77u);
  EXPECT_EQ(render_setting_text(s, "ao_directions"), "513");
  for (const char* bad : {"spp=0", "ao_rays=65537", "ao_directions=100", "max_distance=0", "max_distance=-1", "integrator=photon",
                          "ambient=101", "colour=red"})
    EXPECT_THROW(with_render_settings({}, bad, "t"), Error) << bad;
  EXPECT_THROW(render_setting_text({}, "colour"), Error);
}

RenderSettings small(Integrator integrator) {
  RenderSettings s;
  s.integrator = integrator;
  s.width = 24, s.height = 18;
  s.spp = 2, s.ao_rays = 4, s.shadow_rays = 3, s.glossy_rays = 2, s.depth = 3;
  return s;
}

class RegionOfEveryIntegrator : public ::testing::TestWithParam<Integrator> {};

TEST_P(RegionOfEveryIntegrator, EqualsTheSamePixelsOfTheWholeImage) {
  const Scene scene = make_builtin_scene("cornell", {});
  RenderSettings settings = small(GetParam());
  const Image whole = render_scene(scene, settings).image;
  ASSERT_EQ(whole.width, 24);
  settings.region = ImageTile{5, 3, 19, 11};
  const RenderResult part = render_scene(scene, settings);
  ASSERT_EQ(part.image.width, 14);
  ASSERT_EQ(part.image.height, 8);
  EXPECT_EQ(part.stats.width, 14);
  for (int y = 3; y < 11; ++y)
    for (int x = 5; x < 19; ++x) {
      const Vec3f a = whole.at(x, y), b = part.image.at(x - 5, y - 3);
      ASSERT_EQ(std::memcmp(&a, &b, sizeof(Vec3f)), 0) << integrator_name(GetParam()) << " pixel " << x << ", " << y;
    }
}

INSTANTIATE_TEST_SUITE_P(RenderScene, RegionOfEveryIntegrator, ::testing::ValuesIn(kIntegrators),
                         [](const auto& info) { return std::string(integrator_name(info.param)); });

TEST(RenderScene, RefusesBadRegionsAndSettings) {
  const Scene scene = make_builtin_scene("sphere", {});
  RenderSettings s = small(Integrator::ao);
  s.region = ImageTile{20, 0, 30, 5};  // beyond the 24 pixels of width
  EXPECT_THROW(render_scene(scene, s), Error);
  s.region = ImageTile{4, 4, 4, 9};  // empty
  EXPECT_THROW(render_scene(scene, s), Error);
  s.region = {};
  s.ao_rays = 0;
  EXPECT_THROW(render_scene(scene, s), Error);
  s = small(Integrator::ao);
  s.accel = "octree";
  EXPECT_THROW(render_scene(scene, s), Error);
  s = small(Integrator::ao);
  s.occluders = "fields";
  EXPECT_THROW(render_scene(scene, s), Error);
}

TEST(RenderScene, ChoosesTheOccluderAsTheCommandLineDoes) {
  Scene scene = make_builtin_scene("sphere", {});
  RenderSettings s;
  EXPECT_EQ(occluder_spec(s, scene), "");
  s.occluders = "field";
  EXPECT_EQ(occluder_spec(s, scene), "field");
  s.occluder = "field:positions=290";
  EXPECT_EQ(occluder_spec(s, scene), "field:positions=290");
  s.occluder = "bvh";
  EXPECT_THROW(occluder_spec(s, scene), Error);  // fields asked, an exact structure given
  s.occluders = "exact";
  EXPECT_EQ(occluder_spec(s, scene), "bvh");
  s.occluder = "field";
  EXPECT_THROW(occluder_spec(s, scene), Error);
  s = RenderSettings{};
  scene.meshes[0].occluder = MeshOccluder::field;
  EXPECT_EQ(occluder_spec(s, scene), "field:meshes=marked");
}

TEST(RenderScene, ImagesDoNotDependOnTheThreadCount) {
  const Scene scene = make_builtin_scene("cornell", {});
  const RenderSettings s = small(Integrator::path);
  Image one, two;
  {
    ThreadLimit limit(1);
    one = render_scene(scene, s).image;
  }
  {
    ThreadLimit limit(2);
    two = render_scene(scene, s).image;
  }
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Vec3f)), 0);
}

TEST(StructureQueries, StridedArraysEqualTheBatch) {
  const Scene scene = make_builtin_scene("boxes", {});
  SceneGeometry geometry(scene);
  // More rays than one chunk, so the chunking is exercised.
  const std::size_t n = 70000;
  std::vector<Ray> rays(n);
  Rng rng(3, 1);
  const Bounds3f b = scene.bounds();
  for (Ray& r : rays) {
    const Vec3f o{b.lo.x + (b.hi.x - b.lo.x) * rng.uniform(), b.lo.y + (b.hi.y - b.lo.y) * rng.uniform(), b.lo.z + (b.hi.z - b.lo.z) * rng.uniform()};
    r = Ray{o, uniform_sphere(rng.uniform(), rng.uniform()), 0.0f, rng.uniform() < 0.5f ? 1.0f : std::numeric_limits<float>::infinity()};
  }
  for (const char* spec : {"bvh", "beam:dirs=33,n=16"}) {
    const BuiltStructure built = build_structure(spec, geometry);
    std::vector<Hit> expected(n);
    intersect_batch(built.structure, rays, expected);
    std::vector<std::uint8_t> expected_occluded(n);
    occluded_batch(built.structure, rays, expected_occluded);
    // Interleaved (array of structures, 8 floats a ray) read through strides.
    const float* base = &rays[0].org.x;
    const std::ptrdiff_t stride = sizeof(Ray);
    RayArrays a;
    a.ox = {base, stride}, a.oy = {base + 1, stride}, a.oz = {base + 2, stride};
    a.dx = {base + 3, stride}, a.dy = {base + 4, stride}, a.dz = {base + 5, stride};
    a.tmin = {base + 6, stride}, a.tmax = {base + 7, stride};
    a.count = n;
    std::vector<float> t(n);
    std::vector<std::uint32_t> instance(n), prim(2 * n);
    HitArrays out;
    out.t.data = t.data();
    out.instance.data = instance.data();
    out.prim = {prim.data(), 2 * sizeof(std::uint32_t)};  // every other element
    intersect_arrays(built.structure, a, out);
    std::vector<std::uint8_t> occluded(n);
    occluded_arrays(built.structure, a, StridedOut<std::uint8_t>{occluded.data(), 1});
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_EQ(std::memcmp(&t[i], &expected[i].t, sizeof(float)), 0) << spec << " ray " << i;
      ASSERT_EQ(instance[i], expected[i].instance);
      ASSERT_EQ(prim[2 * i], expected[i].prim);
    }
    EXPECT_EQ(occluded, expected_occluded) << spec;
  }
}

TEST(StructureQueries, EditsNeedAnUpdatableStructure) {
  const Scene scene = make_builtin_scene("boxes", {});
  SceneGeometry geometry(scene);
  BuiltStructure bvh = build_structure("bvh:levels=1", geometry);
  EXPECT_FALSE(is_updatable(bvh.structure));
  try {
    move_object(bvh.structure, scene.instances()[0].id, Transform{});
    ADD_FAILURE() << "a flattened BVH took an edit";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be edited"), std::string::npos) << e.what();
  }
  BuiltStructure beam = build_structure("beam:dirs=33,n=16", geometry);
  EXPECT_TRUE(is_updatable(beam.structure));
  // The object a ray down through the scene hits first is gone from its answers once removed and committed.
  const Bounds3f box = scene.bounds();
  const Ray down{box.center() + Vec3f{0.0f, box.extent().y, 0.0f}, {0.0f, -1.0f, 0.0f}};
  const auto hit_of = [&](const AnyStructure& s) { return std::visit([&](const auto& x) { return x.intersect(down); }, s); };
  const Hit before = hit_of(beam.structure);
  ASSERT_TRUE(before) << "the probe ray should hit an object";
  remove_object(beam.structure, before.instance);
  commit_objects(beam.structure);
  const Hit after = hit_of(beam.structure);
  EXPECT_TRUE(!after || after.instance != before.instance) << "the removed object is still hit";
}

}  // namespace
}  // namespace vf

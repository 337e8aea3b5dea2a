#include <gtest/gtest.h>

#include <limits>

#include "differential/structure_specs.hpp"
#include "differential/test_scenes.hpp"
#include "visfield/accel/batch.hpp"
#include "visfield/core/error.hpp"
#include "visfield/registry/planning.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/registry/structure_queries.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

// The vf::Error message of building `spec` over `scene`, or "" when it builds.
std::string build_error(const std::string& spec, const Scene& scene) {
  SceneGeometry geometry(scene);
  try {
    build_structure(spec, geometry);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const Scene& small_scene() {
  static const Scene scene = test::scene_from_triangles(test::random_soup(31, 500, 0.05f, 0.1f));
  return scene;
}

TEST(Registry, EveryEntryBuildsWithItsDefaultsAndNamesItself) {
  EXPECT_EQ(structure_names(), (std::vector<std::string>{"bvh", "grid", "kdtree", "median-bsp", "brute", "beam", "field", "auto"}));
  for (const StructureInfo& info : structure_table()) {
    SceneGeometry geometry(small_scene());
    const BuiltStructure built = build_structure(info.name, geometry);
    const AccelStats s = structure_stats(built.structure);
    EXPECT_GE(s.reference_count, 500u) << info.name;  // subdivisions reference a triangle once per cell
    EXPECT_GT(s.memory_bytes, 0u) << info.name;
    EXPECT_TRUE(built.resolved.starts_with(info.name)) << built.resolved;
    EXPECT_FALSE(info.summary.empty());
  }
}

TEST(Registry, DefaultsAreTheConfigDefaults) {
  // The help text states these defaults; the structures' Config structs hold them.
  const auto default_of = [](std::string_view structure, std::string_view key) {
    for (const ParamSpec& p : find_structure(structure).params)
      if (p.key == key) return std::stod(std::string(p.default_value));
    ADD_FAILURE() << structure << " has no parameter " << key;
    return 0.0;
  };
  EXPECT_EQ(default_of("bvh", "bins"), BvhConfig{}.bin_count);
  EXPECT_EQ(default_of("bvh", "leaf"), BvhConfig{}.max_leaf_size);
  EXPECT_EQ(default_of("bvh", "kt"), BvhConfig{}.traversal_cost);
  EXPECT_EQ(default_of("bvh", "ki"), BvhConfig{}.intersection_cost);
  EXPECT_EQ(default_of("grid", "density"), UniformGridConfig{}.density);
  EXPECT_EQ(default_of("grid", "exact"), UniformGridConfig{}.exact_overlap ? 1.0 : 0.0);
  EXPECT_EQ(default_of("kdtree", "kt"), KdTreeConfig{}.traversal_cost);
  EXPECT_EQ(default_of("kdtree", "ki"), KdTreeConfig{}.intersection_cost);
  EXPECT_FLOAT_EQ(static_cast<float>(default_of("kdtree", "empty")), KdTreeConfig{}.empty_bonus);
  EXPECT_EQ(default_of("kdtree", "depth"), KdTreeConfig{}.max_depth);
  EXPECT_EQ(default_of("median-bsp", "depth"), MedianBspConfig{}.max_depth);
  EXPECT_EQ(default_of("median-bsp", "leaf"), MedianBspConfig{}.max_leaf_size);
  EXPECT_EQ(default_of("beam", "dirs"), static_cast<double>(BeamFieldConfig{}.direction_count()));
  EXPECT_EQ(default_of("beam", "n"), BeamFieldConfig{}.resolution);
  EXPECT_EQ(default_of("beam", "depth"), BeamFieldConfig{}.max_depth);
  EXPECT_EQ(default_of("beam", "leaf"), BeamFieldConfig{}.leaf_size);
  EXPECT_EQ(default_of("field", "positions"), field::ObjectFieldConfig{}.positions);
  EXPECT_EQ(default_of("field", "directions"), field::ObjectFieldConfig{}.directions);
  EXPECT_EQ(default_of("field", "bilinear"), field::ObjectFieldConfig{}.direction_lookup == field::DirectionLookup::bilinear ? 1.0 : 0.0);
  EXPECT_EQ(default_of("field", "blend"), field::ObjectFieldConfig{}.position_lookup == field::PositionLookup::blend ? 1.0 : 0.0);
  EXPECT_EQ(default_of("field", "through"), field::ObjectFieldConfig{}.sample_line == field::SampleLine::through ? 1.0 : 0.0);
}

TEST(Registry, EveryRangeTheRegistryAcceptsTheStructureAccepts) {
  // The registry's ranges are what users can type; each end must build (the library checks too).
  // BeamField's size is the product of its direction count and n² (n=1024 at 513 directions is 2 GB
  // of tile tables), an ObjectField's of its positions and directions² (256² at 4226 positions is 277M
  // precompute rays, minutes under the sanitizers): each end is built with the other factor at its smallest.
  const auto companion = [](std::string_view name, std::string_view key) -> std::string {
    if (name == "field") return ",positions=290";
    if (name != "beam") return "";
    return key == "dirs" ? ",n=16" : key == "n" ? ",dirs=33" : ",dirs=33,n=16";
  };
  for (const StructureInfo& info : structure_table()) {
    for (const ParamSpec& p : info.params) {
      if (p.type != ParamType::whole && p.type != ParamType::number) continue;
      if (info.name == "auto") continue;  // its rays= only sets the workload size
      for (const double value : {p.min, p.max}) {
        std::string text = std::to_string(value);
        if (p.type == ParamType::whole) text = std::to_string(static_cast<std::uint64_t>(value));
        const std::string spec = std::string(info.name) + ":" + std::string(p.key) + "=" + text + companion(info.name, p.key);
        // Under the sanitizers (VISFIELD_TEST_SCALE < 1) an end whose build is large only to stress
        // (BeamField's n=1024 and dirs=8193, a field's 256² directions) is parsed and estimated, not built.
        SceneGeometry geometry(small_scene());
        if (test::test_scale() < 1.0 && estimate_structure_bytes(spec, geometry) > 16.0 * 1024 * 1024) continue;
        EXPECT_EQ(build_error(spec, small_scene()), "") << spec;
      }
    }
  }
}

TEST(Registry, ParametersReachTheStructure) {
  SceneGeometry geometry(small_scene());
  const AccelStats leaf1 = structure_stats(build_structure("bvh:leaf=1,levels=1", geometry).structure);
  const AccelStats leaf8 = structure_stats(build_structure("bvh:leaf=8,levels=1", geometry).structure);
  EXPECT_GT(leaf1.leaf_count, leaf8.leaf_count);
  const AccelStats dense = structure_stats(build_structure("grid:density=8", geometry).structure);
  const AccelStats sparse = structure_stats(build_structure("grid:density=0.5", geometry).structure);
  EXPECT_GT(dense.node_count, 4 * sparse.node_count);
  const AccelStats shallow = structure_stats(build_structure("kdtree:depth=2", geometry).structure);
  EXPECT_LE(shallow.max_depth, 3);
  const AccelStats bsp = structure_stats(build_structure("median-bsp:depth=3", geometry).structure);
  EXPECT_LE(bsp.max_depth, 4);
  const AccelStats coarse = structure_stats(build_structure("beam:dirs=33,n=16", geometry).structure);
  const AccelStats fine = structure_stats(build_structure("beam:dirs=129,n=32", geometry).structure);
  EXPECT_GT(fine.memory_bytes, 4 * coarse.memory_bytes);
  const AccelStats flat = structure_stats(build_structure("beam:dirs=33,depth=0", geometry).structure);
  EXPECT_EQ(flat.max_depth, 0);
  EXPECT_EQ(flat.leaf_count, flat.node_count);  // one leaf per non-empty tile
}

TEST(Registry, BadSpecsAreRefusedWithOneLineNamingTheProblem) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"octree", "--accel octree: unknown structure (valid: bvh, grid, kdtree, median-bsp, brute, beam, field, auto)"},
      {"bvh:leaves=4", "unknown key 'leaves' (valid keys: bins, leaf, kt, ki, levels)"},
      {"bvh:leaf=0", "leaf=0: expected a non-negative integer in 1..128"},
      {"bvh:leaf=many", "leaf=many"},
      {"grid:density=-1", "density=-1"},
      {"grid:exact=maybe", "exact=maybe"},
      {"kdtree:levels=3", "levels=3: expected one of auto, 1, 2"},
      {"bvh:leaf=4,leaf=5", "leaf is given twice"},
      {"bvh:", "empty parameter list"},
      {"bvh:leaf", "not key=value"},
      {":leaf=4", "no name"},
      {"auto:kind=diffuse", "kind=diffuse"},
      {"brute:leaf=2", "unknown key 'leaf' (valid keys: levels)"},
      {"beam:n=0", "n=0: expected a non-negative integer in 16..1024"},
      {"beam:dirs=500", "dirs=500: expected one of 33, 129, 513, 2049, 8193"},
      {"beam:depth=13", "depth=13: expected a non-negative integer in 0..12"},
      {"beam:levels=2", "unknown key 'levels' (valid keys: dirs, n, depth, leaf, stream)"},
  };
  for (const auto& [spec, expected] : cases) {
    std::string message;
    try {
      check_structure_spec(spec);
    } catch (const Error& e) {
      message = e.what();
    }
    EXPECT_NE(message.find(expected), std::string::npos) << spec << " -> '" << message << "'";
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
}

TEST(Registry, ResolvedSpecsSayWhatWasChosen) {
  SceneGeometry geometry(small_scene());
  EXPECT_EQ(build_structure("bvh", geometry).resolved, "bvh:levels=1");
  EXPECT_EQ(build_structure("bvh:leaf=4,levels=2", geometry).resolved, "bvh:leaf=4,levels=2");
  EXPECT_TRUE(std::holds_alternative<InstanceLayer>(build_structure("grid:levels=2", geometry).structure));
  EXPECT_TRUE(std::holds_alternative<UniformGrid>(build_structure("grid:levels=1", geometry).structure));
}

TEST(Registry, LevelsAutoFlattensSmallScenesAndInstancesManyCopies) {
  // 64 boxes of 12 triangles: few triangles, flattened.
  const Scene boxes = make_builtin_scene("boxes");
  SceneGeometry few(boxes);
  EXPECT_TRUE(std::holds_alternative<Bvh>(build_structure("bvh", few).structure));
  // 300 copies of a 5000-triangle soup: 1.5M instanced triangles from 5000 unique ones.
  Scene copies = test::scene_from_triangles(test::random_soup(2, 5000, 0.01f, 0.05f));
  for (int i = 1; i < 300; ++i) {
    Transform t;
    t.translation = {static_cast<float>(i % 20), 0.0f, static_cast<float>(i / 20)};
    copies.add_instance(0, t);
  }
  SceneGeometry many(copies);
  const BuiltStructure built = build_structure("bvh", many);
  EXPECT_TRUE(std::holds_alternative<InstanceLayer>(built.structure));
  EXPECT_EQ(built.resolved, "bvh:levels=2");
  EXPECT_FALSE(many.is_flattened());  // the two-level build never flattens
}

TEST(Registry, AutoBuildsWhatThePlannerPicks) {
  SceneGeometry geometry(small_scene());
  // One ray: nothing pays for a costly build, so the grid or brute force (builds linear in N) win.
  const BuiltStructure one = build_structure("auto:rays=1,kind=camera", geometry);
  EXPECT_TRUE(std::holds_alternative<UniformGrid>(one.structure) || std::holds_alternative<BruteForce>(one.structure)) << one.resolved;
  EXPECT_EQ(one.resolved.rfind("auto:kind=camera,rays=1 -> ", 0), 0u) << one.resolved;
  // A trillion AO rays with any error allowed: the fields' constant-time lookups; with none, never a field.
  const BuiltStructure loose = build_structure("auto:rays=1000000000000,kind=ao,error=255", geometry);
  EXPECT_TRUE(std::holds_alternative<field::FieldScene>(loose.structure)) << loose.resolved;
  EXPECT_EQ(loose.resolved.rfind("auto:kind=ao,rays=1000000000000,error=255 -> field:", 0), 0u) << loose.resolved;
  const BuiltStructure exact = build_structure("auto:rays=1000000000000,kind=ao", geometry);
  EXPECT_FALSE(std::holds_alternative<field::FieldScene>(exact.structure)) << exact.resolved;
  EXPECT_NE(build_error("auto:calibration=missing.json", small_scene()).find("missing.json"), std::string::npos);
  EXPECT_NE(build_error("auto:error=300", small_scene()).find("error=300"), std::string::npos);
}

TEST(Registry, APlanMeasuresFieldsItsModelCannotVouchForAndHandsTheChosenOneOver) {
  SceneGeometry geometry(small_scene());
  const RayKind kinds[] = {RayKind::ao};
  const SceneProfile profile = profile_for_plan(geometry, kinds, true);
  ASSERT_GT(profile.field_probe_rms, 0.0);
  Calibration loose = builtin_calibration();
  loose.plan.field_error.sigma = 3.0;  // every bound far over the error, nothing ruled out: every field is measured
  PlanRequest request;
  request.kind = RayKind::ao;
  request.rays = 1e12;
  request.max_error = 0.999 * profile.field_probe_rms;  // the probe, measured, is out
  std::optional<BuiltStructure> kept;
  const Plan plan = plan_structures(geometry, profile, loose, request, &kept);
  EXPECT_EQ(plan.to_measure, kNoRow);
  const PlanRow& chosen = plan.rows[plan.chosen];
  ASSERT_EQ(chosen.spec.rfind("field:", 0), 0u) << chosen.spec << ": " << plan.reason;  // finer fields beat the probe here
  EXPECT_TRUE(chosen.error_measured);
  EXPECT_LE(chosen.error, request.max_error);
  EXPECT_NEAR(chosen.error, field_error_rms(chosen.spec, geometry), 0.0);  // the measurement is the probe's measure
  ASSERT_TRUE(kept.has_value());
  EXPECT_TRUE(std::holds_alternative<field::FieldScene>(kept->structure));
  EXPECT_EQ(kept->resolved.rfind(chosen.spec, 0), 0u) << kept->resolved;
  // Without a field to measure, nothing is handed over.
  std::optional<BuiltStructure> none;
  request.max_error = 0.0;
  plan_structures(geometry, profile, loose, request, &none);
  EXPECT_FALSE(none.has_value());
}

TEST(Registry, BatchQueriesMatchSingleQueries) {
  const Scene scene = test::scene_from_triangles(test::random_soup(32, 2000, 0.02f, 0.1f));
  std::vector<Ray> rays;
  for (int i = 0; i < 1000; ++i) {
    const float s = static_cast<float>(i) / 1000.0f;
    rays.push_back(Ray{{s, 0.5f, -1.0f}, {0.0f, 0.1f * s, 1.0f}, 0.0f, i % 3 == 0 ? 1.2f : INFINITY});
  }
  for (const std::string& name : structure_names()) {
    SceneGeometry geometry(scene);
    const BuiltStructure built = build_structure(name, geometry);
    std::visit(
        [&](const auto& a) {
          std::vector<Hit> hits(rays.size());
          std::vector<std::uint8_t> occluded(rays.size());
          intersect_batch(a, std::span<const Ray>(rays), std::span<Hit>(hits));
          occluded_batch(a, std::span<const Ray>(rays), std::span<std::uint8_t>(occluded));
          std::size_t hit_count = 0;
          for (std::size_t i = 0; i < rays.size(); ++i) {
            const Hit single = a.intersect(rays[i]);
            ASSERT_EQ(hits[i].found, single.found) << name << " ray " << i;
            EXPECT_EQ(hits[i].t, single.t);
            EXPECT_EQ(occluded[i] != 0, a.occluded(rays[i]));
            hit_count += single ? 1 : 0;
          }
          EXPECT_GT(hit_count, 100u) << name;
        },
        built.structure);
  }
}

TEST(Registry, HelpListsEveryStructureAndParameter) {
  const std::string help = structures_help();
  for (const StructureInfo& info : structure_table()) {
    EXPECT_NE(help.find(std::string(info.name) + " (" + exactness_name(info.exactness)), std::string::npos) << info.name;
    for (const ParamSpec& p : info.params)
      EXPECT_NE(help.find(std::string(p.key) + "="), std::string::npos) << info.name << " " << p.key;
  }
  EXPECT_NE(help.find("updatable with levels=2"), std::string::npos);
}

}  // namespace
}  // namespace vf

namespace vf {
namespace {

TEST(Registry, InvalidRaysHitNothingInEveryStructure) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const Vec3f org{0.5f, 0.5f, -1.0f}, dir{0.01f, 0.02f, 1.0f};
  const std::vector<Ray> invalid = {
      Ray{org, {0, 0, 0}},          Ray{org, {-0.0f, 0, 0}},       Ray{org, {nan, 0, 1}},
      Ray{org, {inf, 0, 1}},        Ray{{nan, 0.5f, -1}, dir},     Ray{{-inf, 0.5f, -1}, dir},
      Ray{org, dir, 2.0f, 1.0f},    Ray{org, dir, 1.0f, 1.0f},     Ray{org, dir, nan, inf},
      Ray{org, dir, 0.0f, nan},
      // NaN in every origin coordinate: every slab value NaN, which box tests ignore (the c_api fuzz target's find).
      Ray{{nan, nan, nan}, {nan, nan, 0.125f}}, Ray{{nan, nan, nan}, dir}, Ray{{nan, nan, nan}, {nan, nan, nan}, nan, nan},
  };
  for (const Ray& r : invalid) EXPECT_FALSE(r.is_valid());
  std::vector<Ray> nothing_to_hit = invalid;
  nothing_to_hit.push_back(Ray{org, dir, -inf, -1.0f});  // valid, but the segment lies behind the origin
  EXPECT_TRUE((Ray{org, dir}.is_valid()));
  for (const std::string& spec : test::exact_structure_specs()) {
    SceneGeometry geometry(small_scene());
    const BuiltStructure built = build_structure(test::test_sized(spec), geometry);
    const std::string& name = spec;
    std::visit(
        [&](const auto& s) {
          ASSERT_TRUE(s.intersect(Ray{org, dir})) << name << ": the valid ray should hit the soup";
          for (std::size_t i = 0; i < nothing_to_hit.size(); ++i) {
            EXPECT_FALSE(s.intersect(nothing_to_hit[i])) << name << ", ray " << i;
            EXPECT_FALSE(s.occluded(nothing_to_hit[i])) << name << ", ray " << i;
          }
        },
        built.structure);
    // The batch paths too, each ray alone and in runs with valid ones between.
    std::vector<Ray> batch;
    for (const Ray& r : nothing_to_hit) batch.insert(batch.end(), {r, Ray{org, dir}, r, r});
    std::vector<Hit> hits(batch.size());
    std::vector<std::uint8_t> blocked(batch.size());
    intersect_batch(built.structure, batch, hits);
    occluded_batch(built.structure, batch, blocked);
    for (std::size_t i = 0; i < batch.size(); ++i) {
      EXPECT_EQ(static_cast<bool>(hits[i]), i % 4 == 1) << name << ", batch ray " << i;
      EXPECT_EQ(blocked[i] != 0, i % 4 == 1) << name << ", batch ray " << i;
    }
  }
}

}  // namespace
}  // namespace vf

#include <gtest/gtest.h>

#include <cmath>

#include "visfield/core/error.hpp"
#include "visfield/scenes/builtin.hpp"
#include "visfield/select/calibrate.hpp"
#include "visfield/select/decision.hpp"
#include "visfield/select/timing.hpp"

namespace vf {
namespace {

struct Fixture {
  Scene scene = make_builtin_scene("cornell", {.size = 400});
  TriangleSet triangles = flatten(scene);
};

TEST(Select, OnABuiltinSceneGivesFiniteConsistentEstimates) {
  const Fixture f;
  const Calibration& calibration = builtin_calibration();
  for (RayKind kind : kCalibratedKinds) {
    const Selection s = select_structure(f.scene, f.triangles, 100000, calibration, kind);
    EXPECT_EQ(s.kind, kind);
    EXPECT_EQ(s.triangles, f.triangles.size());
    EXPECT_EQ(s.rays, 100000u);
    EXPECT_EQ(s.sample_count, 500u);
    EXPECT_TRUE(std::isfinite(s.grid_ray_us));
    EXPECT_GT(s.grid_ray_us, 0.0);
    EXPECT_DOUBLE_EQ(s.tree_build_ms, estimated_tree_build_ms(calibration.constants, s.triangles));
    EXPECT_DOUBLE_EQ(s.tree_ray_us, estimated_tree_ray_us(calibration.constants, kind, s.triangles) *
                                        calibration.machine.threads / threads_in_force());
    EXPECT_DOUBLE_EQ(s.critical_rays, estimated_critical_rays(s.tree_build_ms, s.grid_ray_us, s.tree_ray_us));
    EXPECT_FALSE(std::isnan(s.critical_rays));
    EXPECT_EQ(s.structure, grid_wins(1e5, s.critical_rays) ? "grid" : "kdtree");
    ASSERT_TRUE(s.grid.has_value());
    EXPECT_EQ(s.grid->resolution(), s.grid_resolution);
    EXPECT_EQ(s.grid_build_ms, s.grid->stats().build_ms);  // the build the grid timed itself
    EXPECT_EQ(s.grid_statistics.cell_count, static_cast<std::size_t>(s.grid_resolution[0]) * s.grid_resolution[1] *
                                                s.grid_resolution[2]);
    EXPECT_GT(s.grid_memory_bytes, 0u);
  }
}

TEST(Select, DecisionFlipsBetweenFewAndManyRays) {
  const Fixture f;
  // A kd-tree that costs 1e-4 ms per N log2 N to build and almost nothing per ray: R_C is finite.
  Calibration calibration;
  calibration.constants.build_ms_per_n_log2_n = 1e-4;
  calibration.constants.ray_us_per_log2_n = {1e-12, 1e-12};
  const Selection few = select_structure(f.scene, f.triangles, 0, calibration, RayKind::path);
  EXPECT_TRUE(std::isfinite(few.critical_rays));
  EXPECT_GT(few.critical_rays, 0.0);
  EXPECT_EQ(few.structure, "grid");
  const Selection many = select_structure(f.scene, f.triangles, 1'000'000'000'000'000ull, calibration, RayKind::path);
  EXPECT_EQ(many.structure, "kdtree");
  // And a kd-tree that is slow per ray never pays off.
  calibration.constants.ray_us_per_log2_n = {1e6, 1e6};
  const Selection never = select_structure(f.scene, f.triangles, 1'000'000'000'000'000ull, calibration, RayKind::random);
  EXPECT_TRUE(std::isinf(never.critical_rays));
  EXPECT_EQ(never.structure, "grid");
}

TEST(Select, RefusesBadOptions) {
  const Fixture f;
  SelectOptions options;
  options.sample_rays = 0;
  EXPECT_THROW(select_structure(f.scene, f.triangles, 10, builtin_calibration(), RayKind::path, options), Error);
  options = {};
  options.epsilon = -1.0;
  EXPECT_THROW(select_structure(f.scene, f.triangles, 10, builtin_calibration(), RayKind::path, options), Error);
  EXPECT_THROW(select_structure(f.scene, TriangleSet{}, 10, builtin_calibration(), RayKind::path), Error);
}

TEST(Calibrate, MeasuresEveryFieldAndDerivesTheConstants) {
  std::vector<NamedScene> scenes;
  for (const char* spec : {"builtin:boxes:size=8", "builtin:sphere:size=500"}) {
    NamedScene s;
    s.name = spec;
    s.scene = parse_builtin_scene(spec);
    s.triangles = flatten(s.scene);
    scenes.push_back(std::move(s));
  }
  CalibrationOptions options;
  options.rays = 400;
  options.sample_rays = 100;
  options.build_repetitions = 1;
  std::size_t reported = 0;
  const Calibration c = calibrate(scenes, options, [&](const SceneMeasurement&) { ++reported; });
  EXPECT_EQ(reported, 2u);
  ASSERT_EQ(c.scenes.size(), 2u);
  EXPECT_EQ(c.machine.threads >= 1, true);
  EXPECT_FALSE(c.machine.cpu_model.empty());
  for (std::size_t i = 0; i < 2; ++i) {
    const SceneMeasurement& m = c.scenes[i];
    EXPECT_EQ(m.name, scenes[i].name);
    EXPECT_EQ(m.triangles, scenes[i].triangles.size());
    EXPECT_GT(m.tree_build_ms, 0.0);
    EXPECT_GT(m.grid_memory_bytes, 0u);
    EXPECT_GT(m.tree_memory_bytes, 0u);
    EXPECT_GT(m.grid_statistics.cell_count, 0u);
    for (RayKind kind : kCalibratedKinds) {
      EXPECT_EQ(m.timings(kind).ray_count, 400u);
      EXPECT_EQ(m.timings(kind).sample_count, 100u);
      EXPECT_GT(m.timings(kind).grid_us, 0.0);
      EXPECT_GT(m.timings(kind).tree_us, 0.0);
      EXPECT_GT(m.timings(kind).grid_sample_us, 0.0);
    }
  }
  const CalibrationConstants expected = compute_constants(c.scenes);
  EXPECT_EQ(c.constants.build_ms_per_n_log2_n, expected.build_ms_per_n_log2_n);
  EXPECT_EQ(c.constants.ray_us_per_log2_n, expected.ray_us_per_log2_n);
  EXPECT_NO_THROW(calibration_from_json(calibration_to_json(c), "measured"));
}

TEST(Calibrate, RefusesBadOptionsAndNoScenes) {
  CalibrationOptions options;
  EXPECT_THROW(calibrate({}, options), Error);
  options.rays = 0;
  EXPECT_THROW(validate_calibration_options(options), Error);
  options = {};
  options.path_bounces = 17;
  EXPECT_THROW(validate_calibration_options(options), Error);
  options = {};
  options.build_repetitions = 0;
  EXPECT_THROW(validate_calibration_options(options), Error);
  EXPECT_NO_THROW(validate_calibration_options(CalibrationOptions{}));
}

}  // namespace
}  // namespace vf

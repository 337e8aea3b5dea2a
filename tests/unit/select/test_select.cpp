#include <gtest/gtest.h>

#include <array>
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

TEST(Select, EstimatesFollowThePapersEquationsWithKnownConstants) {
  const Fixture f;
  // Constants set here, not read from the code: eq. 7 T_B^H = C_B N log2 N, eq. 8 t_R^H = C_R log2 N
  // (rescaled from the calibration's 4 threads to ours), R_C = T_B^H / (t_R^G (1 + eps) - t_R^H).
  Calibration calibration;
  calibration.constants.build_ms_per_n_log2_n = 2.5e-4;
  calibration.constants.ray_us_per_log2_n = {0.03, 0.05};
  calibration.machine.threads = 4;
  const double n = static_cast<double>(f.triangles.size()), log2n = std::log2(n);
  for (RayKind kind : kCalibratedKinds) {
    const Selection s = select_structure(f.scene, f.triangles, 100000, calibration, kind);
    EXPECT_EQ(s.kind, kind);
    EXPECT_EQ(s.triangles, f.triangles.size());
    EXPECT_EQ(s.rays, 100000u);
    EXPECT_EQ(s.sample_count, 500u);
    ASSERT_TRUE(std::isfinite(s.grid_ray_us));
    EXPECT_GT(s.grid_ray_us, 0.0);
    EXPECT_NEAR(s.tree_build_ms, 2.5e-4 * n * log2n, 1e-9 * n * log2n);
    const double c_r = kind == kCalibratedKinds[0] ? 0.03 : 0.05;
    const double tree_us = c_r * log2n * 4.0 / threads_in_force();
    EXPECT_NEAR(s.tree_ray_us, tree_us, 1e-12 * tree_us);
    const double denominator = s.grid_ray_us * 1.01 - tree_us;
    if (denominator > 0.0) {
      EXPECT_NEAR(s.critical_rays, s.tree_build_ms * 1000.0 / denominator, 1e-9 * s.critical_rays);
    } else {
      EXPECT_TRUE(std::isinf(s.critical_rays));
    }
    EXPECT_EQ(s.structure, 100000.0 < s.critical_rays ? "grid" : "kdtree");
    EXPECT_NEAR(s.grid_total_ms, 100000.0 * s.grid_ray_us / 1000.0, 1e-9 * s.grid_total_ms);
    EXPECT_NEAR(s.tree_total_ms, s.tree_build_ms + 100000.0 * tree_us / 1000.0, 1e-9 * s.tree_total_ms);
    ASSERT_TRUE(s.grid.has_value());
    EXPECT_EQ(s.grid->resolution(), s.grid_resolution);
    EXPECT_GT(s.grid_build_ms, 0.0);
    EXPECT_EQ(s.grid_statistics.cell_count, static_cast<std::size_t>(s.grid_resolution[0]) * s.grid_resolution[1] *
                                                s.grid_resolution[2]);
    EXPECT_GE(s.grid_memory_bytes, sizeof(std::uint32_t) * s.grid_statistics.cell_count) << "at least a start index a cell";
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
  // The constants are the means over the scenes of eq. 7's and eq. 8's ratios, computed here.
  double c_b = 0.0;
  std::array<double, 2> c_r{};
  for (const SceneMeasurement& m : c.scenes) {
    const double n = static_cast<double>(m.triangles), log2n = std::log2(n);
    c_b += m.tree_build_ms / (n * log2n) / 2.0;
    for (std::size_t k = 0; k < 2; ++k) c_r[k] += m.timings(kCalibratedKinds[k]).tree_us / log2n / 2.0;
  }
  EXPECT_NEAR(c.constants.build_ms_per_n_log2_n, c_b, 1e-12 * c_b);
  for (std::size_t k = 0; k < 2; ++k) EXPECT_NEAR(c.constants.ray_us_per_log2_n[k], c_r[k], 1e-12 * c_r[k]);
  EXPECT_EQ(calibration_from_json(calibration_to_json(c), "measured").constants, c.constants) << "the file keeps the constants";
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

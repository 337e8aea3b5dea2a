#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "visfield/core/error.hpp"
#include "visfield/scenes/builtin.hpp"
#include "visfield/select/calibrate.hpp"
#include "visfield/select/timing.hpp"

namespace vf {
namespace {

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

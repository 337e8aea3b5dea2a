#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include <nlohmann/json.hpp>

#include "synthetic.hpp"
#include "visfield/core/error.hpp"
#include "visfield/select/calibration.hpp"

namespace vf {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

Calibration sample_calibration() {
  Calibration c;
  c.machine = {"host-1", 2, "Test CPU @ 1.0GHz"};
  c.settings.rays = 12345;
  c.settings.sample_rays = 321;
  c.settings.build_repetitions = 2;
  c.settings.path_bounces = 3;
  c.settings.seed = 99;
  c.scenes.push_back(test::model_scene("builtin:soup", 1000, 1.25e-4, 0.07, 0.13, 0.75, 1.5, 2.25));
  c.scenes.push_back(test::model_scene("models/bunny.ply", 69451, 1.5e-4, 0.0625, 0.1875, 7.125, 3.0, 0.1));
  c.scenes[1].rays[1].grid_sample_us = 0.123456789012345;
  c.constants = compute_constants(c.scenes);
  return c;
}

void expect_same(const SceneMeasurement& a, const SceneMeasurement& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.grid_resolution, b.grid_resolution);
  EXPECT_EQ(a.grid_memory_bytes, b.grid_memory_bytes);
  EXPECT_EQ(a.grid_build_ms, b.grid_build_ms);
  EXPECT_EQ(a.tree_build_ms, b.tree_build_ms);
  EXPECT_EQ(a.tree_memory_bytes, b.tree_memory_bytes);
  const GridStatistics &g = a.grid_statistics, &h = b.grid_statistics;
  EXPECT_EQ(g.cell_count, h.cell_count);
  EXPECT_EQ(g.empty_cells, h.empty_cells);
  EXPECT_EQ(g.sparseness, h.sparseness);
  EXPECT_EQ(g.max_refs, h.max_refs);
  EXPECT_EQ(g.mean, h.mean);
  EXPECT_EQ(g.variance, h.variance);
  EXPECT_EQ(g.std_dev, h.std_dev);
  EXPECT_EQ(g.skewness, h.skewness);
  EXPECT_EQ(g.kurtosis, h.kurtosis);
  for (RayKind kind : kRayKinds) {
    const RayTimings &s = a.timings(kind), &t = b.timings(kind);
    EXPECT_EQ(s.ray_count, t.ray_count);
    EXPECT_EQ(s.grid_us, t.grid_us);
    EXPECT_EQ(s.tree_us, t.tree_us);
    EXPECT_EQ(s.sample_count, t.sample_count);
    EXPECT_EQ(s.grid_sample_us, t.grid_sample_us);
  }
}

void expect_same(const Calibration& a, const Calibration& b) {
  EXPECT_EQ(a.machine.hostname, b.machine.hostname);
  EXPECT_EQ(a.machine.threads, b.machine.threads);
  EXPECT_EQ(a.machine.cpu_model, b.machine.cpu_model);
  EXPECT_EQ(a.settings.rays, b.settings.rays);
  EXPECT_EQ(a.settings.sample_rays, b.settings.sample_rays);
  EXPECT_EQ(a.settings.build_repetitions, b.settings.build_repetitions);
  EXPECT_EQ(a.settings.path_bounces, b.settings.path_bounces);
  EXPECT_EQ(a.settings.seed, b.settings.seed);
  EXPECT_EQ(a.constants.build_ms_per_n_log2_n, b.constants.build_ms_per_n_log2_n);
  EXPECT_EQ(a.constants.ray_us_per_log2_n, b.constants.ray_us_per_log2_n);
  ASSERT_EQ(a.scenes.size(), b.scenes.size());
  for (std::size_t i = 0; i < a.scenes.size(); ++i) expect_same(a.scenes[i], b.scenes[i]);
}

TEST(CalibrationJson, RoundTripsEveryFieldExactly) {
  const Calibration c = sample_calibration();
  const std::string text = calibration_to_json(c);
  expect_same(calibration_from_json(text, "c.json"), c);
  // The format tag and version lead the document.
  EXPECT_EQ(text.find("\"format\""), text.find('"'));
  EXPECT_NE(text.find("\"visfield-calibration\""), std::string::npos);
  EXPECT_NE(text.find("\"version\": 1"), std::string::npos);
}

TEST(CalibrationJson, SavesAtomicallyAndLoadsBack) {
  const fs::path dir = fs::path(VISFIELD_TEST_BINARY_DIR) / "calibration-json";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Calibration c = sample_calibration();
  save_calibration(dir / "cal.json", c);
  expect_same(load_calibration(dir / "cal.json"), c);
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u);  // no temporary left behind
  EXPECT_THROW(save_calibration(dir / "missing-folder" / "cal.json", c), Error);
}

TEST(CalibrationJson, TheBuiltInCalibrationIsValid) {
  const Calibration& c = builtin_calibration();
  EXPECT_GT(c.constants.build_ms_per_n_log2_n, 0.0);
  for (RayKind kind : kRayKinds) EXPECT_GT(c.constants.ray_us(kind), 0.0);
  EXPECT_NO_THROW(calibration_from_json(calibration_to_json(c), "builtin"));
}

// Expects calibration_from_json of `text` to throw one line naming the file and containing `needle`.
void expect_error(const std::string& text, const std::string& needle) {
  try {
    calibration_from_json(text, "my-cal.json");
    ADD_FAILURE() << "accepted: " << needle;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.rfind("my-cal.json: ", 0), 0u) << message;
    EXPECT_NE(message.find(needle), std::string::npos) << "wanted '" << needle << "' in: " << message;
  }
}

// Applies `edit` to the JSON of sample_calibration() and expects an error containing `needle`.
void expect_edit_error(const std::function<void(json&)>& edit, const std::string& needle) {
  json doc = json::parse(calibration_to_json(sample_calibration()));
  edit(doc);
  expect_error(doc.dump(), needle);
}

TEST(CalibrationJson, RejectsMalformedJson) {
  expect_error("", "not valid JSON");
  expect_error("{\"format\": \"visfield-calibration\",", "not valid JSON");
  expect_error("[1, 2]", "(top level): expected an object");
}

TEST(CalibrationJson, RejectsWrongFormatOrVersion) {
  expect_edit_error([](json& d) { d["format"] = "visfield-scene"; }, "format: expected \"visfield-calibration\"");
  expect_edit_error([](json& d) { d.erase("format"); }, "format: missing");
  expect_edit_error([](json& d) { d["version"] = 2; }, "version: unsupported version 2");
  expect_edit_error([](json& d) { d["version"] = "1"; }, "version: unsupported version \"1\"");
  expect_edit_error([](json& d) { d.erase("version"); }, "version: missing");
}

TEST(CalibrationJson, RejectsMissingFieldsAndRayKinds) {
  expect_edit_error([](json& d) { d.erase("machine"); }, "machine: missing");
  expect_edit_error([](json& d) { d["settings"].erase("rays"); }, "settings.rays: missing");
  expect_edit_error([](json& d) { d["constants"]["ray_us_per_log2_n"].erase("path"); },
                    "constants.ray_us_per_log2_n.path: missing");
  expect_edit_error([](json& d) { d["scenes"][1]["rays"].erase("random"); }, "scenes[1].rays.random: missing");
  expect_edit_error([](json& d) { d["scenes"][0]["grid"]["statistics"].erase("kurtosis"); },
                    "scenes[0].grid.statistics.kurtosis: missing");
  expect_edit_error([](json& d) { d["scenes"][0].erase("kdtree"); }, "scenes[0].kdtree: missing");
}

TEST(CalibrationJson, RejectsWrongTypes) {
  expect_edit_error([](json& d) { d["scenes"][1]["triangles"] = "many"; }, "scenes[1].triangles: expected a non-negative integer");
  expect_edit_error([](json& d) { d["scenes"][0]["triangles"] = 12.5; }, "scenes[0].triangles: expected a non-negative integer");
  expect_edit_error([](json& d) { d["scenes"][0]["name"] = 7; }, "scenes[0].name: expected a string");
  expect_edit_error([](json& d) { d["constants"]["build_ms_per_n_log2_n"] = "fast"; },
                    "constants.build_ms_per_n_log2_n: expected a number");
  expect_edit_error([](json& d) { d["scenes"] = json::object(); }, "scenes: expected an array");
  expect_edit_error([](json& d) { d["machine"] = 3; }, "machine: expected an object");
  expect_edit_error([](json& d) { d["scenes"][0]["grid"]["resolution"] = {1, 2}; }, "scenes[0].grid.resolution");
  expect_edit_error([](json& d) { d["scenes"][0]["rays"]["path"]["grid_us"] = nullptr; },
                    "scenes[0].rays.path.grid_us: expected a number");
}

TEST(CalibrationJson, RejectsOutOfRangeValues) {
  expect_edit_error([](json& d) { d["constants"]["build_ms_per_n_log2_n"] = 0.0; }, "constants.build_ms_per_n_log2_n");
  expect_edit_error([](json& d) { d["constants"]["ray_us_per_log2_n"]["random"] = -1.0; }, "ray_us_per_log2_n.random");
  expect_edit_error([](json& d) { d["scenes"][0]["grid"]["statistics"]["sparseness"] = 1.5; }, "sparseness");
  expect_edit_error([](json& d) { d["scenes"][0]["triangles"] = 0; }, "scenes[0].triangles");
  expect_edit_error([](json& d) { d["scenes"][0]["rays"]["random"]["kdtree_us"] = -0.5; }, "scenes[0].rays.random.kdtree_us");
  expect_edit_error([](json& d) { d["settings"]["path_bounces"] = 17; }, "settings.path_bounces");
  expect_edit_error([](json& d) { d["machine"]["threads"] = -2; }, "machine.threads");
}

TEST(CalibrationJson, LoadNamesAMissingFileOrAFolder) {
  const fs::path dir = fs::path(VISFIELD_TEST_BINARY_DIR) / "calibration-json-missing";
  fs::create_directories(dir);
  try {
    load_calibration(dir / "nope.json");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nope.json"), std::string::npos);
  }
  EXPECT_THROW(load_calibration(dir), Error);
  std::ofstream(dir / "bad.json") << "{\"format\": \"visfield-calibration\", \"version\": 1}";
  try {
    load_calibration(dir / "bad.json");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json: machine: missing"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vf

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include <nlohmann/json.hpp>

#include "synthetic.hpp"
#include "visfield/core/error.hpp"
#include "visfield/select/calibrate.hpp"
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
  c.scenes[1].plan = test::synthetic_plan_measurement(test::synthetic_plan_model(), test::synthetic_profile(69451, 3, 0.375));
  c.scenes[1].plan.candidates.resize(9);  // a few candidates left out (over the memory limit)
  c.constants = compute_constants(c.scenes);
  c.plan = fit_plan_model(c.scenes, 2);
  return c;
}

TEST(CalibrationJson, RoundTripsEveryFieldExactly) {
  const Calibration c = sample_calibration();
  const std::string text = calibration_to_json(c);
  EXPECT_EQ(calibration_from_json(text, "c.json"), c);  // every field, exactly
  // The format tag and version lead the document.
  EXPECT_EQ(text.find("\"format\""), text.find('"'));
  EXPECT_NE(text.find("\"visfield-calibration\""), std::string::npos);
  EXPECT_NE(text.find("\"version\": 3"), std::string::npos);
}

TEST(CalibrationJson, SavesAtomicallyAndLoadsBack) {
  const fs::path dir = fs::path(VISFIELD_TEST_BINARY_DIR) / "calibration-json";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Calibration c = sample_calibration();
  save_calibration(dir / "cal.json", c);
  EXPECT_EQ(load_calibration(dir / "cal.json"), c);
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u);  // no temporary left behind
  EXPECT_THROW(save_calibration(dir / "missing-folder" / "cal.json", c), Error);
}

TEST(CalibrationJson, TheBuiltInCalibrationIsValid) {
  const Calibration& c = builtin_calibration();
  EXPECT_GT(c.constants.build_ms_per_n_log2_n, 0.0);
  for (RayKind kind : kCalibratedKinds) EXPECT_GT(c.constants.ray_us(kind), 0.0);
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
  expect_error("", "invalid JSON");
  expect_error("{\"format\": \"visfield-calibration\",", "invalid JSON");
  expect_error("[1, 2]", "top level: expected an object");
}

TEST(CalibrationJson, RejectsWrongFormatOrVersion) {
  expect_edit_error([](json& d) { d["format"] = "visfield-scene"; }, "format: expected \"visfield-calibration\"");
  expect_edit_error([](json& d) { d.erase("format"); }, "top level: missing required key \"format\"");
  expect_edit_error([](json& d) { d["version"] = 1; }, "version: unsupported version 1 (this build reads version 3; run visfield calibrate again)");
  expect_edit_error([](json& d) { d["version"] = "1"; }, "version: unsupported version \"1\"");
  expect_edit_error([](json& d) { d.erase("version"); }, "top level: missing required key \"version\"");
}

TEST(CalibrationJson, RejectsMissingFieldsAndRayKinds) {
  expect_edit_error([](json& d) { d.erase("machine"); }, "top level: missing required key \"machine\"");
  expect_edit_error([](json& d) { d["settings"].erase("rays"); }, "settings: missing required key \"rays\"");
  expect_edit_error([](json& d) { d["constants"]["ray_us_per_log2_n"].erase("path"); },
                    "constants.ray_us_per_log2_n: missing required key \"path\"");
  expect_edit_error([](json& d) { d["scenes"][1]["rays"].erase("random"); }, "scenes[1].rays: missing required key \"random\"");
  expect_edit_error([](json& d) { d["scenes"][0]["grid"]["statistics"].erase("kurtosis"); },
                    "scenes[0].grid.statistics: missing required key \"kurtosis\"");
  expect_edit_error([](json& d) { d["scenes"][0].erase("kdtree"); }, "scenes[0]: missing required key \"kdtree\"");
  expect_edit_error([](json& d) { d.erase("plan"); }, "top level: missing required key \"plan\"");
  expect_edit_error([](json& d) { d["plan"]["candidates"].erase("beam"); }, "plan.candidates: missing required key \"beam\"");
  expect_edit_error([](json& d) { d["scenes"][1]["plan"]["candidates"][0]["ray_us"].erase("ao"); },
                    "scenes[1].plan.candidates[0].ray_us: missing required key \"ao\"");
  expect_edit_error([](json& d) { d["scenes"][1]["plan"].erase("profile"); }, "scenes[1].plan: missing required key \"profile\"");
}

TEST(CalibrationJson, RejectsPlanEntriesThisBuildDoesNotWeigh) {
  expect_edit_error([](json& d) { d["scenes"][1]["plan"]["candidates"][0]["spec"] = "octree"; },
                    "scenes[1].plan.candidates[0].spec: not a candidate of this build's planner");
  expect_edit_error([](json& d) { d["plan"]["candidates"]["octree"] = d["plan"]["candidates"]["beam"]; },
                    "plan.candidates: unknown key \"octree\"");
  expect_edit_error([](json& d) { d["plan"]["field_error"]["coefficients"] = {1, 2, 3}; }, "plan.field_error.coefficients");
  expect_edit_error([](json& d) { d["scenes"][1]["plan"]["candidates"][2]["ao_rms"] = 300; }, "ao_rms");
  expect_edit_error([](json& d) { d["scenes"][1]["plan"]["profile"]["ao_occluded"] = 1.5; }, "ao_occluded");
}

TEST(CalibrationJson, RejectsWrongTypes) {
  expect_edit_error([](json& d) { d["scenes"][1]["triangles"] = "many"; }, "scenes[1].triangles: expected an integer in 1..");
  expect_edit_error([](json& d) { d["scenes"][0]["triangles"] = 12.5; }, "scenes[0].triangles: expected an integer in 1..");
  expect_edit_error([](json& d) { d["scenes"][0]["name"] = 7; }, "scenes[0].name: expected a non-empty string");
  expect_edit_error([](json& d) { d["constants"]["build_ms_per_n_log2_n"] = "fast"; },
                    "constants.build_ms_per_n_log2_n: expected a number > 0");
  expect_edit_error([](json& d) { d["scenes"] = json::object(); }, "scenes: expected an array");
  expect_edit_error([](json& d) { d["machine"] = 3; }, "machine: expected an object");
  expect_edit_error([](json& d) { d["scenes"][0]["grid"]["resolution"] = {1, 2}; }, "scenes[0].grid.resolution");
  expect_edit_error([](json& d) { d["scenes"][0]["rays"]["path"]["grid_us"] = nullptr; },
                    "scenes[0].rays.path.grid_us: expected a number >= 0");
}

TEST(CalibrationJson, RejectsUnknownKeys) {
  expect_edit_error([](json& d) { d["settings"]["rayz"] = 3; }, "settings: unknown key \"rayz\"");
  expect_edit_error([](json& d) { d["scenes"][0]["grid"]["cells"] = 3; }, "scenes[0].grid: unknown key \"cells\"");
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
  std::ofstream(dir / "bad.json") << "{\"format\": \"visfield-calibration\", \"version\": 3}";
  try {
    load_calibration(dir / "bad.json");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json: top level: missing required key \"machine\""), std::string::npos)
        << e.what();
  }
}

TEST(CalibrationJson, RefusesACalibrationFromAnotherMachineOrThreadCount) {
  Calibration c = builtin_calibration();
  c.machine = MachineInfo{"lab", 2, "Some CPU @ 3.0GHz"};
  EXPECT_NO_THROW(require_calibration_for(c, MachineInfo{"other-host", 2, "Some CPU @ 3.0GHz"}, "cal.json"));
  const auto message = [&](const MachineInfo& here) {
    try {
      require_calibration_for(c, here, "cal.json");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  const std::string other_cpu = message(MachineInfo{"lab", 2, "Another CPU"});
  EXPECT_EQ(other_cpu.rfind("cal.json: measured on Some CPU @ 3.0GHz with 2 threads, but this is Another CPU with 2 threads", 0), 0u)
      << other_cpu;
  EXPECT_EQ(other_cpu.find("--threads"), std::string::npos) << other_cpu;
  const std::string other_threads = message(MachineInfo{"lab", 8, "Some CPU @ 3.0GHz"});
  EXPECT_NE(other_threads.find("or use --threads 2"), std::string::npos) << other_threads;
}

}  // namespace
}  // namespace vf

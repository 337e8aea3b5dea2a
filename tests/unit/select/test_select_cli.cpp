// End-to-end tests of the selection subcommands: calibrate, select, stats, report.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "support/run_command.hpp"
#include "visfield/select/calibration.hpp"
#include "visfield/select/plan.hpp"

namespace vf {
namespace {

namespace fs = std::filesystem;
using test::run_command;

std::size_t line_count(const std::string& text) {
  std::size_t lines = 0;
  for (char c : text) lines += c == '\n';
  return lines;
}

class SelectCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(VISFIELD_TEST_BINARY_DIR) / "select-cli" / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  test::CommandResult visfield(const std::string& args) { return run_command(std::string(VISFIELD_EXE) + " " + args, dir_); }
  std::set<std::string> files() const {
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) names.insert(entry.path().filename().string());
    return names;
  }
  // Bad input: the given exit code, one line on stderr containing `needle`, no file written.
  void expect_clean_failure(const std::string& args, const std::string& needle, int exit_code = 1) {
    const std::set<std::string> before = files();
    const auto r = visfield(args);
    EXPECT_EQ(r.exit_code, exit_code) << args;
    EXPECT_EQ(line_count(r.err), 1u) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(files(), before) << args;
  }
  // The grid-or-kd-tree calibration alone (--no-plan: fast).
  void calibrate_small() {
    const auto r = visfield("calibrate builtin:boxes:size=8 builtin:cornell:size=100 --rays 300 --sample-rays 100 "
                            "--build-repetitions 1 --no-plan --threads 2 -o cal.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("measured builtin:boxes:size=8"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("constants: C_B"), std::string::npos) << r.out;
  }
  fs::path dir_;
};

TEST_F(SelectCli, CalibrateWritesALoadableFile) {
  calibrate_small();
  const Calibration c = load_calibration(dir_ / "cal.json");
  ASSERT_EQ(c.scenes.size(), 2u);
  EXPECT_EQ(c.scenes[1].name, "builtin:cornell:size=100");
  EXPECT_EQ(c.settings.rays, 300u);
  EXPECT_EQ(c.machine.threads, 2);
}

TEST_F(SelectCli, CalibrateMeasuresEveryStructureForThePlannerAndSelectUsesIt) {
  const auto r = visfield("calibrate builtin:boxes:size=8 builtin:sphere:size=300 --rays 300 --sample-rays 100 "
                          "--build-repetitions 1 --threads 2 -o plan.json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("17 structures for the planner"), std::string::npos) << r.out;
  const Calibration c = load_calibration(dir_ / "plan.json");
  ASSERT_EQ(c.scenes.size(), 2u);
  for (const SceneMeasurement& s : c.scenes) {
    ASSERT_EQ(s.plan.candidates.size(), plan_candidates().size()) << s.name;
    EXPECT_GT(s.plan.profile.grid_sample_us[plan_kind_index(RayKind::path)], 0.0) << s.name;
    for (RayKind kind : kRayKinds) EXPECT_GT(s.plan.profile.bvh_sample_us[plan_kind_index(kind)], 0.0) << s.name;
    EXPECT_GT(s.plan.profile.bvh_build_ms, 0.0) << s.name;
    EXPECT_GT(s.plan.find("beam")->update_ms, 0.0) << s.name;  // BeamField moves objects in place: a move was timed
    EXPECT_GT(s.plan.find("bvh:levels=2")->update_ms, 0.0) << s.name;  // and so does the two-level BVH
    EXPECT_LT(s.plan.find("bvh:levels=1")->update_ms, 0.0) << s.name;  // a flattened BVH rebuilds
    EXPECT_LT(s.plan.find("field:positions=1090,directions=16")->ray_us[plan_kind_index(RayKind::random)], 0.0);
    EXPECT_GT(s.plan.find("field:positions=1090,directions=16")->ao_rms, 0.0) << s.name;
  }
  EXPECT_EQ(c.plan.field_error.samples, 16u);  // two scenes x the eight fields other than the probe (whose RMS is measured)
  EXPECT_GT(c.plan.constants[plan_candidate_index("kdtree:levels=1")].ray_us[plan_kind_index(RayKind::ao)], 0.0);

  const auto select = visfield("select builtin:sphere:size=2000 --rays 1e6 --kind random --calibration plan.json --threads 2");
  ASSERT_EQ(select.exit_code, 0) << select.err;
  for (const PlanCandidate& candidate : plan_candidates()) {
    std::string row(" ");
    row.append(candidate.spec).append(" ");
    EXPECT_NE(select.out.find(row), std::string::npos) << candidate.spec << "\n" << select.out;
  }
  for (const char* needle : {"workload:     1000000 random rays, 0 updates, error <= 0", "grid sample:", "candidate", "build ms",
                             "(answers occlusion (ao, shadow) rays only)", "decision:", "why:          lowest predicted total"})
    EXPECT_NE(select.out.find(needle), std::string::npos) << needle << "\n" << select.out;
  // The starred row is the decision.
  const std::size_t star = select.out.find("\n* ");
  ASSERT_NE(star, std::string::npos) << select.out;
  const std::string starred = select.out.substr(star + 3, select.out.find(' ', star + 3) - star - 3);
  EXPECT_NE(select.out.find("decision:     " + starred + "\n"), std::string::npos) << select.out;

  const auto report = visfield("report --from plan.json --splits 2 -o report.md");
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const std::string md = test::read_text_file(dir_ / "report.md");
  for (const char* needle : {"## The planner", "| ao | 8 |", "| path | 0 |", "R = 1e+09", "Overall:", "## Fields sized from a target error",
                             "| builtin:sphere:size=300 |"})
    EXPECT_NE(md.find(needle), std::string::npos) << needle << "\n" << md;
}

TEST_F(SelectCli, SelectWithTheBuiltInCalibrationWeighsFieldsWhenAnErrorIsAllowed) {
  const auto exact = visfield("select builtin:boxes:size=8 --rays 100 --kind ao --threads 2");
  ASSERT_EQ(exact.exit_code, 0) << exact.err;
  EXPECT_NE(exact.out.find("calibration:  built in"), std::string::npos) << exact.out;
  EXPECT_NE(exact.out.find("(approximate; error=0 allows exact structures only)"), std::string::npos) << exact.out;
  // A sphere of 20,000 triangles and a trillion AO rays: the fields' constant-time lookups win.
  const auto loose = visfield("select builtin:sphere --rays 1e12 --kind ao --error 255 --threads 2");
  ASSERT_EQ(loose.exit_code, 0) << loose.err;
  EXPECT_EQ(loose.out.find("(approximate;"), std::string::npos) << loose.out;
  EXPECT_NE(loose.out.find("field probe:  field:positions=1090,directions=16 RMS "), std::string::npos) << loose.out;
  EXPECT_NE(loose.out.find("decision:     field:"), std::string::npos) << loose.out;
}

TEST_F(SelectCli, FieldBuildSizesAFieldFromATargetError) {
  std::ofstream(dir_ / "tet.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const std::string mesh = "tet.obj";
  const auto r = visfield("field build " + mesh + " --target-rms 200 --no-progress --threads 2 -o s.vfield");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The loosest target: the smallest field the planner weighs.
  EXPECT_NE(r.out.find("sized for RMS <= 200: positions=1090, directions=16"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("field: 1090 positions x 16^2"), std::string::npos) << r.out;
  expect_clean_failure("field build " + mesh + " --target-rms 0.01 --threads 2 -o t.vfield",
                       "--target-rms 0.01: no field the planner weighs is expected to meet it");
  expect_clean_failure("field build " + mesh + " --target-rms 3 --positions 1090 -o t.vfield", "excludes", 2);
  expect_clean_failure("field build " + mesh + " --calibration c.json -o t.vfield", "requires", 2);
}

TEST_F(SelectCli, SelectRefusesBadInputWithOneLine) {
  std::ofstream(dir_ / "bad.json") << "{\"format\": \"visfield-calibration\", \"version\": 4}";
  expect_clean_failure("select builtin:boxes --rays 100 --calibration bad.json", "bad.json: version: unsupported version 4");
  expect_clean_failure("select builtin:boxes --rays 100 --calibration missing.json", "missing.json");
  expect_clean_failure("select builtin:boxes --rays 100 --kind diffuse", "--kind", 2);
  expect_clean_failure("select builtin:boxes", "--rays", 2);
  expect_clean_failure("select builtin:boxes --rays 2.5", "--rays");
  expect_clean_failure("select builtin:boxes --rays 100 --error 300", "--error", 2);
  expect_clean_failure("select builtin:boxes --rays 100 --updates 1.5", "--updates");
  expect_clean_failure("select builtin:boxes --rays 100 --kind ao --max-memory 1KiB", "more than --max-memory 1.0 KiB");
}

TEST_F(SelectCli, StatsPrintsTheGridStatistics) {
  const auto r = visfield("stats builtin:stadium:size=2000");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* needle : {"sparseness:", "maxRefs:", "mean:", "variance:", "std dev:", "skewness:", "kurtosis:", "memory:", " x "})
    EXPECT_NE(r.out.find(needle), std::string::npos) << needle << "\n" << r.out;
  // --grid sets the grid's parameters, and only the grid's.
  const auto dense = visfield("stats builtin:stadium:size=2000 --grid grid:density=8");
  ASSERT_EQ(dense.exit_code, 0) << dense.err;
  EXPECT_NE(dense.out.find("grid:density=8,levels=1"), std::string::npos) << dense.out;
  EXPECT_NE(dense.out, r.out);
  expect_clean_failure("stats builtin:boxes --grid bvh", "--grid", 2);
  expect_clean_failure("stats builtin:boxes --grid grid:density=0", "density=0", 2);
  expect_clean_failure("stats builtin:boxes --accel grid", "--accel", 2);
}

TEST_F(SelectCli, CalibrateRefusesAMissingFolderBeforeMeasuring) {
  expect_clean_failure("calibrate builtin:boxes builtin:cornell -o no/such/folder/cal.json", "does not exist");
  expect_clean_failure("calibrate builtin:nosuchscene -o cal2.json", "nosuchscene");
}

TEST_F(SelectCli, ReportWritesTheTablesFromMeasurementsOrAFile) {
  std::ofstream(dir_ / "tet.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const auto r = visfield("report --no-builtin --scene builtin:boxes:size=8 --scene builtin:cornell:size=100 "
                          "--scene builtin:sphere:size=300 --scene " + (dir_ / "tet.obj").string() +
                          " --rays 300 --sample-rays 100 --build-repetitions 1 --no-plan --splits 3 --threads 2"
                          " --save-measurements cal.json -o report.md");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string md = test::read_text_file(dir_ / "report.md");
  for (const char* needle : {"## Table 1", "| builtin:sphere:size=300 |", "| tet.obj | 4 |", "## Leave-k-out", "| 3 |",
                             "## Decision accuracy",
                             "| random | 1e+04 |", "| path | 1e+07 |", "Overall:", "visfield report --scene builtin:boxes:size=8"})
    EXPECT_NE(md.find(needle), std::string::npos) << needle << "\n" << md;
  const auto again = visfield("report --from cal.json --splits 3 -o again.md");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const std::string md2 = test::read_text_file(dir_ / "again.md");
  // Same measurements, same tables (only the quoted command differs).
  EXPECT_EQ(md.substr(md.find("## Table 1")), md2.substr(md2.find("## Table 1")));
  // The quoted command reproduces the report exactly.
  const std::string quoted = md2.substr(md2.find("- Command: `") + 12, md2.find("`\n", md2.find("- Command: `")) - md2.find("- Command: `") - 12);
  ASSERT_EQ(quoted.rfind("visfield report --from cal.json ", 0), 0u) << quoted;
  fs::rename(dir_ / "again.md", dir_ / "first.md");
  const auto rerun = visfield(quoted.substr(std::string("visfield ").size()));
  ASSERT_EQ(rerun.exit_code, 0) << rerun.err;
  EXPECT_EQ(test::read_text_file(dir_ / "again.md"), test::read_text_file(dir_ / "first.md"));
  expect_clean_failure("report --no-builtin --scene builtin:boxes -o r.md", "at least 2 scenes");
  expect_clean_failure("report --from cal.json --models /tmp -o r.md", "excludes", 2);
}

}  // namespace
}  // namespace vf

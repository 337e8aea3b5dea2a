// End-to-end tests of the selection subcommands: calibrate, select, stats, report.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "support/run_command.hpp"
#include "visfield/select/calibration.hpp"

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
  void calibrate_small() {
    const auto r = visfield("calibrate builtin:boxes:size=8 builtin:cornell:size=100 --rays 300 --sample-rays 100 "
                            "--build-repetitions 1 --threads 2 -o cal.json");
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

TEST_F(SelectCli, SelectPrintsEveryQuantityAndTheDecision) {
  calibrate_small();
  const auto r = visfield("select builtin:sphere:size=2000 --rays 1e6 --kind random --calibration cal.json --threads 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* needle : {"triangles N:", "grid:", "sparseness", "kurtosis", "T_B^G (measured):", "t_R^G (sampled):",
                             "T_B^H (estimated):", "t_R^H (estimated):", "R_C:", "decision:"})
    EXPECT_NE(r.out.find(needle), std::string::npos) << needle << "\n" << r.out;
  EXPECT_TRUE(r.out.find("decision:           grid") != std::string::npos ||
              r.out.find("decision:           kdtree") != std::string::npos)
      << r.out;
  const auto builtin = visfield("select builtin:boxes:size=8 --rays 100");
  ASSERT_EQ(builtin.exit_code, 0) << builtin.err;
  EXPECT_NE(builtin.out.find("calibration:        built in"), std::string::npos) << builtin.out;
}

TEST_F(SelectCli, SelectRefusesBadInputWithOneLine) {
  std::ofstream(dir_ / "bad.json") << "{\"format\": \"visfield-calibration\", \"version\": 3}";
  expect_clean_failure("select builtin:boxes --rays 100 --calibration bad.json", "bad.json: version: unsupported version 3");
  expect_clean_failure("select builtin:boxes --rays 100 --calibration missing.json", "missing.json");
  expect_clean_failure("select builtin:boxes --rays 100 --kind diffuse", "--kind", 2);
  expect_clean_failure("select builtin:boxes", "--rays", 2);
  expect_clean_failure("select builtin:boxes --rays 2.5", "--rays");
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
                          " --rays 300 --sample-rays 100 --build-repetitions 1 --splits 3 --threads 2"
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

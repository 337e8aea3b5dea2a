// visfield-bench end to end: the JSON and table it prints, --count, and how it refuses bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/run_command.hpp"

namespace vf {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr bool kHaveEmbree = VISFIELD_BENCH_HAVE_EMBREE != 0;
// A few hundred triangles with a camera: every ray kind has work to do. (Not the Cornell room: there,
// AO and shadow rays leaving a wall next to a corner start exactly on the adjacent wall, a t = 0 hit
// that our structures count and Embree does not, so a few rays legitimately differ from Embree.)
const std::string kScene = "--scene builtin:boxes:size=40 ";
const std::string kSmallRun = "--width 32 --height 24 --reps 2 --warmup 1 --threads 2 ";

// The specs given to --accel and the names the rows carry (the spec as resolved).
std::vector<std::pair<std::string, std::string>> structures() {
  std::vector<std::pair<std::string, std::string>> specs{
      {"bvh", "bvh:levels=1"}, {"bvh:leaf=4,levels=2", "bvh:leaf=4,levels=2"}, {"brute", "brute:levels=1"}};
  if (kHaveEmbree) {
    specs.emplace_back("embree", "embree:levels=1");
    specs.emplace_back("embree:levels=2", "embree:levels=2");
  }
  return specs;
}

std::string accel_option() {
  std::string list;
  for (const auto& [spec, name] : structures()) list += (list.empty() ? "" : ",") + spec;
  return "--accel " + list + " ";
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

class BenchCli : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    for (char& c : name) c = c == '/' ? '_' : c;
    dir_ = fs::path(VISFIELD_TEST_BINARY_DIR) / "bench-work" / name;
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  test::CommandResult bench(const std::string& args) {
    return test::run_command(std::string(VISFIELD_BENCH_EXE) + " " + args, dir_);
  }
  json bench_json(const std::string& args) {
    const auto r = bench(args + " --json");
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
    EXPECT_EQ(r.err, "") << args;
    return json::parse(r.out);
  }
  // Bad input: status `status`, nothing on stdout, one line on stderr naming `needle`, no file written.
  void expect_refused(const std::string& args, int status, const std::string& needle) {
    const auto r = bench(args);
    EXPECT_EQ(r.exit_code, status) << args << "\n" << r.err;
    EXPECT_EQ(r.out, "") << args;
    EXPECT_EQ(test::line_count(r.err), 1) << args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("visfield-bench: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << "\n" << r.err;
    EXPECT_TRUE(fs::is_empty(dir_)) << "left a file behind: " << args;
  }
  fs::path dir_;
};

class BenchCliKinds : public BenchCli, public ::testing::WithParamInterface<const char*> {};

TEST_P(BenchCliKinds, JsonHasOneAgreeingRecordPerStructure) {
  const std::string kind = GetParam();
  const json doc = bench_json(kScene + kSmallRun + accel_option() + "--rays " + kind);
  EXPECT_EQ(doc.at("kind"), kind);
  EXPECT_TRUE(doc.at("scene").is_string());
  EXPECT_GT(doc.at("triangles").get<long>(), 400);
  EXPECT_GT(doc.at("rays").get<long>(), 0);
  EXPECT_EQ(doc.at("threads"), 2);
  const json& results = doc.at("results");
  const auto specs = structures();
  ASSERT_EQ(results.size(), specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const json& row = results[i];
    const std::string& name = specs[i].second;
    SCOPED_TRACE(name);
    EXPECT_EQ(row.at("accel"), name);
    EXPECT_GT(row.at("build_ms").get<double>(), 0.0);
    EXPECT_GT(row.at("bytes").get<long>(), 0);
    EXPECT_GT(row.at("mrays_per_s").get<double>(), 0.0);
    EXPECT_EQ(row.at("mismatches"), 0);
    if (kHaveEmbree) {
      EXPECT_GT(row.at("ratio_to_embree").get<double>(), 0.0);
      if (name == "embree:levels=1") {
        EXPECT_DOUBLE_EQ(row.at("ratio_to_embree").get<double>(), 1.0);
      }
    } else {
      EXPECT_TRUE(row.at("ratio_to_embree").is_null());
    }
  }
  EXPECT_EQ(doc.at("reference"), kHaveEmbree ? "embree:levels=1" : "bvh:levels=1");
}

INSTANTIATE_TEST_SUITE_P(EveryRayKind, BenchCliKinds, ::testing::Values("primary", "ao", "shadow", "random"));

TEST_F(BenchCli, CountGivesExactlyThatManyRaysFewerOrMoreThanTheImageHas) {
  // 32x24 = 768 pixels: 500 subsamples the primary rays, 3000 needs a larger image.
  for (const auto& [kind, count] : std::vector<std::pair<std::string, int>>{
           {"primary", 500}, {"primary", 3000}, {"ao", 1000}, {"shadow", 300}, {"random", 777}}) {
    const json doc =
        bench_json(kScene + kSmallRun + "--accel bvh --rays " + kind + " --count " + std::to_string(count));
    EXPECT_EQ(doc.at("rays"), count) << kind;
  }
}

// --ray-order line: the AO rays along the lines, grouped by line, through every structure (Embree
// in packets too), all agreeing; the same number of rays as in pixel order.
TEST_F(BenchCli, LineOrderGivesEveryStructureTheSameStreams) {
  const std::string accels = std::string("beam:dirs=33,n=16,median-bsp,bvh") + (kHaveEmbree ? ",embree,embree:call=16" : "");
  const std::string run = kScene + kSmallRun + "--rays ao --ao-directions 33 --accel " + accels;
  const json by_line = bench_json(run + " --ray-order line");
  const json by_pixel = bench_json(run);
  EXPECT_EQ(by_line.at("rays"), by_pixel.at("rays"));
  EXPECT_GT(by_line.at("rays").get<int>(), 1000);
  ASSERT_EQ(by_line.at("results").size(), kHaveEmbree ? 5u : 3u);
  for (const json& row : by_line.at("results")) EXPECT_EQ(row.at("mismatches"), 0) << row.at("accel");
}

// embree:call=best tries every call at both build qualities and shows the fastest as one row; the
// report names "Embree best" and gives each row's ratio to it (1 for that row).
TEST_F(BenchCli, EmbreeBestIsTheFastestOfItsCallsAndQualities) {
  if (!kHaveEmbree) GTEST_SKIP() << "this build has no Embree";
  const json doc = bench_json(kScene + kSmallRun + "--rays ao --accel bvh,embree:call=best");
  const json& results = doc.at("results");
  ASSERT_EQ(results.size(), 2u);
  const std::string best = results[1].at("accel");
  EXPECT_EQ(best.rfind("embree:call=best -> levels=1", 0), 0u) << best;
  EXPECT_EQ(doc.at("embree_best"), best);
  EXPECT_DOUBLE_EQ(results[1].at("ratio_to_embree_best").get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(results[0].at("ratio_to_embree_best").get<double>(), results[0].at("ratio_to_embree").get<double>());
  for (const json& row : results) EXPECT_EQ(row.at("mismatches"), 0) << row.at("accel");
}

// Our structures one ray at a time (call=1): the same answers as their batch path, bit for bit, in a
// row of their own named by the spec as resolved.
TEST_F(BenchCli, OneRayAtATimeIsARowOfItsOwnWithTheBatchsAnswers) {
  const json doc = bench_json(kScene + kSmallRun + "--rays ao --accel bvh,bvh:call=1,kdtree:call=1");
  const json& results = doc.at("results");
  ASSERT_EQ(results.size(), 3u);
  EXPECT_EQ(results[0].at("accel"), "bvh:levels=1");
  EXPECT_EQ(results[1].at("accel"), "bvh:levels=1,call=1");
  EXPECT_EQ(results[2].at("accel").get<std::string>().rfind("kdtree:", 0), 0u);
  EXPECT_NE(results[2].at("accel").get<std::string>().find(",call=1"), std::string::npos);
  for (const json& row : results) EXPECT_EQ(row.at("mismatches"), 0) << row.at("accel");
}

TEST_F(BenchCli, TableHasHeaderColumnsAndOneRowPerStructure) {
  const auto r = bench(kScene + kSmallRun + accel_option() + "--rays ao");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = lines_of(r.out);
  const auto specs = structures();
  // Header, column titles, a row per structure, with two Embree rows the line naming the fastest
  // ("Embree best"), then the flattened bvh's work per ray (the only structure here with counters:
  // bvh:levels=2 is an instance layer).
  ASSERT_EQ(lines.size(), 2 + specs.size() + (kHaveEmbree ? 1 : 0) + 1) << r.out;
  if (kHaveEmbree) {
    EXPECT_EQ(lines[2 + specs.size()].rfind("Embree best for ao rays: embree:levels=", 0), 0u) << r.out;
  }
  EXPECT_EQ(lines.back().rfind("bvh:levels=1 work per ray: ", 0), 0u) << lines.back();
  EXPECT_NE(lines.back().find(" nodes, "), std::string::npos) << lines.back();
  EXPECT_NE(lines[0].find("triangles"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("ao rays"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("threads 2"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find(kHaveEmbree ? "Embree 3." : "Embree not run"), std::string::npos) << lines[0];
  for (const char* column : {"accel", "build ms", "bytes", "Mrays/s", "ratio to Embree", "mismatches"}) {
    EXPECT_NE(lines[1].find(column), std::string::npos) << column;
  }
  for (std::size_t i = 0; i < specs.size(); ++i)
    EXPECT_EQ(lines[2 + i].rfind(specs[i].second + " ", 0), 0u) << lines[2 + i];
}

TEST_F(BenchCli, BadCommandLineValuesExitWithStatus2AndOneLine) {
  const std::string base = kScene + "--rays primary ";
  expect_refused(base + "--accel bvh --count 0", 2, "--count");
  expect_refused(base + "--accel bvh --count -3", 2, "--count");
  expect_refused(base + "--accel bvh --count lots", 2, "--count");
  expect_refused(base + "--accel bvh --count 99999999999", 2, "--count");
  expect_refused(base + "--accel bvh --threads -1", 2, "--threads");
  expect_refused(base + "--accel bvh --threads 100000", 2, "--threads");
  expect_refused(base + "--accel bvh --reps 0", 2, "--reps");
  expect_refused(base + "--accel bvh --width 0", 2, "--width");
  expect_refused(base + "--accel bvh --ao-rays 0", 2, "--ao-rays");
  expect_refused(base + "--accel bvh,octree", 2, "octree");
  expect_refused(base + "--accel bvh:leaf=0", 2, "leaf=0");
  expect_refused(base + "--accel bvh:leef=4", 2, "unknown key 'leef'");
  expect_refused(base + "--accel bvh,,grid", 2, "empty structure name");
  expect_refused(base + "--accel bvh,bvh", 2, "twice");
  expect_refused(base + "--accel bvh --unknown-flag", 2, "--unknown-flag");
  expect_refused(kScene + "--rays sideways --accel bvh", 2, "--rays");
  expect_refused("--rays primary --accel bvh", 2, "--scene");
  expect_refused(kScene + "--rays primary", 2, "--accel");
}

// --dynamic: an updatable structure is edited in place, the others rebuilt, and after the frames both
// answer exactly as a fresh build of the moved scene.
TEST_F(BenchCli, DynamicMovesAnObjectAndUpdatesOrRebuilds) {
  const json doc = bench_json(
      "--scene builtin:boxes:size=12 --rays primary --accel beam:dirs=33,n=16,bvh:levels=1,bvh:levels=2 --count 3000 "
      "--threads 2 --dynamic 3");
  EXPECT_EQ(doc.at("frames"), 3);
  EXPECT_EQ(doc.at("rays"), 3000);
  EXPECT_GT(doc.at("moved_triangles").get<int>(), 0);
  const json& results = doc.at("results");
  ASSERT_EQ(results.size(), 3u);
  EXPECT_TRUE(results[0].at("incremental").get<bool>());   // beam
  EXPECT_FALSE(results[1].at("incremental").get<bool>());  // bvh:levels=1 is rebuilt
  EXPECT_TRUE(results[2].at("incremental").get<bool>());   // bvh:levels=2 updates its top level
  for (const json& row : results) {
    EXPECT_EQ(row.at("mismatches"), 0) << row.dump();
    EXPECT_GT(row.at("rebuild_ms").get<double>(), 0.0) << row.dump();
    EXPECT_GT(row.at("trace_ms").get<double>(), 0.0) << row.dump();
  }
  const auto table = bench("--scene builtin:boxes:size=12 --rays primary --accel beam:dirs=33,n=16 --count 1000 --dynamic 2");
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("update/rebuild"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("moves"), std::string::npos) << table.out;
}

TEST_F(BenchCli, DynamicRefusesBadObjectsAndFrames) {
  const std::string base = "--scene builtin:boxes:size=12 --rays primary --accel bvh --count 100 ";
  expect_refused(base + "--dynamic 0", 2, "--dynamic");
  expect_refused(base + "--move-object 3", 2, "--move-object");
  expect_refused(base + "--dynamic 2 --move-object 100000", 1, "no object 100000");
}

// --walk: the same walkthrough through each structure (Embree too when linked), a table, the CSVs and
// the plot; a scene that does not move is refused.
TEST_F(BenchCli, WalkTimesEveryStructureOnTheSameFrames) {
  const fs::path scene = fs::path(VISFIELD_SOURCE_DIR) / "examples" / "scenes" / "walk.json";
  fs::create_directories(dir_ / "csv");
  const std::string accels = std::string("beam:dirs=33,n=16,bvh") + (kHaveEmbree ? ",embree" : "");
  const auto r = bench("--walk 4 --scene " + scene.string() + " --accel " + accels +
                       " --integrator whitted --width 32 --height 20 --walk-csv csv --walk-plot walk.svg");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("| beam:dirs=33,n=16 |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| bvh:levels=1 |"), std::string::npos) << r.out;
  if (kHaveEmbree) {
    EXPECT_NE(r.out.find("| embree:levels=1 | "), std::string::npos) << r.out;
  }
  EXPECT_TRUE(fs::exists(dir_ / "csv" / "bvh_levels_1.csv"));
  EXPECT_TRUE(fs::exists(dir_ / "walk.svg"));
}

TEST_F(BenchCli, WalkRefusesStillScenesAndBadFrames) {
  const fs::path scene = fs::path(VISFIELD_SOURCE_DIR) / "examples" / "scenes" / "walk.json";
  expect_refused("--walk 4 --scene builtin:boxes:size=12 --accel bvh", 1, "nothing moves");
  expect_refused("--walk 1 --scene " + scene.string() + " --accel bvh", 2, "--walk");
  expect_refused(kScene + "--rays primary --accel bvh --walk-plot p.svg", 2, "only with --walk");
  expect_refused(kScene + "--rays primary --accel bvh --integrator path", 2, "only with --walk");
}

TEST_F(BenchCli, EmbreeWithoutEmbreeIsAUsageError) {
  if (kHaveEmbree) GTEST_SKIP() << "this build links Embree";
  expect_refused(kScene + "--rays primary --accel bvh,embree", 2, "Embree");
}

TEST_F(BenchCli, SceneThatCannotBeLoadedExitsWithStatus1) {
  expect_refused("--scene missing.obj --rays primary --accel bvh", 1, "missing.obj");
  expect_refused("--scene builtin:no_such_scene --rays primary --accel bvh", 1, "no_such_scene");
}

TEST_F(BenchCli, HelpListsTheOptionsAndSucceeds) {
  const auto r = bench("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* option : {"--scene", "--rays", "--accel", "--count", "--threads", "--json", "--reps", "--warmup"}) {
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
  }
}

}  // namespace
}  // namespace vf

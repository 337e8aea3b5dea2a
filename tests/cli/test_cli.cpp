// End-to-end tests of the visfield command line: what a user types, what comes out.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "support/run_command.hpp"
#include "visfield/field/field_params.hpp"
#include "visfield/io/image_io.hpp"
#include "visfield/registry/render_scene.hpp"

namespace vf {
namespace {

namespace fs = std::filesystem;
using test::run_command;

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(VISFIELD_TEST_BINARY_DIR) / "cli-work" /
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  test::CommandResult visfield(const std::string& args) { return run_command(std::string(VISFIELD_EXE) + " " + args, dir_); }
  // Bad input: non-zero exit, exactly one line on stderr mentioning `needle`, and no files left behind.
  void expect_clean_failure(const std::string& args, const std::string& needle) {
    const auto r = visfield(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(test::line_count(r.err), 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << "\n" << r.err;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_TRUE(name.ends_with(".obj") || name.ends_with(".json")) << "left behind: " << name << " by " << args;
    }
  }
  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
  fs::path dir_;
};

TEST_F(Cli, RendersBuiltinSceneToPngAndReportsRaysPerSecond) {
  const auto r = visfield("render builtin:cornell --width 48 --height 32 --ao-rays 8 --out ao.png --no-progress");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("wrote "), std::string::npos);
  EXPECT_NE(r.out.find("Mrays/s"), std::string::npos);
  const Image image = read_image(dir_ / "ao.png");
  EXPECT_EQ(image.width, 48);
  EXPECT_EQ(image.height, 32);
  // An AO image of a closed room is neither all black nor all white.
  float lo = 1.0f, hi = 0.0f;
  for (const Vec3f& p : image.pixels) {
    lo = std::min(lo, p.x);
    hi = std::max(hi, p.x);
  }
  EXPECT_LT(lo, 0.5f);
  EXPECT_GT(hi, 0.5f);
}

TEST_F(Cli, ImageDoesNotDependOnThreadCount) {
  const std::string common = "render builtin:boxes:size=8 --width 40 --height 30 --ao-rays 6 --no-progress --out ";
  ASSERT_EQ(visfield(common + "one.exr --threads 1").exit_code, 0);
  ASSERT_EQ(visfield(common + "two.exr --threads 2").exit_code, 0);
  const Image a = read_image(dir_ / "one.exr"), b = read_image(dir_ / "two.exr");
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  for (std::size_t i = 0; i < a.pixels.size(); ++i) ASSERT_EQ(a.pixels[i], b.pixels[i]) << "pixel " << i;
}

TEST_F(Cli, OcclusionRaysCanGoToAnotherStructure) {
  // Exact structures over the same triangles agree on every ray, so the images are identical; the
  // summary names both structures.
  const std::string common = "render builtin:cornell:size=200 --width 40 --height 30 --ao-rays 6 --no-progress --out ";
  ASSERT_EQ(visfield(common + "bvh.exr").exit_code, 0);
  const auto r = visfield(common + "split.exr --accel bvh --occluder kdtree:kt=10");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("accel bvh:levels=1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("occluder kdtree:kt=10,levels=1"), std::string::npos) << r.out;
  EXPECT_EQ(read_image(dir_ / "bvh.exr").pixels, read_image(dir_ / "split.exr").pixels);
}

TEST_F(Cli, FieldOccludersRenderCloseToTheExactImage) {
  const std::string common = "render builtin:cornell:size=400 --width 48 --height 36 --ao-rays 16 --no-progress --out ";
  ASSERT_EQ(visfield(common + "exact.exr").exit_code, 0);
  const auto r = visfield(common + "field.exr --occluder field:positions=1090,directions=16");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("occluder field:"), std::string::npos) << r.out;
  const Image exact = read_image(dir_ / "exact.exr"), field = read_image(dir_ / "field.exr");
  ASSERT_EQ(exact.pixels.size(), field.pixels.size());
  double sum_sq = 0.0;
  bool differs = false;
  for (std::size_t i = 0; i < exact.pixels.size(); ++i) {
    const double d = exact.pixels[i].x - field.pixels[i].x;
    sum_sq += d * d;
    differs = differs || d != 0.0;
  }
  EXPECT_TRUE(differs);  // the fields did answer the AO rays
  EXPECT_LT(std::sqrt(sum_sq / static_cast<double>(exact.pixels.size())), 0.05);
}

TEST_F(Cli, OccludersSwitchAWholeRenderBetweenFieldsAndExactGeometry) {
  const std::string common = "render builtin:cornell:size=400 --width 32 --height 24 --ao-rays 8 --no-progress --integrator ao --out ";
  auto r = visfield(common + "field.png --occluders field");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("occluder field"), std::string::npos) << r.out;
  r = visfield(common + "field2.png --occluders field --occluder field:positions=290,directions=8");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("occluder field:positions=290,directions=8"), std::string::npos) << r.out;
  r = visfield(common + "exact.png --occluders exact");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("occluder"), std::string::npos) << r.out;  // the --accel BVH answers the AO rays
  r = visfield(common + "bad.png --occluders exact --occluder field");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--occluders exact needs an exact structure"), std::string::npos) << r.err;
  r = visfield(common + "bad.png --occluders field --occluder grid");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--occluders field needs a field"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "bad.png"));
}

// Every integrator renders from the command line, names its output after itself by default and
// reports its rays by kind; the shading ones run with field occluders too.
TEST_F(Cli, EveryIntegratorRendersAndReportsItsRaysByKind) {
  for (const std::string integrator : {"raycast", "whitted", "ao", "softshadow", "glossy", "path"}) {
    const auto r = visfield("render builtin:cornell:size=400 --width 16 --height 12 --no-progress --integrator " + integrator +
                            (integrator == "ao" ? " --ao-rays 4" : ""));
    ASSERT_EQ(r.exit_code, 0) << integrator << ": " << r.err;
    EXPECT_TRUE(fs::exists(dir_ / ("visfield-" + integrator + ".png"))) << integrator;
    EXPECT_NE(r.out.find("rays (camera 192, shadow "), std::string::npos) << r.out;
  }
  const auto r = visfield("render builtin:cornell:size=400 --width 16 --height 12 --no-progress --integrator softshadow "
                          "--occluders field --occluder field:positions=290,directions=8 --out soft.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("occluder field:positions=290,directions=8"), std::string::npos) << r.out;
}

// `visfield walk` renders a scene's walkthrough, writes its frame times as CSV and plots them beside
// another run's; what it cannot do it refuses before the first frame.
TEST_F(Cli, WalkWritesFrameTimesAndAPlot) {
  write("tetra.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  // A ground around the moving tetrahedron keeps it inside the scene's sphere, so BeamField moves it in place.
  write("ground.obj", "v -3 -0.01 -3\nv 3 -0.01 -3\nv 3 -0.01 3\nv -3 -0.01 3\nf 1 3 2\nf 1 4 3\n");
  write("walk.json", R"({"meshes": [{"name": "t", "path": "tetra.obj"}, {"name": "g", "path": "ground.obj"}],
    "instances": [{"mesh": "g"}, {"mesh": "t", "keyframes": [{"time": 0}, {"time": 1, "translate": [0.5, 0, 0], "rotate_euler_deg": [0, 45, 0]}]}],
    "camera_path": [{"time": 0, "position": [0, 1, 4], "look_at": [0, 0.3, 0]}, {"time": 1, "position": [3, 1, 3], "look_at": [0, 0.3, 0]}]})");
  const std::string common = "walk walk.json --frames 6 --width 24 --height 16 --no-progress ";
  auto r = visfield(common + "--csv bvh.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("walk: 6 frames of 24x16, bvh:levels=1"), std::string::npos) << r.out;
  r = visfield(common + "--accel beam:dirs=33,n=16 --integrator whitted --csv beam.csv --plot walk.svg --plot-with bvh.csv "
               "--frames-dir .");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("(0 rebuilds)"), std::string::npos) << r.out;  // BeamField moved the object in place
  EXPECT_TRUE(fs::exists(dir_ / "walk.svg"));
  EXPECT_TRUE(fs::exists(dir_ / "frame-00005.png"));
  std::ifstream csv(dir_ / "beam.csv");
  std::string line;
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 2 + 6);  // title, header, one row per frame

  write("still.json", R"({"meshes": [{"path": "tetra.obj"}]})");
  r = visfield("walk still.json --no-progress --csv still.csv");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("still.json: the scene has no \"camera_path\""), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "still.csv"));
  EXPECT_EQ(visfield(common + "--frames 1").exit_code, 2);
  EXPECT_EQ(visfield(common + "--plot-with bvh.csv").exit_code, 2);
  write("junk.csv", "not a walk\n");
  r = visfield(common + "--csv again.csv --plot p.svg --plot-with junk.csv");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("junk.csv: line 1: not a visfield walk CSV"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "again.csv"));
}

// A scene file that marks a mesh "occluder": "field" renders its AO through that mesh's field (with
// its own parameters) and the other meshes exact, unless --occluders exact says otherwise.
TEST_F(Cli, ASceneMarksWhichMeshesAreFields) {
  write("tetra.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  write("ground.obj", "v -3 -0.01 -3\nv 3 -0.01 -3\nv 3 -0.01 3\nv -3 -0.01 3\nf 1 3 2\nf 1 4 3\n");
  write("scene.json", R"({"meshes": [{"path": "tetra.obj", "occluder": "field", "field": {"positions": 290, "directions": 8}},
                                     {"path": "ground.obj"}]})");
  const std::string common = "render scene.json --width 24 --height 24 --ao-rays 8 --no-progress --out ";
  auto r = visfield(common + "marked.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("occluder field:meshes=marked"), std::string::npos) << r.out;
  r = visfield(common + "exact.png --occluders exact");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("occluder"), std::string::npos) << r.out;
  write("bad.json", R"({"meshes": [{"path": "tetra.obj", "occluder": "field", "field": {"directions": 5}}]})");
  r = visfield("render bad.json --width 8 --height 8 --no-progress --out bad.png");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(test::line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("mesh tetra: field: directions=5: expected"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "bad.png"));
}

// A "T" standing on +Z (a post with a bar on top), as a scan with +Z up is, in OBJ.
std::string z_up_t_obj() {
  std::string obj;
  int first = 1;
  for (const auto& [lo, hi] : {std::pair{Vec3f{-0.3f, -0.3f, 0.0f}, Vec3f{0.3f, 0.3f, 3.0f}}, std::pair{Vec3f{-1.5f, -0.3f, 3.0f}, Vec3f{1.5f, 0.3f, 3.4f}}}) {
    for (int c = 0; c < 8; ++c)
      obj += "v " + std::to_string((c & 1) ? hi.x : lo.x) + " " + std::to_string((c & 2) ? hi.y : lo.y) + " " + std::to_string((c & 4) ? hi.z : lo.z) + "\n";
    for (const auto& f : {std::array{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1}, {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}})
      obj += "f " + std::to_string(first + f[0]) + " " + std::to_string(first + f[1]) + " " + std::to_string(first + f[2]) + "\n";
    first += 8;
  }
  return obj;
}

// The covered pixels' bounding rectangle: the larger of its width and height as a fraction of the image.
double alpha_fill(const Image& image, bool& touches_border) {
  int x0 = image.width, y0 = image.height, x1 = -1, y1 = -1;
  touches_border = false;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (image.alpha[static_cast<std::size_t>(y) * image.width + x] > 0.0f) {
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        touches_border = touches_border || x == 0 || y == 0 || x == image.width - 1 || y == image.height - 1;
      }
  return x1 < 0 ? 0.0 : std::max(static_cast<double>(x1 - x0 + 1) / image.width, static_cast<double>(y1 - y0 + 1) / image.height);
}

TEST_F(Cli, RenderFramesAMeshFromTheGivenUpAndViewOnATransparentBackground) {
  write("t.obj", z_up_t_obj());
  const auto r = visfield("render t.obj --up z --view 45,30 --background transparent --out x.png --width 80 --height 60 --ao-rays 8 --no-progress");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Image image = read_image(dir_ / "x.png");
  ASSERT_EQ(image.alpha.size(), image.pixels.size()) << "the PNG has an alpha channel";
  bool border = true;
  const double fill = alpha_fill(image, border);
  EXPECT_GE(fill, 0.5);
  EXPECT_LE(fill, 0.95);
  EXPECT_FALSE(border);
  std::size_t clear = 0, solid = 0;
  for (std::size_t i = 0; i < image.alpha.size(); ++i) {
    clear += image.alpha[i] == 0.0f, solid += image.alpha[i] == 1.0f;
    if (image.alpha[i] == 0.0f) {
      EXPECT_EQ(image.pixels[i].x, 0.0f);
    }
  }
  EXPECT_EQ(clear + solid, image.alpha.size()) << "one sample a pixel: covered or not";
  EXPECT_GT(clear, image.alpha.size() / 5);
  EXPECT_GT(solid, image.alpha.size() / 10);

  // The default: the same framing from the three-quarter view, opaque on a background apart from the mesh.
  ASSERT_EQ(visfield("render t.obj --background transparent --out clear.png --width 80 --height 60 --ao-rays 8 --no-progress").exit_code, 0);
  ASSERT_EQ(visfield("render t.obj --out default.png --width 80 --height 60 --ao-rays 8 --no-progress").exit_code, 0);
  const Image mask = read_image(dir_ / "clear.png"), shown = read_image(dir_ / "default.png");
  EXPECT_TRUE(shown.alpha.empty());
  const double default_fill = alpha_fill(mask, border);
  EXPECT_GE(default_fill, 0.5);
  EXPECT_LE(default_fill, 0.95);
  double object = 0.0, background = 0.0;
  std::size_t objects = 0;
  for (std::size_t i = 0; i < mask.alpha.size(); ++i) {
    if (mask.alpha[i] == 1.0f) object += shown.pixels[i].x, ++objects;
    if (mask.alpha[i] == 0.0f) background = std::max(background, static_cast<double>(shown.pixels[i].x));
  }
  EXPECT_GT(object / static_cast<double>(objects), background + 0.3) << "the mesh stands apart from the background";

  // A placed camera: FROM,TO[,UP[,FOV]].
  ASSERT_EQ(visfield("render t.obj --camera 0,-9,2,0,0,1.7,0,0,1,40 --out placed.exr --width 40 --height 30 --ao-rays 2 --no-progress").exit_code, 0);
  EXPECT_EQ(read_image(dir_ / "placed.exr").width, 40);
}

TEST_F(Cli, CompareReportsTheErrorAndWritesTheExaggeratedDifference) {
  const std::string common = "render builtin:cornell:size=400 --width 32 --height 24 --ao-rays 8 --no-progress --out ";
  ASSERT_EQ(visfield(common + "exact.png").exit_code, 0);
  ASSERT_EQ(visfield(common + "field.png --occluder field:positions=290,directions=16").exit_code, 0);
  const auto same = visfield("compare exact.png exact.png");
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_NE(same.out.find("rms:  0 (0-255), 0 (0-1)"), std::string::npos) << same.out;
  const auto r = visfield("compare field.png exact.png --diff diff.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* needle : {"rms:  ", "(0-255)", "max:  ", "psnr: ", "differences x5"})
    EXPECT_NE(r.out.find(needle), std::string::npos) << needle << "\n" << r.out;
  EXPECT_EQ(r.out.find("rms:  0 (0-255)"), std::string::npos) << r.out;
  const Image diff = read_image(dir_ / "diff.png");
  EXPECT_EQ(diff.width, 32);
  ASSERT_EQ(visfield("render builtin:cornell --width 16 --height 12 --ao-rays 1 --no-progress --out small.png").exit_code, 0);
  const auto mismatch = visfield("compare small.png exact.png");
  EXPECT_EQ(mismatch.exit_code, 1);
  EXPECT_EQ(std::count(mismatch.err.begin(), mismatch.err.end(), '\n'), 1) << mismatch.err;
}

TEST_F(Cli, FieldFilesAreBuiltAndDescribed) {
  write("tetra.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n");
  const auto built = visfield("field build tetra.obj --positions 290 --directions 16 --mapping polar --storage u16 -o tetra.vfield");
  ASSERT_EQ(built.exit_code, 0) << built.err;
  EXPECT_NE(built.out.find("290 positions x 16^2 polar u16 cells of 4 triangles"), std::string::npos) << built.out;
  const auto info = visfield("field info tetra.vfield");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  for (const char* needle : {"positions:   290", "directions:  16 x 16 polar", "storage:     u16", "hit cells:", "mesh hash:"})
    EXPECT_NE(info.out.find(needle), std::string::npos) << needle << "\n" << info.out;
  for (const char* bad : {"field build tetra.obj --directions 7 -o a.vfield", "field build tetra.obj --positions 300 -o a.vfield",
                          "field build tetra.obj -o a.png", "field build tetra.obj --storage u4 -o a.vfield"}) {
    const auto r = visfield(bad);
    EXPECT_NE(r.exit_code, 0) << bad;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << bad << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "a.vfield"));
  write("cut.vfield", test::read_text_file(dir_ / "tetra.vfield").substr(0, 100));
  const auto cut = visfield("field info cut.vfield");
  EXPECT_EQ(cut.exit_code, 1);
  EXPECT_NE(cut.err.find("cut.vfield: checksum mismatch"), std::string::npos) << cut.err;
}

TEST_F(Cli, StructuresListsTheRegistry) {
  const auto r = visfield("structures");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* needle : {"bvh (exact", "grid (exact", "kdtree (exact", "median-bsp (exact", "brute (exact", "auto (exact", "field (approximate",
                             "levels=auto", "leaf=8", "density=2"})
    EXPECT_NE(r.out.find(needle), std::string::npos) << needle << "\n" << r.out;
}

TEST_F(Cli, InfoPrintsCountsAndStructureMemory) {
  const auto r = visfield("info builtin:soup:size=500,seed=3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("500 kept"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("memory:"), std::string::npos);
  EXPECT_NE(r.out.find("degenerate:"), std::string::npos);
}

TEST_F(Cli, InfoPrintsBeamFieldStatistics) {
  const auto r = visfield("info builtin:soup:size=500,seed=3 --accel beam:dirs=33,n=16");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* needle : {"33 lines x 16x16 tiles", "per direction:", "refs/triangle:", "empty tiles:"})
    EXPECT_NE(r.out.find(needle), std::string::npos) << needle << "\n" << r.out;
  EXPECT_EQ(visfield("info builtin:soup:size=500,seed=3 --accel bvh").out.find("refs/triangle:"), std::string::npos);
}

TEST_F(Cli, WarnsAboutDegenerateTriangles) {
  write("flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n");
  const auto r = visfield("info flat.obj");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("1 zero-area triangles"), std::string::npos) << r.err;
}

TEST_F(Cli, BadCommandLinesFailWithOneLine) {
  expect_clean_failure("render builtin:cornell --ao-rays 0", "--ao-rays");
  expect_clean_failure("render builtin:cornell --spp -3", "--spp");
  expect_clean_failure("render builtin:cornell --width abc", "--width");
  expect_clean_failure("render builtin:cornell --accel octree", "--accel");
  expect_clean_failure("render builtin:cornell --accel bvh:leaf=0", "leaf=0");
  expect_clean_failure("render builtin:cornell --occluder grid:density", "--occluder");
  expect_clean_failure("render builtin:cornell --integrator phong", "--integrator");
  expect_clean_failure("render builtin:cornell --integrator path --depth 0", "--depth");
  expect_clean_failure("render builtin:cornell --integrator softshadow --shadow-rays 0", "--shadow-rays");
  expect_clean_failure("render builtin:cornell --integrator glossy --glossy-rays -2", "--glossy-rays");
  expect_clean_failure("render builtin:cornell --integrator raycast --ambient -0.5", "--ambient");
  expect_clean_failure("render builtin:cornell --integrator path --ao-rays 8", "--ao-rays: only for --integrator ao");
  expect_clean_failure("render builtin:cornell --integrator whitted --shadow-rays 8", "--shadow-rays: only for --integrator softshadow");
  expect_clean_failure("render builtin:cornell --depth 3", "--depth: only for --integrator whitted, path");
  expect_clean_failure("walk builtin:cornell --max-distance 2", "--max-distance: only for --integrator ao");
  expect_clean_failure("render builtin:cornell --max-distance -1", "--max-distance");
  expect_clean_failure("render builtin:cornell --out picture.bmp", "picture.bmp");
  expect_clean_failure("render", "scene");
  expect_clean_failure("frobnicate", "frobnicate");
}

TEST_F(Cli, BadInputFilesFailWithOneLineAndNoOutput) {
  expect_clean_failure("render missing.ply --out x.png", "missing.ply");
  write("bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  expect_clean_failure("render bad_index.obj --out x.png --no-progress", "bad_index.obj");
  write("nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  expect_clean_failure("render nan.obj --out x.png --no-progress", "nan.obj");
  write("broken.json", "{\"meshes\": [");
  expect_clean_failure("render broken.json --out x.png --no-progress", "broken.json");
  expect_clean_failure("render builtin:nosuchscene --out x.png", "nosuchscene");
  expect_clean_failure("render builtin:soup:size=banana --out x.png", "size");
}

TEST_F(Cli, UnwritableOutputFailsCleanly) {
  expect_clean_failure("render builtin:boxes:size=2 --width 8 --height 8 --ao-rays 1 --no-progress --out no/such/dir/x.png",
                       "x.png");
}

TEST_F(Cli, EveryRenderSettingAndFieldParameterIsAnOptionWithTheTablesDefault) {
  // The options are generated from the library's tables (render_setting_specs(), field::kTableParams):
  // each appears in --help as "--option TEXT=default" with its range in its help.
  const auto render = visfield("render --help");
  ASSERT_EQ(render.exit_code, 0) << render.err;
  for (const RenderSettingSpec& spec : render_setting_specs()) {
    std::string option = std::string("--").append(spec.param.key);
    std::replace(option.begin(), option.end(), '_', '-');
    const std::size_t at = render.out.find(option + " ");
    ASSERT_NE(at, std::string::npos) << option << " missing from render --help";
    const std::string line = render.out.substr(at, render.out.find('\n', at) - at);
    EXPECT_NE(line.find(std::string("=").append(spec.param.default_value)), std::string::npos) << line;
  }
  const auto field = visfield("field build --help");
  ASSERT_EQ(field.exit_code, 0) << field.err;
  for (const ParamSpec& param : field::kTableParams) {
    const std::size_t at = field.out.find(std::string("--").append(param.key).append(" "));
    ASSERT_NE(at, std::string::npos) << param.key << " missing from field build --help";
    const std::string line = field.out.substr(at, field.out.find('\n', at) - at);
    EXPECT_NE(line.find(std::string("=").append(param.default_value)), std::string::npos) << line;
  }
  // A value out of a range is refused with the library's wording.
  const auto r = visfield("render builtin:cornell --ao-rays 0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--ao-rays: 0: expected a non-negative integer in 1..65536"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace vf

// Memory estimates and limits of the registry's builds, and their interruption by SIGINT/SIGTERM.

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>

#include "differential/structure_specs.hpp"
#include "support/models.hpp"
#include "differential/test_scenes.hpp"
#include "visfield/accel/batch.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/io/image_io.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/render/ao.hpp"
#include "visfield/render/camera.hpp"
#include "visfield/render/sample_rays.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

// Restores the process-wide limit and signal state whatever a test does.
class ResourceLimits : public ::testing::Test {
 protected:
  void TearDown() override {
    clear_memory_limit();
    clear_interrupt();
  }
};

/// Every exact structure as the tests build it (test_sized: BeamField smaller under the sanitizers), and auto.
std::vector<std::string> specs_with_auto() {
  std::vector<std::string> specs;
  for (const std::string& spec : test::exact_structure_specs()) specs.push_back(test::test_sized(spec));
  specs.emplace_back("auto");
  return specs;
}

std::vector<std::pair<std::string, Scene>> estimate_scenes() {
  std::vector<std::pair<std::string, Scene>> scenes;
  scenes.emplace_back("soup", test::scene_from_triangles(test::random_soup(5, 20'000, 0.002f, 0.03f)));
  scenes.emplace_back("boxes", parse_builtin_scene("builtin:boxes:size=300"));
  scenes.emplace_back("cornell", parse_builtin_scene("builtin:cornell"));
  for (const char* model : {"cow.obj", "bun_zipper.ply"}) {
    const std::filesystem::path path = test::models_dir() / model;
    if (std::filesystem::exists(path))
      scenes.emplace_back(model, load_scene(path.string()));
    else if (test::models_required())
      ADD_FAILURE() << model << " is not in " << test::models_dir() << " (VISFIELD_REQUIRE_MODELS=1)";
  }
  return scenes;
}

TEST_F(ResourceLimits, EstimatesCoverTheBuiltStructureWithoutRefusingSensibleBuilds) {
  for (const auto& [name, scene] : estimate_scenes()) {
    for (const std::string& spec : specs_with_auto()) {
      SceneGeometry geometry(scene);
      const BuiltStructure built = build_structure(spec, geometry);
      const auto final_bytes = static_cast<double>(structure_stats(built.structure).memory_bytes);
      EXPECT_GE(built.estimated_bytes, final_bytes) << spec << " on " << name;
      // Over 8x would refuse builds that fit (constant parts dominate tiny scenes: 1 MiB of slack);
      // auto's estimate holds the decision's grid and a kd-tree at once, and keeps one of them.
      const double factor = spec == "auto" ? 12.0 : 8.0;
      EXPECT_LE(built.estimated_bytes, factor * final_bytes + 1024.0 * 1024.0) << spec << " on " << name;
    }
  }
}

TEST_F(ResourceLimits, ABuildOverTheLimitIsRefusedBeforeItStartsWithItsEstimate) {
  const Scene scene = test::scene_from_triangles(test::random_soup(6, 20'000, 0.002f, 0.03f));
  set_memory_limit(64.0 * 1024.0, "--max-memory 64.0 KiB");
  for (const std::string& spec : specs_with_auto()) {
    SceneGeometry geometry(scene);
    try {
      build_structure(spec, geometry, {}, "--accel ");
      ADD_FAILURE() << spec << " was built past the limit";
    } catch (const Interrupted&) {
      ADD_FAILURE() << "interrupted";
    } catch (const Error& e) {
      const std::string what = e.what();
      const std::string expected = "--accel " + spec + ": the build would need about " +
                                   format_bytes(estimate_structure_bytes(spec, geometry)) + ", more than --max-memory 64.0 KiB";
      EXPECT_EQ(what, expected);
      EXPECT_FALSE(geometry.is_flattened()) << spec << ": work was done before the refusal";
    }
  }
}

TEST_F(ResourceLimits, ATreeThatOutgrowsItsEstimateStopsAtTheLimit) {
  // Large overlapping triangles are copied into both children of every plane: a median BSP of depth
  // 30 with one triangle per leaf references each of them thousands of times.
  const Scene scene = test::scene_from_triangles(test::random_soup(7, 20'000, 0.2f, 0.5f));
  for (const std::string spec : {"median-bsp:depth=30,leaf=1", "kdtree:kt=0.01,depth=40"}) {
    SceneGeometry geometry(scene);
    const double estimate = estimate_structure_bytes(spec, geometry);
    set_memory_limit(2.0 * estimate, "--max-memory test");
    try {
      build_structure(spec, geometry);
      ADD_FAILURE() << spec << " was built past the limit";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("the tree grew to"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("more than --max-memory test"), std::string::npos) << e.what();
    }
  }
}

TEST_F(ResourceLimits, EveryBuildStopsWhenASignalHasArrived) {
  // Large enough that each builder reaches its interrupt checks (parallel-size nodes, grid chunks).
  const Scene scene = test::scene_from_triangles(test::random_soup(8, 60'000, 0.001f, 0.02f));
  const TriangleSet set = flatten(scene);
  request_interrupt(SIGINT);
  EXPECT_THROW(Bvh::build(set), Interrupted);
  EXPECT_THROW(KdTree::build(set), Interrupted);
  EXPECT_THROW(MedianBsp::build(set), Interrupted);
  EXPECT_THROW(UniformGrid::build(set), Interrupted);
  for (const std::string& spec : specs_with_auto()) {
    SceneGeometry geometry(scene);
    EXPECT_THROW(build_structure(spec, geometry), Interrupted) << spec;
  }
}

TEST_F(ResourceLimits, RendersAndBatchesStopAndNothingIsWritten) {
  const Scene scene = parse_builtin_scene("builtin:cornell");
  SceneGeometry geometry(scene);
  const BuiltStructure built = build_structure("bvh", geometry);
  const Bvh& bvh = std::get<Bvh>(built.structure);
  const Camera camera = scene.camera_or_default(32, 32);
  AoOptions ao;
  ao.progress = false;
  const Image image = render_ao(bvh, bvh, scene, camera, ao);

  request_interrupt(SIGTERM);
  try {
    render_ao(bvh, bvh, scene, camera, ao);
    ADD_FAILURE() << "the render ran to the end";
  } catch (const Interrupted& e) {
    EXPECT_EQ(e.signal(), SIGTERM);
    EXPECT_STREQ(e.what(), "interrupted by SIGTERM");
  }
  std::vector<Ray> rays(10'000, Ray{{0.5f, 0.5f, 0.5f}, {0, 0, 1}});
  std::vector<Hit> hits(rays.size());
  std::vector<std::uint8_t> occluded(rays.size());
  EXPECT_THROW(intersect_batch(bvh, std::span<const Ray>(rays), std::span<Hit>(hits)), Interrupted);
  EXPECT_THROW(occluded_batch(bvh, std::span<const Ray>(rays), std::span<std::uint8_t>(occluded)), Interrupted);

  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "visfield-interrupt-write";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  EXPECT_THROW(write_image(folder / "ao.png", image), Interrupted);
  EXPECT_TRUE(std::filesystem::is_empty(folder)) << "a partial or temporary file was left";
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace vf

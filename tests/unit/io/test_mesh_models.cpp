// The shared real-world models: every one loads with the manifest's triangle count.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "visfield/io/mesh_loader.hpp"
#include "support/models.hpp"

namespace vf {
namespace {

const std::filesystem::path kModels = vf::test::models_dir();

#define REQUIRE_MODELS() VF_SKIP_WITHOUT_MODELS(std::filesystem::exists(kModels / "manifest.tsv"), "manifest.tsv")

struct ManifestEntry {
  std::string file;
  std::size_t triangles = 0;
};

std::vector<ManifestEntry> read_manifest() {
  std::ifstream in(kModels / "manifest.tsv");
  std::vector<ManifestEntry> entries;
  std::string line;
  std::getline(in, line);  // header: file, triangles, vertices, sha256
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    ManifestEntry e;
    if (fields >> e.file >> e.triangles) entries.push_back(e);
  }
  return entries;
}

// Expects every coordinate of `b` within `tolerance` of the given corners.
void expect_bounds(const Bounds3f& b, const Vec3f& lo, const Vec3f& hi, float tolerance) {
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(b.lo[axis], lo[axis], tolerance) << "axis " << axis;
    EXPECT_NEAR(b.hi[axis], hi[axis], tolerance) << "axis " << axis;
  }
}

TEST(MeshModels, EveryModelLoadsWithTheManifestTriangleCount) {
  REQUIRE_MODELS();
  const std::vector<ManifestEntry> entries = read_manifest();
  ASSERT_GE(entries.size(), 10u);
  for (const ManifestEntry& e : entries) {
    SCOPED_TRACE(e.file);
    const LoadedMesh loaded = load_mesh(kModels / e.file);
    EXPECT_EQ(loaded.mesh.triangles.size(), e.triangles);
    EXPECT_EQ(loaded.mesh.name, e.file);
    EXPECT_TRUE(loaded.mesh.material_ids.empty() || loaded.mesh.material_ids.size() == e.triangles);
  }
}

TEST(MeshModels, SponzaKeepsItsSixZeroAreaTriangles) {
  REQUIRE_MODELS();
  const LoadedMesh sponza = load_mesh(kModels / "sponza.obj");
  EXPECT_EQ(sponza.mesh.triangles.size(), 66450u);
  EXPECT_EQ(sponza.mesh.count_degenerate(), 6u);
  EXPECT_EQ(sponza.materials.size(), 20u);  // the .mtl's textures are absent and ignored
}

// Duplicate triangles (same three vertex indices as an earlier one, after loading joined vertices
// with equal positions): the counts of the models' documentation, except sponza, whose file repeats
// vertex positions under other indices: 1 duplicate by the file's indices, 10 by position (checked
// with a separate script). lucy (28M triangles) is left out to keep the suite quick.
TEST(MeshModels, DuplicateTrianglesAreCountedAndKept) {
  REQUIRE_MODELS();
  const std::pair<const char*, std::size_t> expected[] = {
      {"dragon_vrip_res2.ply", 1489}, {"CornellBox-Original.obj", 4}, {"sponza.obj", 10}, {"cow.obj", 0},
      {"igea-triangles.ply", 0},      {"teapot.obj", 0}};
  for (const auto& [file, duplicates] : expected) {
    SCOPED_TRACE(file);
    EXPECT_EQ(load_mesh(kModels / file).mesh.count_duplicates(), duplicates);
  }
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {2, 0, 1}, {1, 0, 2}};  // a rotation and a reversal of the first
  EXPECT_EQ(mesh.count_duplicates(), 2u);
}

TEST(MeshModels, CornellBoxNegativeIndicesCrlfTabsAndMaterials) {
  REQUIRE_MODELS();
  const LoadedMesh box = load_mesh(kModels / "CornellBox-Original.obj");
  ASSERT_EQ(box.mesh.triangles.size(), 36u);
  expect_bounds(box.mesh.bounds(), {-1.02f, 0.0f, -1.04f}, {1.0f, 1.99f, 0.99f}, 1e-6f);
  ASSERT_EQ(box.materials.size(), 8u);
  ASSERT_EQ(box.mesh.material_ids.size(), 36u);
  const auto light = std::find_if(box.materials.begin(), box.materials.end(), [](const Material& m) { return m.name == "light"; });
  ASSERT_NE(light, box.materials.end());
  EXPECT_EQ(light->emission, (Vec3f{17.0f, 12.0f, 4.0f}));
  EXPECT_FLOAT_EQ(light->diffuse.x, 0.78f);
  const auto light_index = static_cast<std::uint32_t>(light - box.materials.begin());
  EXPECT_EQ(std::count(box.mesh.material_ids.begin(), box.mesh.material_ids.end(), light_index), 2);
  const auto left = std::find_if(box.materials.begin(), box.materials.end(), [](const Material& m) { return m.name == "leftWall"; });
  ASSERT_NE(left, box.materials.end());
  EXPECT_FLOAT_EQ(left->diffuse.x, 0.63f);
  EXPECT_FLOAT_EQ(left->diffuse.z, 0.05f);
}

TEST(MeshModels, BigEndianArmadilloHasTheDocumentedBounds) {
  REQUIRE_MODELS();
  const LoadedMesh armadillo = load_mesh(kModels / "Armadillo.ply");
  EXPECT_EQ(armadillo.mesh.positions.size(), 172974u);
  expect_bounds(armadillo.mesh.bounds(), {-63.5001f, -54.2415f, -57.7145f}, {63.5001f, 97.0804f, 57.714f}, 1e-3f);
  EXPECT_TRUE(armadillo.materials.empty());  // PLY defines no materials
  EXPECT_TRUE(armadillo.mesh.material_ids.empty());
}

TEST(MeshModels, ConferenceBoundsAndMaterials) {
  REQUIRE_MODELS();
  const LoadedMesh conference = load_mesh(kModels / "conference.obj");
  const Bounds3f b = conference.mesh.bounds();
  EXPECT_NEAR(b.lo.x, -1020.13f, 1e-2f);
  EXPECT_NEAR(b.hi.x, 1685.81f, 1e-2f);
  EXPECT_NEAR(b.hi.y, 650.293f, 1e-2f);
  EXPECT_EQ(conference.materials.size(), 35u);
  // Specular Ks and Phong exponent Ns 40 become a glossy lobe.
  EXPECT_TRUE(std::any_of(conference.materials.begin(), conference.materials.end(),
                          [](const Material& m) { return m.specular.x > 0.1f && m.roughness > 0.0f && m.roughness < 1.0f; }));
}

}  // namespace
}  // namespace vf

// .vfield files: every storage round-trips bit for bit, and a cut, corrupted, wrong-version,
// inconsistent or wrong-mesh file is refused with one line naming it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>
#include <utility>

#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/field/field_file.hpp"
#include "visfield/field/field_scene.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf::field {
namespace {

TriangleSet box_object() {
  const Scene scene = make_builtin_scene("cornell", {.size = 200});
  return mesh_triangles(scene.meshes.at(1));
}

// The message of the vf::Error `f` throws ("" when it does not throw).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// `bytes` with the checksum recomputed, so that a test reaches the checks behind it.
std::string with_checksum(std::string bytes) { return with_field_checksum(std::move(bytes)); }

TEST(FieldFile, EveryStorageRoundTripsBitForBit) {
  const TriangleSet set = box_object();
  for (const CellStorage storage : {CellStorage::u8, CellStorage::u16, CellStorage::f32, CellStorage::bit}) {
    const ObjectField field = ObjectField::build(set, {.positions = 290, .directions = 8, .mapping = HemisphereMapping::polar, .storage = storage});
    const StoredField back = decode_field(encode_field(field, mesh_hash(set)), "f.vfield");
    EXPECT_EQ(back.mesh_hash, mesh_hash(set));
    EXPECT_TRUE(ObjectField::same_tables(back.field.config(), field.config()));
    EXPECT_TRUE(std::ranges::equal(back.field.cell_table(), field.cell_table())) << storage_name(storage);
    EXPECT_EQ(back.field.averages(), field.averages());
    EXPECT_EQ(back.field.sphere().radius, field.sphere().radius);
    EXPECT_EQ(back.field.sphere().centre, field.sphere().centre);
    EXPECT_EQ(back.field.rays_traced(), field.rays_traced());
    const Vec3f org{3.0f, 2.0f, 1.0f};
    for (int q = 0; q < 100; ++q) {
      const Vec3f dir = normalize(Vec3f{-3.0f + 0.02f * q, -2.0f, -1.0f + 0.01f * q});
      const FieldAnswer a = field.trace(org, dir, 0.0f, 100.0f), b = back.field.trace(org, dir, 0.0f, 100.0f);
      EXPECT_EQ(a.hit, b.hit);
      EXPECT_EQ(a.t, b.t);
    }
  }
}

TEST(FieldFile, NormalFieldsRoundTripBitForBit) {
  const TriangleSet set = box_object();
  for (const NormalStorage normals : {NormalStorage::oct16, NormalStorage::oct32}) {
    const ObjectField field = ObjectField::build(set, {.positions = 290, .directions = 8, .normals = normals});
    const StoredField back = decode_field(encode_field(field, mesh_hash(set)), "f.vfield");
    EXPECT_EQ(back.field.config().normals, normals);
    EXPECT_EQ(back.version, kFieldFileVersion);
    EXPECT_FALSE(field.normal_table().empty());
    EXPECT_TRUE(std::ranges::equal(back.field.normal_table(), field.normal_table())) << normals_name(normals);
    EXPECT_TRUE(std::ranges::equal(back.field.cell_table(), field.cell_table()));
  }
}

// A version-1 file (before normal fields) is the version-2 layout without the normal byte count.
TEST(FieldFile, VersionOneFilesAreStillRead) {
  const TriangleSet set = box_object();
  const ObjectField field = ObjectField::build(set, {.positions = 290, .directions = 8});
  std::string bytes = encode_field(field, 7);
  bytes.erase(64, 8);
  bytes[8] = 1;
  const StoredField back = decode_field(with_checksum(bytes), "old.vfield");
  EXPECT_EQ(back.version, 1u);
  EXPECT_EQ(back.field.config().normals, NormalStorage::none);
  EXPECT_TRUE(std::ranges::equal(back.field.cell_table(), field.cell_table()));
}

TEST(FieldFile, SavedAtomicallyAndLoadedForItsMeshOnly) {
  const TriangleSet set = box_object();
  const ObjectField field = ObjectField::build(set, {.positions = 290, .directions = 8});
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "visfield-field-file-test";
  std::filesystem::create_directories(dir);
  const std::filesystem::path path = dir / "box.vfield";
  save_field(field, mesh_hash(set), path);
  EXPECT_TRUE(std::ranges::equal(load_field(path, mesh_hash(set)).field.cell_table(), field.cell_table()));
  const ObjectField bilinear = load_field(path, std::nullopt, {.direction_lookup = DirectionLookup::bilinear}).field;
  EXPECT_EQ(bilinear.config().direction_lookup, DirectionLookup::bilinear);
  EXPECT_NE(error_of([&] { load_field(path, mesh_hash(set) + 1); }).find("made for another mesh"), std::string::npos);
  EXPECT_NE(error_of([&] { load_field(dir / "none.vfield"); }).find("none.vfield: no such file"), std::string::npos);
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename(), "box.vfield") << "left behind: " << entry.path();
  std::filesystem::remove_all(dir);
}

TEST(FieldFile, DamagedFilesAreRefusedWithOneLine) {
  const TriangleSet set = box_object();
  const std::string good = encode_field(ObjectField::build(set, {.positions = 290, .directions = 8}), 7);
  const auto expect_refused = [](const std::string& bytes, const std::string& expected) {
    const std::string message = error_of([&] { decode_field(bytes, "x.vfield"); });
    EXPECT_NE(message.find("x.vfield: " + expected), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  };
  expect_refused("", "the file is cut short");
  expect_refused(good.substr(0, 40), "the file is cut short");
  expect_refused(good.substr(0, good.size() - 1), "checksum mismatch");
  expect_refused("NOTFIELD" + good.substr(8), "not a .vfield file");
  std::string flipped = good;
  flipped[200] ^= 0x10;
  expect_refused(flipped, "checksum mismatch");
  std::string version = good;
  version[8] = 3;
  expect_refused(with_checksum(version), ".vfield version 3, this visfield reads versions 1 and 2");
  std::string positions = good;
  positions[12] = 7;  // 290 -> 263
  expect_refused(with_checksum(positions), "field positions");
  std::string mapping = good;
  mapping[20] = 9;
  expect_refused(with_checksum(mapping), "unknown direction mapping 9");
  std::string normals = good;
  normals[22] = 5;
  expect_refused(with_checksum(normals), "unknown normal storage 5");
  std::string reserved = good;
  reserved[23] = 1;
  expect_refused(with_checksum(reserved), "reserved header bytes");
  std::string no_normal_table = encode_field(ObjectField::build(set, {.positions = 290, .directions = 8, .normals = NormalStorage::oct16}), 7);
  no_normal_table[22] = 0;  // the header says no normals, but the normal table is there
  expect_refused(with_checksum(no_normal_table), "the header's table sizes do not match");
  std::string radius = good;
  const float negative = -1.0f;
  std::memcpy(radius.data() + 44, &negative, 4);
  expect_refused(with_checksum(radius), "object field: its bounding sphere");
  std::string longer = good;
  longer.insert(good.size() - 8, "xxxx");
  expect_refused(with_checksum(longer), std::to_string(longer.size()) + " bytes, its header describes");
}

TEST(FieldFile, ATableBeyondTheMemoryLimitIsRefusedBeforeReading) {
  const TriangleSet set = box_object();
  const std::string bytes = encode_field(ObjectField::build(set, {.positions = 1090, .directions = 64}), 7);  // 4.3 MiB
  set_memory_limit(1 << 20, "the test's 1 MiB");
  const std::string message = error_of([&] { decode_field(bytes, "big.vfield"); });
  clear_memory_limit();
  EXPECT_NE(message.find("big.vfield's field would need about"), std::string::npos) << message;
}

TEST(FieldFile, ScenesCacheTheirFields) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "visfield-field-cache-test";
  std::filesystem::remove_all(dir);
  Scene scene = make_builtin_scene("cornell", {.size = 200});
  scene.meshes.at(1).field_file = (dir / "named" / "cube.vfield").string();
  std::filesystem::create_directories(dir / "named");
  const ObjectFieldConfig config{.positions = 290, .directions = 8};
  const FieldScene first = FieldScene::build(scene, config, {}, (dir / "cache").string());
  EXPECT_TRUE(std::filesystem::exists(dir / "named" / "cube.vfield"));
  std::size_t cached = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "cache")) {
    EXPECT_EQ(entry.path().extension(), ".vfield");
    EXPECT_NE(entry.path().filename().string().find("-290x8-concentric-u8.vfield"), std::string::npos) << entry.path();
    ++cached;
  }
  EXPECT_EQ(cached, 2u);  // the tall box and the sphere; the cube has its own file, the room is exact
  // The second build reads every field back: no precompute, the same tables.
  std::size_t precomputed = 0;
  const FieldScene second = FieldScene::build(scene, config, [&](std::size_t n) { precomputed += n; }, (dir / "cache").string());
  for (std::uint32_t mesh = 0; mesh < scene.meshes.size(); ++mesh) {
    ASSERT_EQ(first.mesh_field(mesh) == nullptr, second.mesh_field(mesh) == nullptr);
    if (first.mesh_field(mesh)) {
      EXPECT_TRUE(std::ranges::equal(first.mesh_field(mesh)->cell_table(), second.mesh_field(mesh)->cell_table())) << mesh;
    }
  }
  EXPECT_EQ(precomputed, 3u * 290u);  // reported as done, all at once
  // A file made for another mesh is refused.
  scene.meshes.at(2).field_file = (dir / "named" / "cube.vfield").string();
  const std::string message = error_of([&] { FieldScene::build(scene, config); });
  EXPECT_NE(message.find("cube.vfield: made for another mesh"), std::string::npos) << message;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace vf::field

// Bad mesh files: each is refused with a one-line vf::Error naming the file.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io_test_support.hpp"
#include "visfield/io/mesh_loader.hpp"

namespace vf {
namespace {

using test::expect_one_line_error;
using test::TempDir;
using test::write_file;

// Loads `path`, requiring a one-line error that names the file and contains `reason`.
void expect_refused(const std::filesystem::path& path, const std::string& reason) {
  const std::string message = expect_one_line_error([&] { load_mesh(path); }, path.string() + ": ");
  EXPECT_NE(message.find(reason), std::string::npos) << message;
}

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

TEST(MeshErrors, MissingFile) {
  TempDir dir;
  expect_refused(dir / "absent.obj", "no such file");
}

TEST(MeshErrors, Directory) {
  TempDir dir;
  std::filesystem::create_directory(dir / "folder.obj");
  expect_refused(dir / "folder.obj", "is a directory");
}

TEST(MeshErrors, UnreadableFile) {
  if (::geteuid() == 0) GTEST_SKIP() << "root reads files whatever their permissions";
  TempDir dir;
  const auto path = write_file(dir / "locked.obj", kTriangle + "f 1 2 3\n");
  ::chmod(path.c_str(), 0);
  expect_refused(path, "cannot open");
}

TEST(MeshErrors, UnsupportedExtension) {
  TempDir dir;
  expect_refused(write_file(dir / "mesh.xyz", kTriangle + "f 1 2 3\n"), "unsupported mesh format");
}

TEST(MeshErrors, GarbageBytesInPly) {
  TempDir dir;
  std::string garbage;
  for (int i = 0; i < 4096; ++i) garbage += static_cast<char>((i * 7919 + 13) % 251);
  expect_refused(write_file(dir / "garbage.ply", garbage), "malformed PLY");
}

TEST(MeshErrors, PlyHeaderWithGarbageBody) {
  TempDir dir;
  const auto path = write_file(dir / "body.ply",
                               "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                               "0 0 0\n1 0 zebra\n");
  expect_refused(path, "malformed PLY");
}

TEST(MeshErrors, TruncatedBinaryPly) {
  TempDir dir;
  std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
  ply += std::string(4 * 12, '\0');  // the vertices, but only part of the first face follows
  ply += static_cast<char>(3);
  ply += std::string(5, '\0');
  expect_refused(write_file(dir / "truncated.ply", ply), "malformed PLY");
}

TEST(MeshErrors, ObjIndexOutOfRange) {
  TempDir dir;
  expect_refused(write_file(dir / "range.obj", kTriangle + "f 1 2 4\n"), "index");
  expect_refused(write_file(dir / "negative.obj", kTriangle + "f -1 -2 -4\n"), "index");
}

TEST(MeshErrors, ObjNanAndInfCoordinates) {
  TempDir dir;
  expect_refused(write_file(dir / "nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "NaN or infinite");
  expect_refused(write_file(dir / "inf.obj", "v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n"), "NaN or infinite");
}

TEST(MeshErrors, ObjWithoutFaces) {
  TempDir dir;
  expect_refused(write_file(dir / "empty.obj", ""), "empty.obj: the file is empty");
  expect_refused(write_file(dir / "comment.obj", "# only a comment line\n"), "no faces");
  expect_refused(write_file(dir / "vertices.obj", kTriangle), "no faces");
  expect_refused(write_file(dir / "lines.obj", kTriangle + "l 1 2 3\n"), "no triangles");
}

// Assimp's glTF reader recurses on nested JSON: 100,000 levels crashed it (stack overflow) before
// the nesting check; a GLB's JSON chunk is checked the same way, and its declared length first.
TEST(MeshErrors, DeeplyNestedGltfAndOverlongGlbChunks) {
  TempDir dir;
  const std::string deep = "{\"asset\": {\"version\": \"2.0\"}, \"x\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  expect_refused(write_file(dir / "deep.gltf", deep), "deep.gltf: malformed GLTF: invalid JSON: arrays and objects nested more than 64 deep");
  const auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  expect_refused(write_file(dir / "deep.glb", "glTF" + u32(2) + u32(static_cast<std::uint32_t>(20 + deep.size())) +
                                                  u32(static_cast<std::uint32_t>(deep.size())) + "JSON" + deep),
                 "deep.glb: malformed GLB: invalid JSON: arrays and objects nested more than 64 deep");
  expect_refused(write_file(dir / "long.glb", "glTF" + u32(2) + u32(1000) + u32(4000000000u) + "JSON{}"),
                 "long.glb: malformed GLB: the header declares 4000000000 bytes of JSON but only 2 bytes follow it");
}

TEST(MeshErrors, GarbageGlbAndStl) {
  TempDir dir;
  expect_refused(write_file(dir / "bad.glb", "not a binary gltf file at all"), "malformed GLB");
  expect_refused(write_file(dir / "bad.stl", std::string(20, 'x')), "malformed STL");
  expect_refused(write_file(dir / "bad.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": 5}"), "malformed GLTF");
}

}  // namespace
}  // namespace vf

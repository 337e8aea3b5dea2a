// Small files of every supported format, written by the test, loaded back.

#include <gtest/gtest.h>

#include <bit>
#include <cstring>

#include "io_test_support.hpp"
#include "visfield/io/mesh_loader.hpp"

namespace vf {
namespace {

using test::TempDir;
using test::write_file;

void expect_vertex(const TriangleMesh& mesh, std::size_t triangle, int corner, const Vec3f& expected) {
  ASSERT_LT(triangle, mesh.triangles.size());
  const Vec3f p = mesh.positions[mesh.triangles[triangle][corner]];
  EXPECT_EQ(p, expected) << "triangle " << triangle << " corner " << corner << ": (" << p.x << ", " << p.y << ", "
                         << p.z << ")";
}

TEST(MeshFormats, ObjNegativeIndicesPentagonCrlfAndTabs) {
  TempDir dir;
  const LoadedMesh loaded = load_mesh(write_file(dir / "pentagon.obj",
                                                 "# pentagon\r\nv 0 0 0\r\nv\t1 0 0\r\nv 1.5\t1 0\r\nv 0.5 2 0\r\nv -0.5 1 0\r\n"
                                                 "f -5 -4 -3 -2 -1\r\n"));
  ASSERT_EQ(loaded.mesh.triangles.size(), 3u);  // fan: (0,1,2) (0,2,3) (0,3,4)
  expect_vertex(loaded.mesh, 0, 0, {0, 0, 0});
  expect_vertex(loaded.mesh, 0, 1, {1, 0, 0});
  expect_vertex(loaded.mesh, 1, 1, {1.5f, 1, 0});
  expect_vertex(loaded.mesh, 2, 1, {0.5f, 2, 0});
  expect_vertex(loaded.mesh, 2, 2, {-0.5f, 1, 0});
  EXPECT_EQ(loaded.mesh.positions.size(), 5u);  // corners shared again after Assimp's per-face copies
  EXPECT_TRUE(loaded.materials.empty());
}

TEST(MeshFormats, ObjKeepsZeroAreaTrianglesAndSkipsLines) {
  TempDir dir;
  const LoadedMesh loaded = load_mesh(write_file(dir / "degenerate.obj",
                                                 "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 1 1 2\nl 1 3\n"));
  ASSERT_EQ(loaded.mesh.triangles.size(), 3u);
  EXPECT_EQ(loaded.mesh.count_degenerate(), 2u);
}

TEST(MeshFormats, ObjMaterialsFromMtlWithMissingTextures) {
  TempDir dir;
  write_file(dir / "two.mtl",
             "newmtl red\nKd 0.9 0.1 0.1\nKs 0.5 0.5 0.5\nNs 98\nmap_Kd missing_texture.png\n"
             "newmtl lamp\nKd 0 0 0\nKe 5 4 3\nmap_bump nothing.jpg\n");
  const LoadedMesh loaded = load_mesh(write_file(dir / "two.obj",
                                                 "mtllib two.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                                 "usemtl red\nf 1 2 3\nf 1 3 4\nusemtl lamp\nf 1 4 2\n"));
  ASSERT_EQ(loaded.mesh.triangles.size(), 3u);
  ASSERT_EQ(loaded.materials.size(), 2u);
  ASSERT_EQ(loaded.mesh.material_ids.size(), 3u);
  const Material& red = loaded.materials[loaded.mesh.material_ids[0]];
  const Material& lamp = loaded.materials[loaded.mesh.material_ids[2]];
  EXPECT_EQ(loaded.mesh.material_ids[1], loaded.mesh.material_ids[0]);
  EXPECT_EQ(red.name, "red");
  EXPECT_FLOAT_EQ(red.diffuse.x, 0.9f);
  EXPECT_FLOAT_EQ(red.specular.y, 0.5f);
  EXPECT_NEAR(red.roughness, 0.1414f, 1e-3f);  // sqrt(2 / (98 + 2))
  EXPECT_EQ(lamp.name, "lamp");
  EXPECT_EQ(lamp.emission, (Vec3f{5, 4, 3}));
}

TEST(MeshFormats, MtlGlassGivesTransmissionAndIndexOfRefraction) {
  TempDir dir;
  write_file(dir / "glass.mtl", "newmtl glass\nKd 0.1 0.1 0.1\nNi 1.33\nd 0.25\nnewmtl plain\nKd 0.5 0.5 0.5\nNi 1.0\nd 1\n");
  const LoadedMesh loaded = load_mesh(write_file(dir / "glass.obj",
                                                 "mtllib glass.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                                 "usemtl glass\nf 1 2 3\nusemtl plain\nf 1 3 4\n"));
  ASSERT_EQ(loaded.materials.size(), 2u);
  const Material& glass = loaded.materials[loaded.mesh.material_ids[0]];
  const Material& plain = loaded.materials[loaded.mesh.material_ids[1]];
  EXPECT_NEAR(glass.transmission, 0.75f, 1e-6f);  // dissolve 0.25
  EXPECT_NEAR(glass.ior, 1.33f, 1e-6f);
  EXPECT_EQ(plain.transmission, 0.0f);
  EXPECT_EQ(plain.ior, 1.5f);  // Ni 1 reads as "not given": the default
}

TEST(MeshFormats, ObjWithMissingMtlFileLoads) {
  TempDir dir;
  const auto path = write_file(dir / "nomtl.obj", "mtllib absent.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n");
  EXPECT_EQ(load_mesh(path).mesh.triangles.size(), 1u);
}

TEST(MeshFormats, AsciiPlyWithQuad) {
  TempDir dir;
  const LoadedMesh loaded = load_mesh(write_file(dir / "quad.ply",
                                                 "ply\nformat ascii 1.0\ncomment a unit quad and a triangle\nelement vertex 5\n"
                                                 "property float x\nproperty float y\nproperty float z\nelement face 2\n"
                                                 "property list uchar int vertex_indices\nend_header\n"
                                                 "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.25 0.5 3\n4 0 1 2 3\n3 0 1 4\n"));
  ASSERT_EQ(loaded.mesh.triangles.size(), 3u);
  expect_vertex(loaded.mesh, 1, 2, {0, 1, 0});
  expect_vertex(loaded.mesh, 2, 2, {0.25f, 0.5f, 3});
  EXPECT_TRUE(loaded.materials.empty());
}

// A binary PLY of `positions` and the triangles {0,1,2}, {0,2,3}, ... with a uchar property before
// the index list (as in the Stanford Armadillo), in the given byte order.
std::string binary_ply(const std::vector<Vec3f>& positions, std::uint32_t triangles, bool big_endian) {
  std::string s = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\nelement vertex " + std::to_string(positions.size()) +
                  "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(triangles) +
                  "\nproperty uchar intensity\nproperty list uchar int vertex_indices\nend_header\n";
  const auto put32 = [&](std::uint32_t v) {
    if (big_endian == (std::endian::native == std::endian::little)) v = __builtin_bswap32(v);
    s.append(reinterpret_cast<const char*>(&v), 4);
  };
  for (const Vec3f& p : positions)
    for (int c = 0; c < 3; ++c) put32(std::bit_cast<std::uint32_t>(p[c]));
  for (std::uint32_t t = 0; t < triangles; ++t) {
    s += static_cast<char>(7);  // intensity
    s += static_cast<char>(3);
    put32(0);
    put32(t + 1);
    put32(t + 2);
  }
  return s;
}

const std::vector<Vec3f> kFan = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5f}, {0, 1, -0.25f}};

TEST(MeshFormats, BinaryPlyOfBothByteOrders) {
  TempDir dir;
  for (const bool big_endian : {false, true}) {
    SCOPED_TRACE(big_endian ? "big endian" : "little endian");
    const LoadedMesh loaded = load_mesh(write_file(dir / (big_endian ? "be.ply" : "le.ply"), binary_ply(kFan, 2, big_endian)));
    ASSERT_EQ(loaded.mesh.triangles.size(), 2u);
    expect_vertex(loaded.mesh, 0, 2, {1, 1, 0.5f});
    expect_vertex(loaded.mesh, 1, 2, {0, 1, -0.25f});
  }
}

TEST(MeshFormats, AsciiStl) {
  TempDir dir;
  const LoadedMesh loaded = load_mesh(write_file(dir / "two.stl",
                                                 "solid two\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
                                                 "   vertex 0 1 0\n  endloop\n endfacet\n facet normal 0 0 1\n  outer loop\n"
                                                 "   vertex 1 0 0\n   vertex 1 1 0\n   vertex 0 1 2.5\n  endloop\n endfacet\nendsolid two\n"));
  ASSERT_EQ(loaded.mesh.triangles.size(), 2u);
  expect_vertex(loaded.mesh, 1, 2, {0, 1, 2.5f});
  EXPECT_EQ(loaded.mesh.positions.size(), 5u);  // STL repeats shared corners; the loader shares them
  EXPECT_TRUE(loaded.materials.empty());
}

TEST(MeshFormats, BinaryStl) {
  TempDir dir;
  std::string s(80, ' ');
  const auto put = [&](const void* p, std::size_t n) { s.append(static_cast<const char*>(p), n); };
  const std::uint32_t count = 1;
  put(&count, 4);
  const float record[12] = {0, 0, 1, /*corners*/ 0, 0, 0, 2, 0, 0, 0, 3, 0};
  put(record, sizeof(record));
  s += std::string(2, '\0');  // attribute byte count
  const LoadedMesh loaded = load_mesh(write_file(dir / "one.stl", s));
  ASSERT_EQ(loaded.mesh.triangles.size(), 1u);
  expect_vertex(loaded.mesh, 0, 2, {0, 3, 0});
}

std::string base64(const std::string& bytes) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t v = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<std::uint8_t>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<std::uint8_t>(bytes[i + 2]);
    out += digits[(v >> 18) & 63];
    out += digits[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? digits[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? digits[v & 63] : '=';
  }
  return out;
}

TEST(MeshFormats, GltfWithEmbeddedBufferNodeTransformsAndMaterial) {
  // One triangle mesh placed by two nodes: a translated parent with a scaled child.
  std::string buffer;
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint16_t indices[4] = {0, 1, 2, 0};  // the last entry pads to 4 bytes
  buffer.append(reinterpret_cast<const char*>(positions), sizeof(positions));
  buffer.append(reinterpret_cast<const char*>(indices), sizeof(indices));
  const std::string gltf = R"({
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0, "translation": [10, 20, 30], "children": [1]}, {"mesh": 0, "scale": [2, 2, 2]}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
    "materials": [{"name": "paint", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1.0]},
                   "emissiveFactor": [0.5, 0, 0]}],
    "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,)" + base64(buffer) + R"("}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
      {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]
  })";
  TempDir dir;
  const LoadedMesh loaded = load_mesh(write_file(dir / "tri.gltf", gltf));
  ASSERT_EQ(loaded.mesh.triangles.size(), 2u);
  expect_vertex(loaded.mesh, 0, 1, {11, 20, 30});  // parent: translated
  expect_vertex(loaded.mesh, 1, 2, {10, 22, 30});  // child: scaled by 2, then translated
  ASSERT_EQ(loaded.materials.size(), 1u);
  EXPECT_EQ(loaded.materials[0].name, "paint");
  EXPECT_FLOAT_EQ(loaded.materials[0].diffuse.y, 0.4f);
  EXPECT_FLOAT_EQ(loaded.materials[0].emission.x, 0.5f);
}

TEST(MeshFormats, AddMeshReindexesMaterials) {
  TempDir dir;
  write_file(dir / "m.mtl", "newmtl a\nKd 0.1 0.2 0.3\nnewmtl b\nKd 0.4 0.5 0.6\n");
  const auto path = write_file(dir / "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl b\nf 1 2 3\nusemtl a\nf 3 2 1\n");
  Scene scene;
  scene.materials.push_back(Material{.name = "extra"});
  const std::uint32_t first = add_mesh(scene, load_mesh(path));
  const std::uint32_t second = add_mesh(scene, load_mesh(path));
  EXPECT_EQ(first, 0u);
  EXPECT_EQ(second, 1u);
  ASSERT_EQ(scene.materials.size(), 6u);  // default, extra, then b and a (order of first use) twice
  scene.add_instance(0);
  scene.add_instance(1);
  EXPECT_FLOAT_EQ(scene.material_of(0, 0).diffuse.x, 0.4f);
  EXPECT_FLOAT_EQ(scene.material_of(0, 1).diffuse.x, 0.1f);
  EXPECT_FLOAT_EQ(scene.material_of(1, 0).diffuse.x, 0.4f);
  EXPECT_EQ(scene.meshes[1].material_ids[0], 4u);
  EXPECT_EQ(scene.materials[4].name, "b");
}

TEST(MeshFormats, AddMeshWithoutMaterialsUsesTheDefault) {
  Scene scene;
  LoadedMesh loaded;
  loaded.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  loaded.mesh.triangles = {{0, 1, 2}};
  EXPECT_EQ(add_mesh(scene, loaded), 0u);
  EXPECT_EQ(scene.materials.size(), 1u);
  loaded.mesh.material_ids = {3};
  EXPECT_THROW(add_mesh(scene, loaded), Error);
}

}  // namespace
}  // namespace vf

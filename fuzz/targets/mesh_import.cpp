// Fuzz target: visfield's side of mesh loading. The input describes an Assimp scene — materials,
// meshes (vertices of any float value, faces of any size with any index), and a node tree with
// transforms and mesh references — which is handed to the converter that load_mesh runs after
// Assimp, then to validate_mesh. Assimp's file parsers are fuzzed upstream; this covers the code
// that turns their output into a TriangleMesh. Any input must give a mesh or a vf::Error.

#include <assimp/material.h>
#include <assimp/scene.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "assimp_scene.hpp"
#include "input_reader.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/mesh.hpp"

namespace {

using Reader = vf::fuzz::InputReader;

aiMaterial* make_material(Reader& in) {
  auto* m = new aiMaterial();
  const std::uint8_t keys = in.byte();
  const aiString name(std::string(1, static_cast<char>('a' + keys % 26)));
  if (keys & 1) m->AddProperty(&name, AI_MATKEY_NAME);
  aiColor3D c(in.bits(), in.bits(), in.bits());
  if (keys & 2) m->AddProperty(&c, 1, AI_MATKEY_COLOR_DIFFUSE);
  if (keys & 4) m->AddProperty(&c, 1, AI_MATKEY_COLOR_EMISSIVE);
  float value = in.bits();
  if (keys & 8) m->AddProperty(&value, 1, AI_MATKEY_SHININESS);
  if (keys & 16) m->AddProperty(&value, 1, AI_MATKEY_ROUGHNESS_FACTOR);
  return m;
}

aiMesh* make_mesh(Reader& in) {
  auto* mesh = new aiMesh();
  mesh->mNumVertices = in.byte() % 64;
  mesh->mVertices = mesh->mNumVertices ? new aiVector3D[mesh->mNumVertices] : nullptr;
  for (unsigned v = 0; v < mesh->mNumVertices; ++v) mesh->mVertices[v] = aiVector3D(in.bits(), in.bits(), in.bits());
  mesh->mNumFaces = in.byte() % 64;
  mesh->mFaces = mesh->mNumFaces ? new aiFace[mesh->mNumFaces] : nullptr;
  for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
    aiFace& face = mesh->mFaces[f];
    face.mNumIndices = in.byte() % 8;
    face.mIndices = face.mNumIndices ? new unsigned[face.mNumIndices] : nullptr;
    for (unsigned c = 0; c < face.mNumIndices; ++c) face.mIndices[c] = in.u16() % (mesh->mNumVertices + 3);
  }
  mesh->mMaterialIndex = in.byte() % 6;
  return mesh;
}

aiNode* make_node(Reader& in, unsigned meshes, int depth) {
  auto* node = new aiNode("n" + std::to_string(depth));
  if (in.byte() & 1)
    for (unsigned r = 0; r < 4; ++r)
      for (unsigned c = 0; c < 4; ++c) node->mTransformation[r][c] = in.bits();
  node->mNumMeshes = in.byte() % 4;
  node->mMeshes = node->mNumMeshes ? new unsigned[node->mNumMeshes] : nullptr;
  for (unsigned i = 0; i < node->mNumMeshes; ++i) node->mMeshes[i] = in.byte() % (meshes + 2);
  const unsigned children = depth < 4 ? in.byte() % 3 : 0;
  if (children > 0) {
    node->mChildren = new aiNode*[children];
    for (unsigned i = 0; i < children; ++i) {
      node->mChildren[i] = make_node(in, meshes, depth + 1);
      node->mChildren[i]->mParent = node;
    }
    node->mNumChildren = children;
  }
  return node;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Reader in(data, size);
  aiScene scene;  // frees everything below
  const bool use_materials = in.byte() & 1;
  scene.mNumMaterials = in.byte() % 5;
  scene.mMaterials = scene.mNumMaterials ? new aiMaterial*[scene.mNumMaterials] : nullptr;
  for (unsigned i = 0; i < scene.mNumMaterials; ++i) scene.mMaterials[i] = make_material(in);
  scene.mNumMeshes = in.byte() % 5;
  scene.mMeshes = scene.mNumMeshes ? new aiMesh*[scene.mNumMeshes] : nullptr;
  for (unsigned i = 0; i < scene.mNumMeshes; ++i) scene.mMeshes[i] = make_mesh(in);
  scene.mRootNode = make_node(in, scene.mNumMeshes, 0);
  try {
    vf::LoadedMesh loaded = vf::io_detail::convert_assimp_scene(scene, use_materials, "fuzz.obj");
    if (!loaded.mesh.triangles.empty()) vf::validate_mesh(loaded.mesh, "fuzz.obj");
  } catch (const vf::Error&) {
  }
  return 0;
}

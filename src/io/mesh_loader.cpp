#include "visfield/io/mesh_loader.hpp"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cctype>
#include <cstdio>
#include <iterator>
#include <string>

#include "assimp_scene.hpp"
#include "file_checks.hpp"
#include "mesh_header.hpp"
#include "visfield/core/error.hpp"

namespace vf {

using io_detail::upper_case;

LoadedMesh load_mesh(const std::filesystem::path& path) {
  const std::string what = path.string();
  io_detail::require_readable_file(path);
  const std::string ext = io_detail::lower_extension(path);
  Assimp::Importer importer;
  if (ext.empty() || !importer.IsExtensionSupported("." + ext))
    throw Error(what + ": unsupported mesh format (expected .obj, .ply, .gltf, .glb, .stl or another format Assimp reads)");
  io_detail::check_mesh_header(path, ext);

  // No triangulation, degenerate removal or vertex joining by Assimp: we fan-triangulate and share
  // bit-identical vertices ourselves so that triangle counts and coordinates stay exactly the file's.
  const aiScene* scene = importer.ReadFile(path.string(), 0);
  const auto malformed = [&] {
    std::string reason = one_line(importer.GetErrorString());
    // Assimp prefixes some messages with the format ("OBJ: vertex index out of range"); we already say it.
    if (reason.starts_with(upper_case(ext) + ": ")) reason.erase(0, ext.size() + 2);
    return Error(what + ": malformed " + upper_case(ext) + ": " + reason);
  };
  if (scene == nullptr) throw malformed();
  if (scene->mNumMeshes == 0) throw Error(what + ": the file holds no mesh (no faces)");
  scene = importer.ApplyPostProcessing(aiProcess_ValidateDataStructure);
  if (scene == nullptr) throw malformed();

  // PLY and STL define no materials; Assimp invents one per file, which must not override the scene's.
  const bool use_materials = ext != "ply" && ext != "stl";
  LoadedMesh loaded = io_detail::convert_assimp_scene(*scene, use_materials, what);
  importer.FreeScene();
  if (loaded.mesh.triangles.empty()) throw Error(what + ": the file holds no triangles or polygons");
  loaded.mesh.name = path.filename().string();
  validate_mesh(loaded.mesh, what);
  return loaded;
}

std::uint32_t add_mesh(Scene& scene, LoadedMesh loaded) {
  for (std::uint32_t id : loaded.mesh.material_ids)
    if (id >= loaded.materials.size())
      throw Error(loaded.mesh.name + ": material id " + std::to_string(id) + " but only " +
                  std::to_string(loaded.materials.size()) + " materials");
  const auto first_material = static_cast<std::uint32_t>(scene.materials.size());
  for (std::uint32_t& id : loaded.mesh.material_ids) id += first_material;
  scene.materials.insert(scene.materials.end(), std::make_move_iterator(loaded.materials.begin()),
                         std::make_move_iterator(loaded.materials.end()));
  scene.meshes.push_back(std::move(loaded.mesh));
  return static_cast<std::uint32_t>(scene.meshes.size() - 1);
}

}  // namespace vf

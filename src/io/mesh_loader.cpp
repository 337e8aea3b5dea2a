#include "visfield/io/mesh_loader.hpp"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cctype>
#include <cstdio>
#include <iterator>
#include <string>

#include "assimp_scene.hpp"
#include "declared_sizes.hpp"
#include "file_checks.hpp"
#include "visfield/core/error.hpp"

namespace vf {
namespace {

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// Assimp picks a reader by extension and, failing that, by probing every reader; a file whose
// header does not match its extension could then be read as some other format. Check the magic
// bytes of the formats that have them so a mislabelled or corrupt file is reported, not guessed.
void require_format_signature(const std::filesystem::path& path, const std::string& ext) {
  std::string expected;
  if (ext == "ply") expected = "ply";
  else if (ext == "glb") expected = "glTF";
  else return;
  std::string head(expected.size(), '\0');
  std::FILE* file = std::fopen(path.c_str(), "rb");
  const std::size_t got = file != nullptr ? std::fread(head.data(), 1, head.size(), file) : 0;
  if (file != nullptr) std::fclose(file);
  if (got != head.size() || head != expected)
    throw Error(path.string() + ": malformed " + upper(ext) + ": the file does not start with \"" + expected + "\"");
}

}  // namespace

LoadedMesh load_mesh(const std::filesystem::path& path) {
  const std::string what = path.string();
  io_detail::require_readable_file(path);
  const std::string ext = io_detail::lower_extension(path);
  Assimp::Importer importer;
  if (ext.empty() || !importer.IsExtensionSupported("." + ext))
    throw Error(what + ": unsupported mesh format (expected .obj, .ply, .gltf, .glb, .stl or another format Assimp reads)");
  require_format_signature(path, ext);
  io_detail::check_declared_sizes(path, ext);

  // No triangulation, degenerate removal or vertex joining by Assimp: we fan-triangulate and share
  // bit-identical vertices ourselves so that triangle counts and coordinates stay exactly the file's.
  const aiScene* scene = importer.ReadFile(path.string(), 0);
  const auto malformed = [&] {
    return Error(what + ": malformed " + upper(ext) + ": " + io_detail::one_line(importer.GetErrorString()));
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

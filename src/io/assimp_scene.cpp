#include "assimp_scene.hpp"

#include <assimp/material.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "visfield/core/error.hpp"

namespace vf::io_detail {
namespace {

// Shares vertices whose positions are bit-identical (after folding -0 into +0), so the loader keeps
// the file's coordinates exactly while Assimp's per-corner vertex copies collapse back.
class VertexWelder {
 public:
  explicit VertexWelder(std::size_t expected) { index_of_key_.reserve(expected); }

  std::uint32_t index_of(const Vec3f& p) {
    const Key key{std::bit_cast<std::uint32_t>(p.x + 0.0f), std::bit_cast<std::uint32_t>(p.y + 0.0f),
                  std::bit_cast<std::uint32_t>(p.z + 0.0f)};
    const auto [it, inserted] = index_of_key_.try_emplace(key, static_cast<std::uint32_t>(positions_.size()));
    if (inserted) positions_.push_back(p);
    return it->second;
  }

  std::vector<Vec3f> take_positions() { return std::move(positions_); }

 private:
  using Key = std::array<std::uint32_t, 3>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 0x9E3779B97F4A7C15ull;
      for (std::uint32_t v : k) h = (h ^ v) * 0xBF58476D1CE4E5B9ull, h ^= h >> 31;
      return static_cast<std::size_t>(h);
    }
  };
  std::unordered_map<Key, std::uint32_t, KeyHash> index_of_key_;
  std::vector<Vec3f> positions_;
};

bool is_assimp_default_material(const aiMaterial& material) {
  aiString name;
  return material.Get(AI_MATKEY_NAME, name) == aiReturn_SUCCESS && std::string(name.C_Str()) == AI_DEFAULT_MATERIAL_NAME;
}

Vec3f color_or(const aiMaterial& material, const char* key, unsigned type, unsigned index, Vec3f fallback) {
  aiColor3D c;
  if (material.Get(key, type, index, c) != aiReturn_SUCCESS) return fallback;
  return {c.r, c.g, c.b};
}

Vec3f clamp01(const Vec3f& c) {
  return {std::clamp(c.x, 0.0f, 1.0f), std::clamp(c.y, 0.0f, 1.0f), std::clamp(c.z, 0.0f, 1.0f)};
}

Material convert_material(const aiMaterial& source, unsigned index, const std::string& what) {
  Material m;
  aiString name;
  m.name = source.Get(AI_MATKEY_NAME, name) == aiReturn_SUCCESS && name.length > 0 ? std::string(name.C_Str())
                                                                                   : "material" + std::to_string(index);
  const Vec3f diffuse = color_or(source, AI_MATKEY_COLOR_DIFFUSE, m.diffuse);
  const Vec3f specular = color_or(source, AI_MATKEY_COLOR_SPECULAR, m.specular);
  const Vec3f emission = color_or(source, AI_MATKEY_COLOR_EMISSIVE, m.emission);
  if (!is_finite(diffuse) || !is_finite(specular) || !is_finite(emission))
    throw Error(what + ": material '" + m.name + "' has a NaN or infinite colour");
  m.diffuse = clamp01(diffuse);
  m.specular = clamp01(specular);
  m.emission = max(emission, Vec3f{0.0f});
  float roughness = 0.0f;
  float shininess = 0.0f;
  if (source.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness) == aiReturn_SUCCESS) {
    m.roughness = std::isfinite(roughness) ? std::clamp(roughness, 0.0f, 1.0f) : 0.0f;
  } else if (source.Get(AI_MATKEY_SHININESS, shininess) == aiReturn_SUCCESS && std::isfinite(shininess) &&
             shininess > 0.0f) {
    // Phong exponent n to a microfacet roughness with the same lobe width: alpha = sqrt(2 / (n + 2)).
    m.roughness = std::clamp(std::sqrt(2.0f / (shininess + 2.0f)), 0.0f, 1.0f);
  }
  float emissive_strength = 1.0f;  // glTF KHR_materials_emissive_strength
  if (source.Get(AI_MATKEY_EMISSIVE_INTENSITY, emissive_strength) == aiReturn_SUCCESS && std::isfinite(emissive_strength) &&
      emissive_strength > 0.0f)
    m.emission = m.emission * emissive_strength;
  // Transmission: glTF's KHR_materials_transmission factor, else MTL's dissolve (d, or 1 - Tr).
  float transmission = 0.0f, opacity = 1.0f, ior = 0.0f;
  if (source.Get(AI_MATKEY_TRANSMISSION_FACTOR, transmission) == aiReturn_SUCCESS && std::isfinite(transmission))
    m.transmission = std::clamp(transmission, 0.0f, 1.0f);
  else if (source.Get(AI_MATKEY_OPACITY, opacity) == aiReturn_SUCCESS && std::isfinite(opacity))
    m.transmission = std::clamp(1.0f - opacity, 0.0f, 1.0f);
  // MTL's Ni (glTF's KHR_materials_ior); 1 and below mean "not given" in most exporters' files.
  if (source.Get(AI_MATKEY_REFRACTI, ior) == aiReturn_SUCCESS && std::isfinite(ior) && ior > 1.0f)
    m.ior = std::min(ior, 4.0f);
  return m;
}

// Which LoadedMesh material each Assimp material becomes, numbered in order of first use so that
// materials no triangle uses (Assimp adds a few of its own) are left out. Assimp invents a default
// material for files that name none; when no triangle uses a real one, the mesh carries no
// materials at all (every triangle then uses the scene's default material).
class MaterialTable {
 public:
  MaterialTable(const aiScene& scene, bool use_materials, const std::string& what)
      : scene_(scene), use_materials_(use_materials), what_(what), ours_(scene.mNumMaterials) {}

  /// Our index for Assimp material `index`.
  std::uint32_t index_of(unsigned index) {
    if (!use_materials_ || index >= scene_.mNumMaterials || scene_.mMaterials[index] == nullptr ||
        is_assimp_default_material(*scene_.mMaterials[index]))
      return default_index();
    if (!ours_[index]) {
      ours_[index] = static_cast<std::uint32_t>(materials_.size());
      materials_.push_back(convert_material(*scene_.mMaterials[index], index, what_));
    }
    uses_real_ = true;
    return *ours_[index];
  }

  /// Moves the materials into `out` (none, and no per-triangle ids, when only the default is used).
  void finish(LoadedMesh& out) {
    if (!uses_real_) {
      out.mesh.material_ids.clear();
      return;
    }
    out.materials = std::move(materials_);
  }

 private:
  std::uint32_t default_index() {
    if (!default_) {
      default_ = static_cast<std::uint32_t>(materials_.size());
      materials_.push_back(Material{});
    }
    return *default_;
  }

  const aiScene& scene_;
  bool use_materials_;
  const std::string& what_;
  std::vector<std::optional<std::uint32_t>> ours_;
  std::optional<std::uint32_t> default_;
  std::vector<Material> materials_;
  bool uses_real_ = false;
};

// Deeper node trees are refused: real files nest a few levels, and recursion must stay bounded.
constexpr int kMaxNodeDepth = 256;

class SceneConverter {
 public:
  SceneConverter(const aiScene& scene, bool use_materials, const std::string& what)
      : scene_(scene), what_(what), materials_(scene, use_materials, what), welder_(corner_count(scene)) {}

  LoadedMesh run() {
    if (scene_.mRootNode != nullptr) visit(*scene_.mRootNode, aiMatrix4x4{}, 0);
    out_.mesh.positions = welder_.take_positions();
    materials_.finish(out_);
    return std::move(out_);
  }

 private:
  static std::size_t corner_count(const aiScene& scene) {
    std::size_t n = 0;
    for (unsigned i = 0; i < scene.mNumMeshes; ++i) n += scene.mMeshes[i] != nullptr ? scene.mMeshes[i]->mNumVertices : 0;
    return n;
  }

  // Assimp validates its scenes, but this code does not rely on it: a hole or a loop in the structure
  // is reported, never followed.
  [[noreturn]] void malformed(const std::string& problem) const { throw Error(what_ + ": malformed scene: " + problem); }

  void visit(const aiNode& node, const aiMatrix4x4& parent, int depth) {
    if (depth > kMaxNodeDepth) malformed("the node tree is deeper than " + std::to_string(kMaxNodeDepth) + " levels");
    const aiMatrix4x4 to_world = parent * node.mTransformation;
    for (unsigned i = 0; i < node.mNumMeshes; ++i) {
      if (node.mMeshes[i] >= scene_.mNumMeshes) {
        std::ostringstream msg;
        msg << what_ << ": node '" << node.mName.C_Str() << "' names mesh " << node.mMeshes[i] << " of "
            << scene_.mNumMeshes;
        throw Error(msg.str());
      }
      if (scene_.mMeshes[node.mMeshes[i]] == nullptr) malformed("mesh " + std::to_string(node.mMeshes[i]) + " is missing");
      append_mesh(*scene_.mMeshes[node.mMeshes[i]], to_world);
    }
    for (unsigned i = 0; i < node.mNumChildren; ++i) {
      if (node.mChildren[i] == nullptr) malformed("a child of node '" + std::string(node.mName.C_Str()) + "' is missing");
      visit(*node.mChildren[i], to_world, depth + 1);
    }
  }

  void append_mesh(const aiMesh& mesh, const aiMatrix4x4& to_world) {
    // Multiplying by an identity matrix would still turn -0 into +0; skip it to keep values as read.
    const bool identity = to_world == aiMatrix4x4{};
    if (mesh.mNumVertices > 0 && mesh.mVertices == nullptr) malformed("mesh '" + std::string(mesh.mName.C_Str()) + "' has no vertex array");
    if (mesh.mNumFaces > 0 && mesh.mFaces == nullptr) malformed("mesh '" + std::string(mesh.mName.C_Str()) + "' has no face array");
    std::vector<std::uint32_t> ours(mesh.mNumVertices);
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = identity ? mesh.mVertices[v] : to_world * mesh.mVertices[v];
      ours[v] = welder_.index_of({p.x, p.y, p.z});
    }
    std::optional<std::uint32_t> material;  // looked up at the first triangle: unused materials stay out
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices < 3) continue;  // points and lines carry no surface
      if (face.mIndices == nullptr) malformed("a face of mesh '" + std::string(mesh.mName.C_Str()) + "' has no indices");
      for (unsigned c = 0; c < face.mNumIndices; ++c) {
        if (face.mIndices[c] >= mesh.mNumVertices) {
          std::ostringstream msg;
          msg << what_ << ": face " << f << " of mesh '" << mesh.mName.C_Str() << "' uses vertex "
              << face.mIndices[c] << " but the mesh has only " << mesh.mNumVertices << " vertices";
          throw Error(msg.str());
        }
      }
      if (!material) material = materials_.index_of(mesh.mMaterialIndex);
      // Fan triangulation: an n-gon becomes n - 2 triangles around its first corner.
      for (unsigned c = 1; c + 1 < face.mNumIndices; ++c) {
        out_.mesh.triangles.push_back({ours[face.mIndices[0]], ours[face.mIndices[c]], ours[face.mIndices[c + 1]]});
        out_.mesh.material_ids.push_back(*material);
      }
    }
  }

  const aiScene& scene_;
  const std::string& what_;
  MaterialTable materials_;
  VertexWelder welder_;
  LoadedMesh out_;
};

}  // namespace

LoadedMesh convert_assimp_scene(const aiScene& scene, bool use_materials, const std::string& what) {
  return SceneConverter(scene, use_materials, what).run();
}

}  // namespace vf::io_detail

#pragma once
// Private to the io module: turns an imported Assimp scene into one LoadedMesh.

#include <string>

#include "visfield/io/mesh_loader.hpp"

struct aiScene;

namespace vf::io_detail {

/// Merges every polygon of every mesh the node tree of `scene` references into one mesh: node
/// transforms are baked into the positions, polygons are fan-triangulated (zero-area triangles
/// kept), points and lines are skipped, and vertices with bit-identical positions are shared.
/// When `use_materials`, the file's materials (Kd, Ks, Ns or roughness, Ke) become
/// LoadedMesh::materials and Assimp's stand-in default material a plain Material{}; otherwise (formats
/// such as PLY and STL that define none, where Assimp invents one) the mesh carries no materials.
/// `what` (the file name) prefixes errors. The result is not yet validated (see validate_mesh).
/// O(corners) time and memory.
LoadedMesh convert_assimp_scene(const aiScene& scene, bool use_materials, const std::string& what);

}  // namespace vf::io_detail

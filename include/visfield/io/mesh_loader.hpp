#pragma once
/// \file Mesh files in, validated TriangleMesh out (Assimp: OBJ, PLY ascii/binary LE/BE, glTF/GLB, STL).

#include <filesystem>
#include <vector>

#include "visfield/core/mesh.hpp"
#include "visfield/core/scene.hpp"

namespace vf {

/// A loaded mesh plus the materials its file named (per-triangle material_ids index into `materials`).
struct LoadedMesh {
  TriangleMesh mesh;
  std::vector<Material> materials;
};

/// Loads every mesh of a file into one TriangleMesh (polygons fan-triangulated, node transforms
/// applied, vertices of the file kept as they are). Throws vf::Error with a one-line message naming
/// the file on a missing/unreadable/malformed file, NaN/Inf coordinates, bad indices or no triangles.
LoadedMesh load_mesh(const std::filesystem::path& path);

/// Appends `loaded` to `scene` (its materials appended and re-indexed); returns the new mesh index.
std::uint32_t add_mesh(Scene& scene, LoadedMesh loaded);

}  // namespace vf

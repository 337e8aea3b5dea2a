#include "visfield/core/mesh.hpp"

#include <algorithm>
#include <sstream>
#include <vector>

#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"

namespace vf {

Bounds3f TriangleMesh::bounds() const {
  Bounds3f b;
  for (const Vec3f& p : positions) b.extend(p);
  return b;
}

bool is_degenerate_triangle(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  const Vec3f n = cross(b - a, c - a);
  return n.x == 0.0f && n.y == 0.0f && n.z == 0.0f;
}

std::size_t TriangleMesh::count_degenerate() const {
  std::size_t count = 0;
  for (const TriangleIndices& t : triangles)
    if (is_degenerate_triangle(positions[t[0]], positions[t[1]], positions[t[2]])) ++count;
  return count;
}

std::size_t TriangleMesh::count_duplicates() const {
  std::vector<TriangleIndices> keys(triangles);
  for (TriangleIndices& k : keys) std::sort(k.begin(), k.end());
  vf::parallel_sort(keys.begin(), keys.end());
  std::size_t count = 0;
  for (std::size_t i = 1; i < keys.size(); ++i) count += keys[i] == keys[i - 1];
  return count;
}

std::size_t TriangleMesh::memory_bytes() const {
  return positions.capacity() * sizeof(Vec3f) + triangles.capacity() * sizeof(TriangleIndices) +
         material_ids.capacity() * sizeof(std::uint32_t);
}

void validate_mesh(const TriangleMesh& mesh, const std::string& what) {
  if (mesh.triangles.empty()) throw Error(what + ": mesh has no triangles");
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!is_finite(mesh.positions[i])) {
      std::ostringstream msg;
      msg << what << ": vertex " << i << " has a NaN or infinite coordinate";
      throw Error(msg.str());
    }
    if (max_component(abs(mesh.positions[i])) > kMaxCoordinate) {
      std::ostringstream msg;
      msg << what << ": vertex " << i << " has coordinate " << max_component(abs(mesh.positions[i]))
          << ", beyond the ±" << kMaxCoordinate << " visfield supports";
      throw Error(msg.str());
    }
  }
  const std::size_t vertex_count = mesh.positions.size();
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    for (std::uint32_t index : mesh.triangles[i]) {
      if (index >= vertex_count) {
        std::ostringstream msg;
        msg << what << ": triangle " << i << " uses vertex " << index << " but the mesh has only " << vertex_count
            << " vertices";
        throw Error(msg.str());
      }
    }
  }
  if (!mesh.material_ids.empty() && mesh.material_ids.size() != mesh.triangles.size())
    throw Error(what + ": material id count differs from triangle count");
}

}  // namespace vf

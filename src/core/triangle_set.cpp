#include "visfield/core/triangle_set.hpp"
#include "visfield/core/parallel.hpp"


namespace vf {

std::size_t TriangleSet::memory_bytes() const {
  return triangles.capacity() * sizeof(triangles[0]) + (prim.capacity() + instance.capacity()) * sizeof(std::uint32_t);
}

namespace {

/// One placed mesh: its triangles go through `transform` and are tagged with `id`.
struct Placement {
  const TriangleMesh* mesh;
  Transform transform;
  ObjectId id;
};

TriangleSet collect(const std::vector<Placement>& placements) {
  std::size_t total = 0;
  for (const Placement& p : placements) total += p.mesh->triangles.size();
  TriangleSet set;
  set.triangles.resize(total);
  std::vector<std::uint8_t> keep(total, 0);
  std::size_t offset = 0;
  for (const Placement& p : placements) {
    const TriangleMesh& mesh = *p.mesh;
    const bool identity = p.transform.is_identity();
    vf::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 4096), [&](const auto& range) {
      for (std::size_t t = range.begin(); t != range.end(); ++t) {
        const TriangleIndices& idx = mesh.triangles[t];
        auto& out = set.triangles[offset + t];
        for (int k = 0; k < 3; ++k)
          out[k] = identity ? mesh.positions[idx[k]] : p.transform.apply_point(mesh.positions[idx[k]]);
        keep[offset + t] = is_degenerate_triangle(out[0], out[1], out[2]) ? 0 : 1;
      }
    });
    offset += mesh.triangles.size();
  }
  // Compact in order, serially: keeps the output independent of scheduling.
  std::size_t kept = 0;
  offset = 0;
  set.prim.reserve(total);
  set.instance.reserve(total);
  for (const Placement& p : placements) {
    const std::size_t count = p.mesh->triangles.size();
    for (std::size_t t = 0; t < count; ++t) {
      const std::size_t g = offset + t;
      if (!keep[g]) continue;
      set.triangles[kept++] = set.triangles[g];
      set.prim.push_back(static_cast<std::uint32_t>(t));
      set.instance.push_back(p.id);
      for (const Vec3f& corner : set.triangles[kept - 1]) set.bounds.extend(corner);
    }
    offset += count;
  }
  set.degenerate_count = total - kept;
  set.triangles.resize(kept);
  set.triangles.shrink_to_fit();
  return set;
}

}  // namespace

TriangleSet flatten(const Scene& scene) {
  std::vector<Placement> placements;
  placements.reserve(scene.instances().size());
  for (const Instance& inst : scene.instances())
    placements.push_back({&scene.meshes[inst.mesh], inst.transform, inst.id});
  return collect(placements);
}

TriangleSet object_triangles(const TriangleMesh& mesh, const Transform& transform, ObjectId id) {
  return collect({{&mesh, transform, id}});
}

TriangleSet mesh_triangles(const TriangleMesh& mesh) { return collect({{&mesh, Transform{}, kInvalidId}}); }

}  // namespace vf

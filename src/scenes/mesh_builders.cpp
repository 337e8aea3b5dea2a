#include "mesh_builders.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace vf::scenes {

void add_quad(TriangleMesh& mesh, const Quad& q, std::uint32_t material) {
  const auto first = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), q.begin(), q.end());
  mesh.triangles.push_back({first, first + 1, first + 2});
  mesh.triangles.push_back({first, first + 2, first + 3});
  mesh.material_ids.resize(mesh.triangles.size(), material);
}

void add_quad_frame(TriangleMesh& mesh, const Quad& inner, const Quad& outer, std::uint32_t material) {
  const auto first = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), inner.begin(), inner.end());
  mesh.positions.insert(mesh.positions.end(), outer.begin(), outer.end());
  for (std::uint32_t k = 0; k < 4; ++k) {
    const std::uint32_t i0 = first + k, i1 = first + (k + 1) % 4;
    const std::uint32_t o0 = first + 4 + k, o1 = first + 4 + (k + 1) % 4;
    // Walking the outer edge forwards and the inner edge backwards keeps the trapezoid counter-clockwise.
    mesh.triangles.push_back({o0, o1, i1});
    mesh.triangles.push_back({o0, i1, i0});
  }
  mesh.material_ids.resize(mesh.triangles.size(), material);
}

TriangleMesh make_box_mesh(std::string name, const Bounds3f& box) {
  TriangleMesh mesh;
  mesh.name = std::move(name);
  // Eight shared corners (bit i of the index selects hi on axis i), so the box is closed by index too.
  for (std::uint32_t c = 0; c < 8; ++c)
    mesh.positions.push_back({(c & 1) ? box.hi.x : box.lo.x, (c & 2) ? box.hi.y : box.lo.y, (c & 4) ? box.hi.z : box.lo.z});
  for (std::uint32_t axis = 0; axis < 3; ++axis) {
    // (u, v, axis) is a cyclic permutation of (x, y, z), so u x v points along +axis.
    const std::uint32_t u = 1u << ((axis + 1) % 3), v = 1u << ((axis + 2) % 3);
    for (std::uint32_t side = 0; side < 2; ++side) {
      const std::uint32_t base = side << axis;
      std::array<std::uint32_t, 4> q{base, base | u, base | u | v, base | v};
      if (side == 0) std::reverse(q.begin(), q.end());  // the low face looks along -axis
      mesh.triangles.push_back({q[0], q[1], q[2]});
      mesh.triangles.push_back({q[0], q[2], q[3]});
    }
  }
  return mesh;
}

TriangleMesh make_ground_mesh(std::string name, float cx, float cz, float half_size, float y, std::uint32_t material) {
  TriangleMesh mesh;
  mesh.name = std::move(name);
  const float x0 = cx - half_size, x1 = cx + half_size, z0 = cz - half_size, z1 = cz + half_size;
  add_quad(mesh, {Vec3f{x0, y, z0}, Vec3f{x0, y, z1}, Vec3f{x1, y, z1}, Vec3f{x1, y, z0}}, material);
  mesh.occluder = MeshOccluder::exact;  // a receiver: its field would be one coarse plane
  return mesh;
}

std::vector<std::size_t> apportion(std::size_t total, const std::vector<double>& weights, std::size_t min_each) {
  const std::size_t n = weights.size();
  std::vector<std::size_t> counts(n, min_each);
  if (n == 0) return counts;
  const std::size_t rest = total - min_each * n;
  const double weight_sum = std::accumulate(weights.begin(), weights.end(), 0.0);
  std::vector<double> remainder(n);
  std::size_t given = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double exact = static_cast<double>(rest) * weights[i] / weight_sum;
    const auto whole = static_cast<std::size_t>(std::floor(exact));
    counts[i] += whole;
    given += whole;
    remainder[i] = exact - static_cast<double>(whole);
  }
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return remainder[a] > remainder[b]; });
  // Rounding can leave the floors short (the usual case) or, in pathological float cases, over.
  for (std::size_t k = 0; given < rest; k = (k + 1) % n, ++given) ++counts[order[k]];
  std::size_t k = n;
  while (given > rest) {
    k = (k == 0 ? n : k) - 1;  // smallest remainders first, cyclically
    if (counts[order[k]] > min_each) { --counts[order[k]]; --given; }
  }
  return counts;
}

std::uint32_t add_material(Scene& scene, Material material) {
  scene.materials.push_back(std::move(material));
  return static_cast<std::uint32_t>(scene.materials.size() - 1);
}

Material make_material(std::string name, const Vec3f& diffuse, const Vec3f& emission) {
  Material m;
  m.name = std::move(name);
  m.diffuse = diffuse;
  m.emission = emission;
  return m;
}

}  // namespace vf::scenes

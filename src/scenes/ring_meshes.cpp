// Closed meshes made of vertex rings stitched together: the sphere and the torus-knot tube. Rings may
// hold different vertex counts, which is what lets these meshes hit any even triangle count exactly:
// stitching rings of na and nb vertices takes na + nb triangles, so a closed chain of rings (or a chain
// capped by two pole fans) holds exactly 2 * (vertices in rings) triangles.

#include <algorithm>
#include <cmath>
#include <numbers>

#include "mesh_builders.hpp"

namespace vf::scenes {
namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;

// Triangulates the band between ring A (na vertices from index a0) and ring B (nb vertices from b0).
// Vertex k of a ring of n sits at angle 2*pi*k/n; the walk advances whichever ring's next vertex comes
// first (compared exactly in integers), so the band is closed, has no T-junctions and holds na + nb
// triangles. Outward when (angle direction) x (A to B direction) points outwards.
void stitch_rings(TriangleMesh& mesh, std::uint32_t a0, std::uint32_t na, std::uint32_t b0, std::uint32_t nb) {
  std::uint32_t i = 0, j = 0;
  while (i < na || j < nb) {
    const bool advance_a = j == nb || (i < na && std::uint64_t{i + 1} * nb <= std::uint64_t{j + 1} * na);
    if (advance_a) {
      mesh.triangles.push_back({a0 + i, a0 + (i + 1) % na, b0 + j % nb});
      ++i;
    } else {
      mesh.triangles.push_back({a0 + i % na, b0 + (j + 1) % nb, b0 + j});
      ++j;
    }
  }
}

// Appends a ring of n vertices: centre + radius * (cos(a) * e0 + sin(a) * e1) for a = 2*pi*k/n.
std::uint32_t add_ring(TriangleMesh& mesh, const Vec3f& centre, const Vec3f& e0, const Vec3f& e1, float radius,
                       std::size_t n) {
  const auto first = static_cast<std::uint32_t>(mesh.positions.size());
  for (std::size_t k = 0; k < n; ++k) {
    const float a = kTwoPi * static_cast<float>(k) / static_cast<float>(n);
    mesh.positions.push_back(centre + (e0 * std::cos(a) + e1 * std::sin(a)) * radius);
  }
  return first;
}

}  // namespace

TriangleMesh make_sphere_mesh(std::string name, const Vec3f& center, float radius, std::size_t triangle_count) {
  TriangleMesh mesh;
  mesh.name = std::move(name);
  const std::size_t ring_vertices = triangle_count / 2;
  // With rings evenly spaced in latitude, ring_vertices ~ 4 (rings + 1)^2 / pi for square-ish triangles.
  const double ideal_rings = std::round(std::sqrt(std::numbers::pi * static_cast<double>(triangle_count) / 8.0)) - 1.0;
  const std::size_t ring_count = std::clamp<std::size_t>(static_cast<std::size_t>(std::max(1.0, ideal_rings)), 1,
                                                         ring_vertices / 3);
  std::vector<double> weights(ring_count);
  std::vector<float> latitude(ring_count);
  for (std::size_t i = 0; i < ring_count; ++i) {
    latitude[i] = std::numbers::pi_v<float> * static_cast<float>(i + 1) / static_cast<float>(ring_count + 1);
    weights[i] = std::sin(static_cast<double>(latitude[i]));
  }
  const std::vector<std::size_t> counts = apportion(ring_vertices, weights, 3);

  // Latitude 0 is the +y pole; angle runs from +x towards +z, so (angle dir) x (pole-to-pole dir) is outward.
  const auto north = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.push_back(center + Vec3f{0.0f, radius, 0.0f});
  std::vector<std::uint32_t> first(ring_count);
  for (std::size_t i = 0; i < ring_count; ++i) {
    const Vec3f ring_centre = center + Vec3f{0.0f, radius * std::cos(latitude[i]), 0.0f};
    first[i] = add_ring(mesh, ring_centre, {1, 0, 0}, {0, 0, 1}, radius * std::sin(latitude[i]), counts[i]);
  }
  const auto south = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.push_back(center - Vec3f{0.0f, radius, 0.0f});

  const auto n_first = static_cast<std::uint32_t>(counts.front());
  for (std::uint32_t k = 0; k < n_first; ++k) mesh.triangles.push_back({north, first[0] + (k + 1) % n_first, first[0] + k});
  for (std::size_t i = 0; i + 1 < ring_count; ++i)
    stitch_rings(mesh, first[i], static_cast<std::uint32_t>(counts[i]), first[i + 1], static_cast<std::uint32_t>(counts[i + 1]));
  const auto n_last = static_cast<std::uint32_t>(counts.back());
  for (std::uint32_t k = 0; k < n_last; ++k) mesh.triangles.push_back({south, first.back() + k, first.back() + (k + 1) % n_last});
  return mesh;
}

namespace {

// Centre line of the (p, q) torus knot and its derivative.
struct KnotCurve {
  float p, q;
  Vec3f point(float t) const {
    const float rho = 2.0f + std::cos(q * t);
    return {rho * std::cos(p * t), rho * std::sin(p * t), std::sin(q * t)};
  }
  Vec3f tangent(float t) const {
    const float rho = 2.0f + std::cos(q * t), drho = -q * std::sin(q * t);
    return {drho * std::cos(p * t) - p * rho * std::sin(p * t), drho * std::sin(p * t) + p * rho * std::cos(p * t),
            q * std::cos(q * t)};
  }
  float length() const {
    constexpr int kSteps = 4096;
    double sum = 0.0;
    for (int k = 0; k < kSteps; ++k) sum += vf::length(tangent(kTwoPi * (static_cast<float>(k) + 0.5f) / kSteps));
    return static_cast<float>(sum * kTwoPi / kSteps);
  }
};

}  // namespace

TriangleMesh make_torus_knot_mesh(std::string name, int p, int q, float tube_radius, std::size_t triangle_count) {
  TriangleMesh mesh;
  mesh.name = std::move(name);
  const KnotCurve curve{static_cast<float>(p), static_cast<float>(q)};
  const std::size_t ring_vertices = triangle_count / 2;
  // Square-ish triangles: rings along the curve / vertices around the tube = length / circumference.
  const double aspect = curve.length() / (kTwoPi * tube_radius);
  const double around = std::round(std::sqrt(static_cast<double>(ring_vertices) / aspect));
  const std::size_t per_ring = std::clamp<std::size_t>(static_cast<std::size_t>(std::max(3.0, around)), 3, ring_vertices / 3);
  const std::size_t ring_count = std::clamp<std::size_t>(ring_vertices / per_ring, 3, ring_vertices / 3);
  const std::vector<std::size_t> counts = apportion(ring_vertices, std::vector<double>(ring_count, 1.0), 3);

  std::vector<std::uint32_t> first(ring_count);
  for (std::size_t i = 0; i < ring_count; ++i) {
    const float t = kTwoPi * static_cast<float>(i) / static_cast<float>(ring_count);
    const Vec3f centre = curve.point(t);
    // A frame that depends only on t is periodic, so the last ring stitches to the first without a twist.
    // The tangent always has an azimuthal component and the centre none, so the cross product is non-zero.
    const Vec3f tangent = normalize(curve.tangent(t));
    const Vec3f binormal = normalize(cross(tangent, centre));
    const Vec3f normal = cross(binormal, tangent);
    // (angle dir at 0) x (along the curve) = binormal x tangent = normal: outward.
    first[i] = add_ring(mesh, centre, normal, binormal, tube_radius, counts[i]);
  }
  for (std::size_t i = 0; i < ring_count; ++i) {
    const std::size_t next = (i + 1) % ring_count;
    stitch_rings(mesh, first[i], static_cast<std::uint32_t>(counts[i]), first[next], static_cast<std::uint32_t>(counts[next]));
  }
  return mesh;
}

}  // namespace vf::scenes

#pragma once
/// \file Procedural triangle sets for the differential tests: random soups (several scales),
/// coplanar sets, duplicates, a shared-edge height field.

#include <array>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "visfield/core/mesh.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::test {

using Triangle = std::array<Vec3f, 3>;

/// A mesh of the given triangles with unshared vertices, in the given order.
inline TriangleMesh mesh_from_triangles(const std::vector<Triangle>& triangles) {
  TriangleMesh mesh;
  mesh.name = "test";
  for (const Triangle& t : triangles) {
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), t.begin(), t.end());
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

/// A scene of one object (identity transform) holding the triangles.
inline Scene scene_from_triangles(const std::vector<Triangle>& triangles) {
  return scene_from_mesh(mesh_from_triangles(triangles));
}

/// The flattened triangles of scene_from_triangles(triangles).
inline TriangleSet set_from_triangles(const std::vector<Triangle>& triangles) {
  return flatten(scene_from_triangles(triangles));
}

/// A scene of `copies` objects of each of the given meshes, each copy rotated about a random axis by
/// a random angle, scaled by a random factor in [0.5, 2] and moved to a random place in a box of
/// `spread` times the meshes' size, so that copies overlap and interpenetrate. Ids follow the order
/// mesh 0 copies, mesh 1 copies, ...
inline Scene scattered_copies(std::vector<TriangleMesh> meshes, int copies, float spread, std::uint64_t seed) {
  Rng rng(seed, 0x1c5u);
  Scene scene;
  scene.name = "scattered copies";
  Bounds3f all;
  for (const TriangleMesh& m : meshes) all.extend(m.bounds());
  const float size = max_component(all.extent());
  scene.meshes = std::move(meshes);
  for (std::uint32_t m = 0; m < scene.meshes.size(); ++m) {
    for (int c = 0; c < copies; ++c) {
      Transform t;
      const Vec3f axis{rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f};
      t.rotation = Mat3::rotation(length(axis) > 1e-3f ? axis : Vec3f{0, 1, 0}, 360.0f * rng.uniform());
      t.scale = std::exp2(2.0f * rng.uniform() - 1.0f);
      t.translation = Vec3f{rng.uniform(), rng.uniform(), rng.uniform()} * (spread * size);
      scene.add_instance(m, t);
    }
  }
  return scene;
}

/// Random point in [0, 1)^3.
inline Vec3f random_point(Rng& rng) { return {rng.uniform(), rng.uniform(), rng.uniform()}; }

/// `count` triangles with centres uniform in the unit cube and corners within a cube of half-size s
/// around the centre, s log-uniform in [min_size, max_size].
inline std::vector<Triangle> random_soup(std::uint64_t seed, std::size_t count, float min_size, float max_size) {
  Rng rng(seed, 0x50u);
  std::vector<Triangle> out;
  out.reserve(count);
  const float log_min = std::log(min_size), log_max = std::log(max_size);
  while (out.size() < count) {
    const Vec3f c = random_point(rng);
    const float s = std::exp(log_min + (log_max - log_min) * rng.uniform());
    Triangle t;
    for (Vec3f& p : t) p = c + (random_point(rng) * 2.0f - Vec3f(1.0f)) * s;
    if (!is_degenerate_triangle(t[0], t[1], t[2])) out.push_back(t);
  }
  return out;
}

/// `levels` shells of `per_level` random triangles about the origin, every second level half the
/// size of the one before: a deep, narrow BVH (40 levels bound a GPU traversal stack near 100
/// entries, 80 past 128, so the kernels' largest stack capacity runs).
inline std::vector<Triangle> nested_shells(int levels, std::size_t per_level) {
  std::vector<Triangle> shells;
  for (int level = 0; level < levels; ++level) {
    const float r = std::ldexp(1.0f, -level / 2);
    // Made at unit size and scaled: made at their own size, the deep levels' corners would round
    // together in the unit cube.
    for (const Triangle& t : random_soup(100 + static_cast<std::uint64_t>(level), per_level, 0.05f * std::max(r, 0x1p-8f), 0.1f * std::max(r, 0x1p-8f)))
      shells.push_back({t[0] * r, t[1] * r, t[2] * r});
  }
  return shells;
}

/// `count` random triangles all in the plane through `origin` spanned by e1, e2 (exactly in it when
/// the plane is axis-aligned, to rounding otherwise).
inline std::vector<Triangle> coplanar_soup(std::uint64_t seed, std::size_t count, Vec3f origin, Vec3f e1, Vec3f e2) {
  Rng rng(seed, 0xc0u);
  std::vector<Triangle> out;
  while (out.size() < count) {
    const float cu = rng.uniform(), cv = rng.uniform(), s = 0.02f + 0.2f * rng.uniform();
    Triangle t;
    for (Vec3f& p : t) p = origin + e1 * (cu + s * (rng.uniform() - 0.5f)) + e2 * (cv + s * (rng.uniform() - 0.5f));
    if (!is_degenerate_triangle(t[0], t[1], t[2])) out.push_back(t);
  }
  return out;
}

/// A height field of n x n quads (2 triangles each) over [0,1]^2 with random heights: every inner
/// edge and vertex is shared, as in a closed mesh.
inline std::vector<Triangle> height_field(std::uint64_t seed, int n) {
  Rng rng(seed, 0x4fu);
  std::vector<float> h(static_cast<std::size_t>(n + 1) * (n + 1));
  for (float& x : h) x = 0.2f * rng.uniform();
  const auto vertex = [&](int i, int j) {
    return Vec3f{static_cast<float>(i) / n, h[static_cast<std::size_t>(j) * (n + 1) + i], static_cast<float>(j) / n};
  };
  std::vector<Triangle> out;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      out.push_back({vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1)});
      out.push_back({vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
    }
  return out;
}

}  // namespace vf::test

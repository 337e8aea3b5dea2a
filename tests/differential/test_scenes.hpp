#pragma once
/// \file Procedural triangle sets for the differential tests: random soups (several scales),
/// coplanar sets, duplicates, a shared-edge height field.

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "visfield/core/mesh.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::test {

using Triangle = std::array<Vec3f, 3>;

/// A TriangleSet of one mesh (identity instance) with unshared vertices, in the given order.
inline TriangleSet set_from_triangles(const std::vector<Triangle>& triangles) {
  TriangleMesh mesh;
  mesh.name = "test";
  for (const Triangle& t : triangles) {
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), t.begin(), t.end());
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return flatten(scene_from_mesh(std::move(mesh)));
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

#pragma once
/// \file Ray sets for the differential tests: random, axis-parallel, zero direction components,
/// origins on surfaces, grazing rays, t ranges ending exactly at hits, model-style rays.

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "visfield/core/ray.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::test {

/// Uniform random point in `b` grown by `margin` times its extent on every side.
inline Vec3f point_around(Rng& rng, const Bounds3f& b, float margin) {
  const Vec3f e = b.extent();
  return {b.lo.x - margin * e.x + (1 + 2 * margin) * e.x * rng.uniform(),
          b.lo.y - margin * e.y + (1 + 2 * margin) * e.y * rng.uniform(),
          b.lo.z - margin * e.z + (1 + 2 * margin) * e.z * rng.uniform()};
}

/// Uniform random direction.
inline Vec3f random_direction(Rng& rng) { return uniform_sphere(rng.uniform(), rng.uniform()); }

/// Point with barycentrics (u, v) on triangle t (u of corner 1, v of corner 2).
inline Vec3f point_on(const std::array<Vec3f, 3>& t, float u, float v) {
  return t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * v;
}

/// Random origins around the set, random directions, unbounded.
inline std::vector<Ray> random_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  Rng rng(seed, 0x1u);
  std::vector<Ray> rays(n);
  for (Ray& r : rays) r = Ray{point_around(rng, set.bounds, 0.5f), random_direction(rng)};
  return rays;
}

/// Directions along +-x, +-y, +-z.
inline std::vector<Ray> axis_parallel_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  Rng rng(seed, 0x2u);
  std::vector<Ray> rays(n);
  for (Ray& r : rays) {
    Vec3f dir{0.0f};
    dir[static_cast<int>(rng.next_u32() % 3)] = rng.uniform() < 0.5f ? -1.0f : 1.0f;
    r = Ray{point_around(rng, set.bounds, 0.2f), dir};
  }
  return rays;
}

/// One direction component exactly zero (+0 or -0), with the origin's coordinate on that axis often
/// equal to a triangle corner's, so that the ray runs exactly in a plane of some box.
inline std::vector<Ray> zero_component_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  Rng rng(seed, 0x3u);
  std::vector<Ray> rays(n);
  for (Ray& r : rays) {
    Vec3f dir = random_direction(rng);
    const int axis = static_cast<int>(rng.next_u32() % 3);
    dir[axis] = rng.uniform() < 0.5f ? -0.0f : 0.0f;
    if (dir[(axis + 1) % 3] == 0.0f && dir[(axis + 2) % 3] == 0.0f) dir[(axis + 1) % 3] = 1.0f;
    Vec3f org = point_around(rng, set.bounds, 0.2f);
    if (set.size() > 0 && rng.uniform() < 0.7f) {
      const auto& t = set.triangles[rng.next_u32() % set.size()];
      org[axis] = t[rng.next_u32() % 3][axis];
    }
    r = Ray{org, dir};
  }
  return rays;
}

/// Origins exactly on a triangle's corner, on an edge, or inside it; random directions, tmin = 0.
inline std::vector<Ray> surface_origin_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  Rng rng(seed, 0x4u);
  std::vector<Ray> rays(n);
  for (Ray& r : rays) {
    const auto& t = set.triangles[rng.next_u32() % set.size()];
    Vec3f org;
    switch (rng.next_u32() % 3) {
      case 0: org = t[rng.next_u32() % 3]; break;
      case 1: {
        const int k = static_cast<int>(rng.next_u32() % 3);
        const float s = rng.uniform();
        org = t[k] + (t[(k + 1) % 3] - t[k]) * s;
        break;
      }
      default: {
        const float u = rng.uniform(), v = rng.uniform() * (1.0f - u);
        org = point_on(t, u, v);
      }
    }
    r = Ray{org, random_direction(rng)};
  }
  return rays;
}

/// Rays in (to rounding) a triangle's plane: along an edge line, and through an inner point from
/// outside the triangle.
inline std::vector<Ray> grazing_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  Rng rng(seed, 0x5u);
  std::vector<Ray> rays(n);
  for (Ray& r : rays) {
    const auto& t = set.triangles[rng.next_u32() % set.size()];
    if (rng.uniform() < 0.5f) {
      const int k = static_cast<int>(rng.next_u32() % 3);
      const Vec3f edge = t[(k + 1) % 3] - t[k];
      r = Ray{t[k] - edge * (0.5f + rng.uniform()), edge};
    } else {
      const float u = rng.uniform(), v = rng.uniform() * (1.0f - u);
      const Vec3f inner = point_on(t, u, v);
      const Vec3f in_plane = (t[1] - t[0]) * (rng.uniform() - 0.5f) + (t[2] - t[0]) * (rng.uniform() - 0.5f);
      r = Ray{inner - in_plane * (1.0f + rng.uniform()), in_plane};
    }
  }
  return rays;
}

/// For every ray the oracle hits at t: copies with tmax = t, tmin = t, tmax just below t and tmin
/// just above t (in that order, four per hit).
inline std::vector<Ray> boundary_t_rays(std::span<const Ray> rays, const std::vector<std::optional<Hit>>& hits) {
  std::vector<Ray> out;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!hits[i]) continue;
    const float t = hits[i]->t;
    Ray r = rays[i];
    out.push_back(Ray{r.org, r.dir, r.tmin, t});
    out.push_back(Ray{r.org, r.dir, t, r.tmax});
    out.push_back(Ray{r.org, r.dir, r.tmin, std::nextafter(t, -std::numeric_limits<float>::infinity())});
    out.push_back(Ray{r.org, r.dir, std::nextafter(t, std::numeric_limits<float>::infinity()), r.tmax});
  }
  return out;
}

/// Model-style rays: half between two uniform points of the bounding sphere (segment, tmax = 1), half
/// from random surface points along a cosine-weighted direction about either side of the triangle's
/// normal (AO-like; tmin = 0, tmax unbounded or a random fraction of the scene size).
inline std::vector<Ray> model_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  Rng rng(seed, 0x6u);
  const Vec3f centre = set.bounds.center();
  const float radius = 0.5f * length(set.bounds.extent()) * 1.01f;
  std::vector<Ray> rays(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (i % 2 == 0) {
      const Vec3f a = centre + random_direction(rng) * radius, b = centre + random_direction(rng) * radius;
      rays[i] = Ray{a, b - a, 0.0f, 1.0f};
      continue;
    }
    const auto& t = set.triangles[rng.next_u32() % set.size()];
    const float u = rng.uniform(), v = rng.uniform() * (1.0f - u);
    Vec3f normal = normalize(cross(t[1] - t[0], t[2] - t[0]));
    if (!is_finite(normal)) normal = random_direction(rng);  // cross product underflowed
    if (rng.uniform() < 0.5f) normal = -normal;
    Vec3f tangent, bitangent;
    orthonormal_basis(normal, tangent, bitangent);
    const Vec3f local = cosine_hemisphere(rng.uniform(), rng.uniform());
    const Vec3f dir = tangent * local.x + bitangent * local.y + normal * local.z;
    const float tmax = rng.uniform() < 0.5f ? std::numeric_limits<float>::infinity() : radius * rng.uniform();
    rays[i] = Ray{point_on(t, u, v), dir, 0.0f, tmax};
  }
  return rays;
}

}  // namespace vf::test

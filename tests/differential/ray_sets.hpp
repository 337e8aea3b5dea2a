#pragma once
/// \file Ray sets for the differential tests: random, axis-parallel, zero direction components,
/// origins on surfaces, grazing rays, intervals reaching behind the origin, rays a denormal or an ulp
/// off a corner's planes, tiny directions, t ranges ending exactly at hits, model-style rays.

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "visfield/core/ray.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::test {

/// Uniform random point in `b` grown by `margin` times its extent on every side (a flat axis counts
/// 1% of the largest extent, so that rays start off a flat scene's plane: one starting on it would
/// not hit it, tmin being exclusive).
inline Vec3f point_around(Rng& rng, const Bounds3f& b, float margin) {
  const Vec3f e = max(b.extent(), Vec3f(0.01f * max_component(b.extent())));
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

/// A triangle of the set, uniformly at random.
inline const std::array<Vec3f, 3>& random_triangle(Rng& rng, const TriangleSet& set) {
  return set.triangles[rng.next_u32() % set.size()];
}

/// A uniform random point of triangle t.
inline Vec3f random_point_on(Rng& rng, const std::array<Vec3f, 3>& t) {
  const float u = rng.uniform(), v = rng.uniform() * (1.0f - u);
  return point_on(t, u, v);
}

/// `n` rays, the i-th made by `make(rng)` from one generator seeded by (seed, stream).
template <class Make>
std::vector<Ray> generate_rays(std::uint64_t seed, std::uint64_t stream, std::size_t n, Make&& make) {
  Rng rng(seed, stream);
  std::vector<Ray> rays(n);
  for (Ray& r : rays) r = make(rng);
  return rays;
}

/// Random origins around the set, random directions, unbounded.
inline std::vector<Ray> random_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  return generate_rays(seed, 0x1u, n, [&](Rng& rng) { return Ray{point_around(rng, set.bounds, 0.5f), random_direction(rng)}; });
}

/// Directions along +-x, +-y, +-z.
inline std::vector<Ray> axis_parallel_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  return generate_rays(seed, 0x2u, n, [&](Rng& rng) {
    Vec3f dir{0.0f};
    dir[static_cast<int>(rng.next_u32() % 3)] = rng.uniform() < 0.5f ? -1.0f : 1.0f;
    return Ray{point_around(rng, set.bounds, 0.2f), dir};
  });
}

/// One direction component exactly zero (+0 or -0), with the origin's coordinate on that axis often
/// equal to a triangle corner's, so that the ray runs exactly in a plane of some box.
inline std::vector<Ray> zero_component_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  return generate_rays(seed, 0x3u, n, [&](Rng& rng) {
    Vec3f dir = random_direction(rng);
    const int axis = static_cast<int>(rng.next_u32() % 3);
    dir[axis] = rng.uniform() < 0.5f ? -0.0f : 0.0f;
    if (dir[(axis + 1) % 3] == 0.0f && dir[(axis + 2) % 3] == 0.0f) dir[(axis + 1) % 3] = 1.0f;
    Vec3f org = point_around(rng, set.bounds, 0.2f);
    if (set.size() > 0 && rng.uniform() < 0.7f) {
      const auto& t = random_triangle(rng, set);
      org[axis] = t[rng.next_u32() % 3][axis];
    }
    return Ray{org, dir};
  });
}

/// Origins exactly on a triangle's corner, on an edge, or inside it; random directions, tmin = 0.
inline std::vector<Ray> surface_origin_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  return generate_rays(seed, 0x4u, n, [&](Rng& rng) {
    const auto& t = random_triangle(rng, set);
    Vec3f org;
    switch (rng.next_u32() % 3) {
      case 0: org = t[rng.next_u32() % 3]; break;
      case 1: {
        const int k = static_cast<int>(rng.next_u32() % 3);
        org = t[k] + (t[(k + 1) % 3] - t[k]) * rng.uniform();
        break;
      }
      default: org = random_point_on(rng, t);
    }
    return Ray{org, random_direction(rng)};
  });
}

/// Rays in (to rounding) a triangle's plane: along an edge line, and through an inner point from
/// outside the triangle.
inline std::vector<Ray> grazing_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  return generate_rays(seed, 0x5u, n, [&](Rng& rng) {
    const auto& t = random_triangle(rng, set);
    if (rng.uniform() < 0.5f) {
      const int k = static_cast<int>(rng.next_u32() % 3);
      const Vec3f edge = t[(k + 1) % 3] - t[k];
      return Ray{t[k] - edge * (0.5f + rng.uniform()), edge};
    } else {
      const Vec3f inner = random_point_on(rng, t);
      const Vec3f in_plane = (t[1] - t[0]) * (rng.uniform() - 0.5f) + (t[2] - t[0]) * (rng.uniform() - 0.5f);
      return Ray{inner - in_plane * (1.0f + rng.uniform()), in_plane};
    }
  });
}

/// Intervals that start behind the origin (tmin from a quarter to twice the set's diagonal below
/// zero), half of the rays along an axis: the hits behind count, nearest to tmin first, and boxes
/// wholly behind the origin (a flat face's) must not be culled.
inline std::vector<Ray> behind_origin_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  const float diagonal = length(set.bounds.hi - set.bounds.lo) * 1.5f + 1e-3f;
  return generate_rays(seed, 0x7u, n, [&](Rng& rng) {
    Ray r{point_around(rng, set.bounds, 0.2f), random_direction(rng)};
    if (rng.uniform() < 0.5f) {
      r.dir = Vec3f{0.0f, 0.0f, 0.0f};
      r.dir[static_cast<int>(rng.next_u32() % 3)] = rng.uniform() < 0.5f ? -1.0f : 1.0f;
    }
    r.tmin = -diagonal * (0.25f + 1.75f * rng.uniform());
    return r;
  });
}

/// Rays towards a triangle corner along an axis from outside the set, their other coordinates the
/// corner's moved by a denormal (where the corner's is zero, as in a box at the origin) or by one
/// ulp, and their other direction components zero or denormal: the planes through corners lie a
/// denormal or an ulp away, and reciprocals of denormal components overflow.
inline std::vector<Ray> denormal_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  static constexpr float kTiny[] = {0.0f, -0.0f, 1e-45f, -1e-45f, 1e-40f, -1e-40f, 1e-38f};
  const float reach = max_component(set.bounds.hi - set.bounds.lo) + 1e-3f;
  return generate_rays(seed, 0x8u, n, [&](Rng& rng) {
    const auto& t = random_triangle(rng, set);
    const Vec3f corner = t[rng.next_u32() % 3];
    const int axis = static_cast<int>(rng.next_u32() % 3);
    const float sign = rng.uniform() < 0.5f ? -1.0f : 1.0f;
    Ray r{corner, Vec3f{0.0f, 0.0f, 0.0f}};
    r.dir[axis] = sign;
    r.org[axis] = corner[axis] - sign * reach * (0.1f + rng.uniform());
    for (int a = 0; a < 3; ++a) {
      if (a == axis) continue;
      const float off = kTiny[rng.next_u32() % std::size(kTiny)];
      r.org[a] = corner[a] != 0.0f && rng.uniform() < 0.5f ? std::nextafter(corner[a], off < 0.0f ? -INFINITY : INFINITY) : corner[a] + off;
      r.dir[a] = kTiny[rng.next_u32() % std::size(kTiny)];
    }
    return r;
  });
}

/// Random rays whose directions are scaled down to lengths of 1e-38 to 1e-30: hit distances near and
/// past the largest float, where a computed t that overflows is no hit (in occluded as in intersect).
inline std::vector<Ray> tiny_direction_rays(const TriangleSet& set, std::uint64_t seed, std::size_t n) {
  static constexpr float kScale[] = {1e-30f, 1e-36f, 1e-37f, 1e-38f};
  return generate_rays(seed, 0x9u, n, [&](Rng& rng) {
    return Ray{point_around(rng, set.bounds, 0.2f), random_direction(rng) * kScale[rng.next_u32() % std::size(kScale)]};
  });
}

/// For every ray the oracle hits at t: copies with tmax = t, tmin = t, tmax just below t and tmin
/// just below t (in that order, four per hit). The range is (tmin, tmax]: the first and the last
/// must find the hit at t, the second and third must not.
inline std::vector<Ray> boundary_t_rays(std::span<const Ray> rays, const std::vector<Hit>& hits) {
  std::vector<Ray> out;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!hits[i]) continue;
    const float t = hits[i].t;
    Ray r = rays[i];
    out.push_back(Ray{r.org, r.dir, r.tmin, t});
    out.push_back(Ray{r.org, r.dir, t, r.tmax});
    out.push_back(Ray{r.org, r.dir, r.tmin, std::nextafter(t, -std::numeric_limits<float>::infinity())});
    out.push_back(Ray{r.org, r.dir, std::nextafter(t, -std::numeric_limits<float>::infinity()), r.tmax});
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
    const auto& t = random_triangle(rng, set);
    const Vec3f on_surface = random_point_on(rng, t);
    Vec3f normal = normalize(cross(t[1] - t[0], t[2] - t[0]));
    if (!is_finite(normal)) normal = random_direction(rng);  // cross product underflowed
    if (rng.uniform() < 0.5f) normal = -normal;
    Vec3f tangent, bitangent;
    orthonormal_basis(normal, tangent, bitangent);
    const Vec3f local = cosine_hemisphere(rng.uniform(), rng.uniform());
    const Vec3f dir = tangent * local.x + bitangent * local.y + normal * local.z;
    const float tmax = rng.uniform() < 0.5f ? std::numeric_limits<float>::infinity() : radius * rng.uniform();
    rays[i] = Ray{on_surface, dir, 0.0f, tmax};
  }
  return rays;
}

}  // namespace vf::test

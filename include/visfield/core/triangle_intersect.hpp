#pragma once
/// \file Watertight ray–triangle intersection (Woop, Benthin, Wald, JCGT 2013), shared by every
/// exact structure so that they agree bit for bit with the brute-force oracle. Host and device: the
/// CUDA BVH (include/visfield/gpu/bvh_traversal.hpp) runs this very test (its Vec3f operators are
/// constexpr, which nvcc's --expt-relaxed-constexpr admits in device code).

#include "visfield/core/host_device.hpp"
#include "visfield/core/ray.hpp"

namespace vf {

/// Per-ray constants of the watertight test: the permutation that makes dir's largest component z,
/// and the shear that maps dir to +z. Compute once per ray; O(1).
struct WatertightRay {
  Vec3f org;
  int kx = 0, ky = 1, kz = 2;
  float sx = 0, sy = 0, sz = 1;

  /// Precomputes the shear for `ray`; dir must be non-zero.
  VF_HOST_DEVICE explicit WatertightRay(const Ray& ray) : org(ray.org) {
    const Vec3f a{hd::abs(ray.dir.x), hd::abs(ray.dir.y), hd::abs(ray.dir.z)};
    kz = max_axis(a);
    kx = kz == 2 ? 0 : kz + 1;
    ky = kx == 2 ? 0 : kx + 1;
    if (ray.dir[kz] < 0.0f) {
      const int k = kx;
      kx = ky;
      ky = k;
    }
    sx = ray.dir[kx] / ray.dir[kz];
    sy = ray.dir[ky] / ray.dir[kz];
    sz = 1.0f / ray.dir[kz];
  }
};

/// Result of one triangle test: t and the barycentrics of vertices 1 and 2.
struct TriangleHit {
  float t, u, v;
};

/// The largest finite float: a hit's computed t must not exceed it.
inline constexpr float kLargestHitT = 3.40282347e+38f;

/// Watertight test of triangle (p0, p1, p2) against the ray for t in (tmin, tmax]; true and `out`
/// filled on a hit. Edges shared by two triangles are never missed by both. Both sides hit. tmin is
/// exclusive (as in Embree and pbrt): a ray that starts on a triangle does not hit it at t = tmin.
/// A t that overflows (a direction or determinant so small that t_scaled / det passes the largest
/// float) is no hit, even with tmax = inf: a hit's t is always finite, so a test of whether t is
/// finite is a test of whether it hit, and occluded() is whether intersect() hits.
VF_HOST_DEVICE inline bool intersect_triangle(const WatertightRay& r, const Vec3f& p0, const Vec3f& p1, const Vec3f& p2,
                               float tmin, float tmax, TriangleHit& out) {
  const Vec3f a = p0 - r.org, b = p1 - r.org, c = p2 - r.org;
  const float ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
  const float bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
  const float cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
  float e0 = cx * by - cy * bx;  // weight of p0
  float e1 = ax * cy - ay * cx;  // weight of p1
  float e2 = bx * ay - by * ax;  // weight of p2
  if (e0 == 0.0f || e1 == 0.0f || e2 == 0.0f) {
    // On an edge in float: decide in double so that neighbours agree (the paper's fallback).
    e0 = static_cast<float>(static_cast<double>(cx) * by - static_cast<double>(cy) * bx);
    e1 = static_cast<float>(static_cast<double>(ax) * cy - static_cast<double>(ay) * cx);
    e2 = static_cast<float>(static_cast<double>(bx) * ay - static_cast<double>(by) * ax);
  }
  if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f)) return false;
  const float det = e0 + e1 + e2;
  if (det == 0.0f) return false;
  const float az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
  const float t_scaled = e0 * az + e1 * bz + e2 * cz;
  const float inv_det = 1.0f / det;
  const float t = t_scaled * inv_det;
  if (!(t > tmin && t <= tmax && t <= kLargestHitT)) return false;
  out = {t, e1 * inv_det, e2 * inv_det};
  return true;
}

}  // namespace vf

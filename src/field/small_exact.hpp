#pragma once
// Occlusion by the exact part of a scene of fields when it is small (a ground, a few walls): every
// triangle tested against a packet of rays, 16 (AVX-512) or 8 (AVX2) at a time. A lone ray's BVH
// walk costs more than a field lookup (its setup, a root node of 8 boxes, a leaf), and in a mixed
// scene every ray makes one; here a triangle costs a few operations a ray.

#include <array>
#include <cstdint>
#include <span>

#include "visfield/core/ray.hpp"

namespace vf::field {

/// Exact parts of at most this many triangles are tested triangle by triangle (more go through their BVH).
inline constexpr std::size_t kSmallExactTriangles = 64;

/// occluded[i] = 1 when rays[i] hits one of `triangles` in (tmin, tmax] by the watertight test, else 0:
/// bit for bit what intersect_triangle() decides one ray and triangle at a time (and so what a Bvh or
/// BruteForce over them answers). Packets of lanes, the rest one by one; O(rays · triangles).
void occluded_by_small_exact(std::span<const std::array<Vec3f, 3>> triangles, std::span<const Ray> rays, std::uint8_t* occluded);

}  // namespace vf::field

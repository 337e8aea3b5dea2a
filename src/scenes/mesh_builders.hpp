#pragma once
// Mesh building blocks shared by the built-in scene generators (internal to visfield_scenes).

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "visfield/core/bounds.hpp"
#include "visfield/core/mesh.hpp"
#include "visfield/core/scene.hpp"

namespace vf::scenes {

/// Four corners of a planar quad, counter-clockwise seen from the side its normal points to.
using Quad = std::array<Vec3f, 4>;

/// Appends quad q as two triangles with material id `material` (material_ids kept in step).
void add_quad(TriangleMesh& mesh, const Quad& q, std::uint32_t material);

/// Appends the frame between an inner and an outer quad (same orientation, corresponding corners) as
/// four trapezoids (8 triangles) sharing the corners, so the inner quad's hole can be filled without
/// T-junctions. The frame faces the same way as the quads.
void add_quad_frame(TriangleMesh& mesh, const Quad& inner, const Quad& outer, std::uint32_t material);

/// Closed axis-aligned box: 8 shared corners, 12 outward-facing triangles; no material ids (material 0).
TriangleMesh make_box_mesh(std::string name, const Bounds3f& box);

/// Square ground quad at height y, centred on (cx, cz), facing +y; 2 triangles with material `material`;
/// an exact occluder (MeshOccluder::exact).
TriangleMesh make_ground_mesh(std::string name, float cx, float cz, float half_size, float y, std::uint32_t material);

/// Splits `total` into weights.size() parts proportional to `weights` (largest remainder, ties to the
/// lower index), each part at least `min_each`; requires total >= min_each * weights.size().
std::vector<std::size_t> apportion(std::size_t total, const std::vector<double>& weights, std::size_t min_each);

/// Closed sphere of latitude rings with exactly `triangle_count` outward triangles (even, >= 8); ring
/// vertex counts follow sin(latitude) so triangles are near-equilateral. No material ids (material 0).
TriangleMesh make_sphere_mesh(std::string name, const Vec3f& center, float radius, std::size_t triangle_count);

/// Closed (p, q) torus-knot tube with exactly `triangle_count` outward triangles (even, >= 18), in the
/// z = 0 plane around the origin: the centre line is ((2 + cos q t) cos p t, (2 + cos q t) sin p t, sin q t).
/// No material ids (material 0).
TriangleMesh make_torus_knot_mesh(std::string name, int p, int q, float tube_radius, std::size_t triangle_count);

/// Adds `material` to the scene; returns its index.
std::uint32_t add_material(Scene& scene, Material material);

/// Makes a material with the given name, diffuse albedo and emission.
Material make_material(std::string name, const Vec3f& diffuse, const Vec3f& emission = Vec3f{0.0f});

}  // namespace vf::scenes

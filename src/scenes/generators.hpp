#pragma once
// One generator per built-in scene (one file each); registry.cpp checks sizes and dispatches by name.
// `size` arrives already defaulted and range-checked.

#include <cstddef>
#include <cstdint>

#include "visfield/core/scene.hpp"

namespace vf::scenes {

/// `triangles` random triangles in the unit cube [0,1]^3 (soup.cpp).
Scene make_soup_scene(std::uint64_t seed, std::size_t triangles);
/// A torus knot of `knot_triangles` triangles in the middle of an open arena ~100x larger (stadium.cpp).
Scene make_stadium_scene(std::size_t knot_triangles);
/// A unit sphere of `sphere_triangles` triangles resting on a ground plane (sphere.cpp).
Scene make_sphere_scene(std::size_t sphere_triangles);
/// A pyramid of `box_count` instances of one cube mesh, jittered by `seed`, on a ground plane (boxes.cpp).
Scene make_boxes_scene(std::uint64_t seed, std::size_t box_count);
/// A Cornell-like room with a sphere of `sphere_triangles` triangles and two boxes (cornell.cpp).
Scene make_cornell_scene(std::size_t sphere_triangles);

}  // namespace vf::scenes

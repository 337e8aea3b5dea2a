#pragma once
/// \file Built-in procedural scenes: no file needed, every one seeded and sized by parameters.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "visfield/core/scene.hpp"

namespace vf {

/// Parameters shared by every built-in scene.
struct BuiltinParams {
  std::uint64_t seed = 1;  ///< Random seed (same seed, same scene, on every machine).
  std::size_t size = 0;    ///< Scene-specific size knob (triangle count or box count); 0 = the scene's default.
};

/// Built-in scenes are refused when they would hold more triangles than this.
inline constexpr std::size_t kMaxBuiltinTriangles = 50'000'000;

/// Names accepted by make_builtin_scene: "soup", "stadium", "sphere", "boxes", "cornell".
std::vector<std::string> builtin_scene_names();

/// One-line description of a built-in scene and what `size` means for it; throws vf::Error on an
/// unknown name.
std::string builtin_scene_description(const std::string& name);

/// Builds a built-in scene (y is up in all of them):
/// - soup: exactly `size` (default 100000) random triangles in the unit cube, as in the VLF-RT scaling test;
/// - stadium: a dense torus knot (`size` triangles, default 50000) inside an open arena ~100x its size
///   ("teapot in a stadium");
/// - sphere: a sphere of latitude rings with `size` triangles (default 20000) on a ground plane;
/// - boxes: a pyramid of `size` boxes (default 64, one instanced cube mesh), 12 triangles each, on a ground plane;
/// - cornell: a Cornell-like room with a tessellated sphere and two boxes (`size` = sphere triangles,
///   default 4000), a ceiling light quad (emissive) and a point light just below it.
/// Closed tessellated shapes (the sphere, the knot) have an even triangle count: an odd `size` is rounded
/// down. Each scene has a camera. Same (name, seed, size), same scene, bit for bit.
/// Throws vf::Error on an unknown name or a size out of the scene's range. Cost O(triangles).
Scene make_builtin_scene(const std::string& name, const BuiltinParams& params = {});

/// A parsed "builtin:NAME[:key=value,...]": the scene's name and its parameters.
struct BuiltinSpec {
  std::string name;
  BuiltinParams params;
};

/// Parses "builtin:NAME[:key=value,...]" (keys: seed, size; non-negative integers) without building
/// anything. Throws a one-line vf::Error naming the bad name, key or value.
BuiltinSpec parse_builtin_spec(const std::string& spec);

/// parse_builtin_spec, then make_builtin_scene. Throws as both do.
Scene parse_builtin_scene(const std::string& spec);

}  // namespace vf

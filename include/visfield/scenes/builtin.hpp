#pragma once
/// \file Built-in procedural scenes: no file needed, every one seeded and sized by parameters.

#include <cstdint>
#include <string>
#include <vector>

#include "visfield/core/scene.hpp"

namespace vf {

/// Parameters shared by every built-in scene.
struct BuiltinParams {
  std::uint64_t seed = 1;  ///< Random seed (same seed, same scene, on every machine).
  std::size_t size = 0;    ///< Scene-specific size knob (triangle count or tessellation); 0 = the scene's default.
};

/// Names accepted by make_builtin_scene: "soup", "stadium", "sphere", "boxes", "cornell".
std::vector<std::string> builtin_scene_names();

/// One-line description of a built-in scene and what `size` means for it.
std::string builtin_scene_description(const std::string& name);

/// Builds a built-in scene:
/// - soup: `size` (default 100000) random triangles in the unit cube, as in the VLF-RT scaling test;
/// - stadium: a dense tessellated teapot-sized object (`size` triangles, default 50000) inside a large sparse room ("teapot in a stadium");
/// - sphere: a UV-tessellated sphere with `size` triangles (default 20000) on a ground plane;
/// - boxes: a stack of `size` boxes (default 64), 12 triangles each, on a ground plane;
/// - cornell: a Cornell-like room with a tessellated sphere and two boxes (`size` = sphere triangles, default 4000),
///   with a camera and an area light.
/// Each has a camera. Throws vf::Error on an unknown name or a size out of range.
Scene make_builtin_scene(const std::string& name, const BuiltinParams& params = {});

/// Parses "builtin:NAME[:key=value,...]" (keys: seed, size) and builds that scene. Throws vf::Error
/// naming the bad key or value.
Scene parse_builtin_scene(const std::string& spec);

}  // namespace vf

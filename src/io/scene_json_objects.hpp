#pragma once
// Private to the io module: the objects of a scene JSON file (see README.md, "Scene files"), each
// read from a JsonField with every key type-checked and unknown keys refused.

#include <cstdint>
#include <map>
#include <string>

#include "visfield/core/scene.hpp"
#include "visfield/io/json_reader.hpp"

namespace vf::io_detail {

using json::JsonField;
using json::NumberRange;

/// Name -> index maps of what a scene file declared, for resolving an instance's references.
struct SceneNames {
  std::map<std::string, std::uint32_t> meshes;     ///< Index into Scene::meshes.
  std::map<std::string, std::uint32_t> materials;  ///< Index into Scene::materials.
};

/// {"name", "diffuse", "specular", "roughness", "emission"}; colours in [0, 1], emission >= 0.
Material parse_material(const JsonField& field);

/// {"mesh", "translate", "rotate_euler_deg" | "rotate_axis_angle": {"axis", "degrees"}, "scale",
/// "material"}; names resolved through `names`.
Instance parse_instance(const JsonField& field, const SceneNames& names);

/// {"position", "look_at", "up", "fov_deg", "width", "height"}.
Camera parse_camera(const JsonField& field);

/// {"type": "point", "position", "intensity"} or {"type": "sphere", "center", "radius", "radiance"},
/// appended to the scene's point or sphere lights.
void parse_light(const JsonField& field, Scene& scene);

}  // namespace vf::io_detail

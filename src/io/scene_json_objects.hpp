#pragma once
// Private to the io module: the objects of a scene JSON file (see docs/guide.md, "Scene files"), each
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

/// {"name", "diffuse", "specular", "roughness", "emission", "transmission", "ior"}; colours,
/// roughness and transmission in [0, 1], emission >= 0, ior in [1, 4].
Material parse_material(const JsonField& field);

/// {"mesh", "translate", "rotate_euler_deg" | "rotate_axis_angle": {"axis", "degrees"}, "scale",
/// "material", "keyframes"}; names resolved through `names` (the keyframes are read by parse_keyframes).
Instance parse_instance(const JsonField& field, const SceneNames& names);

/// An instance's optional "keyframes": [{"time", "translate", "rotate_euler_deg", "scale"}, ...], at
/// least two, times strictly increasing (empty when the instance has none).
std::vector<PlacementKey> parse_keyframes(const JsonField& instance);

/// "camera_path": [{"time", "position", "look_at", "up"}, ...], at least two keys, times strictly
/// increasing, look_at away from position, up not along the view.
std::vector<CameraKey> parse_camera_path(const JsonField& field);

/// {"position", "look_at", "up", "fov_deg", "width", "height"}.
Camera parse_camera(const JsonField& field);

/// {"type": "point", "position", "intensity"} or {"type": "sphere", "center", "radius", "radiance"},
/// appended to the scene's point or sphere lights.
void parse_light(const JsonField& field, Scene& scene);

}  // namespace vf::io_detail

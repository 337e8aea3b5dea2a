#include "scene_json_objects.hpp"

#include <cstdio>

#include <cmath>

namespace vf::io_detail {
namespace {

template <typename T, typename Read>
T optional_or(const JsonField& object, std::string_view key, T fallback, Read read) {
  const std::optional<JsonField> member = object.optional_member(key);
  return member ? read(*member) : fallback;
}

Vec3f vec3_or(const JsonField& object, std::string_view key, Vec3f fallback, const NumberRange& range) {
  return optional_or(object, key, fallback, [&](const JsonField& f) { return f.as_vec3(range); });
}

std::uint32_t resolve(const JsonField& field, const std::map<std::string, std::uint32_t>& known, const char* kind) {
  const std::string name = field.as_string();
  const auto it = known.find(name);
  if (it == known.end()) field.fail("no " + std::string(kind) + " named \"" + name + "\"");
  return it->second;
}

Mat3 parse_rotation(const JsonField& instance) {
  const std::optional<JsonField> euler = instance.optional_member("rotate_euler_deg");
  const std::optional<JsonField> axis_angle = instance.optional_member("rotate_axis_angle");
  if (euler && axis_angle) instance.fail("give rotate_euler_deg or rotate_axis_angle, not both");
  if (euler) return Mat3::euler_xyz(euler->as_vec3());
  if (!axis_angle) return Mat3{};
  axis_angle->require_object({"axis", "degrees"});
  const JsonField axis_field = axis_angle->member("axis");
  const Vec3f axis = axis_field.as_vec3();
  if (!(length(axis) > 0.0f) || !std::isfinite(length(axis))) axis_field.fail_expected("a non-zero axis");
  return Mat3::rotation(axis, axis_angle->member("degrees").as_float());
}

}  // namespace

Material parse_material(const JsonField& field) {
  field.require_object({"name", "diffuse", "specular", "roughness", "emission", "transmission", "ior"});
  Material m;
  m.name = field.member("name").as_string();
  const NumberRange unit = NumberRange::closed(0.0, 1.0);
  m.diffuse = vec3_or(field, "diffuse", m.diffuse, unit);
  m.specular = vec3_or(field, "specular", m.specular, unit);
  m.roughness = optional_or(field, "roughness", m.roughness, [&](const JsonField& f) { return f.as_float(unit); });
  m.emission = vec3_or(field, "emission", m.emission, NumberRange::non_negative());
  m.transmission = optional_or(field, "transmission", m.transmission, [&](const JsonField& f) { return f.as_float(unit); });
  m.ior = optional_or(field, "ior", m.ior, [](const JsonField& f) { return f.as_float(NumberRange::closed(1.0, 4.0)); });
  return m;
}

Instance parse_instance(const JsonField& field, const SceneNames& names) {
  field.require_object({"mesh", "translate", "rotate_euler_deg", "rotate_axis_angle", "scale", "material", "keyframes"});
  Instance instance;
  instance.mesh = resolve(field.member("mesh"), names.meshes, "mesh");
  instance.transform.translation = vec3_or(field, "translate", Vec3f{0.0f}, NumberRange::any());
  instance.transform.rotation = parse_rotation(field);
  instance.transform.scale = optional_or(field, "scale", 1.0f, [](const JsonField& f) {
    // Objects are rigid with one scale factor, which keeps instance normals and distances exact.
    if (f.json().is_array()) f.fail("non-uniform scale is not supported (an object takes one number > 0)");
    return f.as_float(NumberRange::positive());
  });
  if (const std::optional<JsonField> material = field.optional_member("material"))
    instance.material = resolve(*material, names.materials, "material");
  return instance;
}

namespace {

// The "time" of key `key`, which must come after `previous` (when there is one).
float key_time(const JsonField& key, const std::optional<float>& previous) {
  const JsonField time = key.member("time");
  const float t = time.as_float();
  if (previous && !(t > *previous)) {
    char text[96];
    std::snprintf(text, sizeof text, "times must increase from key to key, got %g after %g", static_cast<double>(t),
                  static_cast<double>(*previous));
    time.fail(text);
  }
  return t;
}

// "position", "look_at" (away from the position; `position_name` names it in the message) and an
// optional "up" (not along the view) of a camera or camera key.
void parse_view(const JsonField& field, const char* position_name, Vec3f& position, Vec3f& look_at, Vec3f& up) {
  position = field.member("position").as_vec3();
  const JsonField target = field.member("look_at");
  look_at = target.as_vec3();
  const Vec3f view = look_at - position;
  if (!(length(view) > 0.0f)) target.fail(std::string("must differ from ") + position_name);
  up = vec3_or(field, "up", up, NumberRange::any());
  const float up_length = length(up);
  if (!(up_length > 0.0f) || length(cross(normalize(view), up / up_length)) < 1e-4f)
    field.member("up").fail("must be non-zero and not parallel to the viewing direction");
}

}  // namespace

std::vector<PlacementKey> parse_keyframes(const JsonField& instance) {
  std::vector<PlacementKey> keys;
  const std::optional<JsonField> list = instance.optional_member("keyframes");
  if (!list) return keys;
  std::optional<float> previous;
  for (const JsonField& entry : list->elements(2)) {
    entry.require_object({"time", "translate", "rotate_euler_deg", "scale"});
    PlacementKey key;
    key.time = key_time(entry, previous);
    previous = key.time;
    key.translate = vec3_or(entry, "translate", key.translate, NumberRange::any());
    key.rotate_euler_deg = vec3_or(entry, "rotate_euler_deg", key.rotate_euler_deg, NumberRange::any());
    key.scale = optional_or(entry, "scale", key.scale, [](const JsonField& f) { return f.as_float(NumberRange::positive()); });
    keys.push_back(key);
  }
  return keys;
}

std::vector<CameraKey> parse_camera_path(const JsonField& field) {
  std::vector<CameraKey> keys;
  std::optional<float> previous;
  for (const JsonField& entry : field.elements(2)) {
    entry.require_object({"time", "position", "look_at", "up"});
    CameraKey key;
    key.time = key_time(entry, previous);
    previous = key.time;
    parse_view(entry, "position", key.position, key.look_at, key.up);
    keys.push_back(key);
  }
  return keys;
}

Camera parse_camera(const JsonField& field) {
  field.require_object({"position", "look_at", "up", "fov_deg", "width", "height"});
  Camera c;
  parse_view(field, "camera.position", c.position, c.look_at, c.up);
  c.fov_degrees = optional_or(field, "fov_deg", c.fov_degrees,
                              [](const JsonField& f) { return f.as_float(NumberRange::open(0.0, 180.0)); });
  c.width = optional_or(field, "width", c.width, [](const JsonField& f) { return f.as_int(1, 65536); });
  c.height = optional_or(field, "height", c.height, [](const JsonField& f) { return f.as_int(1, 65536); });
  return c;
}

void parse_light(const JsonField& field, Scene& scene) {
  if (!field.json().is_object()) field.fail_expected("an object");
  const JsonField type = field.member("type");
  const std::string kind = type.json().is_string() ? type.json().get<std::string>() : std::string();
  if (kind == "point") {
    field.require_object({"type", "position", "intensity"});
    PointLight light;
    light.position = field.member("position").as_vec3();
    light.intensity = vec3_or(field, "intensity", light.intensity, NumberRange::non_negative());
    scene.point_lights.push_back(light);
  } else if (kind == "sphere") {
    field.require_object({"type", "center", "radius", "radiance"});
    SphereLight light;
    light.center = field.member("center").as_vec3();
    light.radius = field.member("radius").as_float(NumberRange::positive());
    light.radiance = vec3_or(field, "radiance", light.radiance, NumberRange::non_negative());
    scene.sphere_lights.push_back(light);
  } else {
    type.fail_expected("\"point\" or \"sphere\"");
  }
}

}  // namespace vf::io_detail

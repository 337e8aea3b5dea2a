#include "visfield/io/scene_file.hpp"

#include "file_checks.hpp"
#include "scene_json_objects.hpp"
#include "visfield/core/error.hpp"
#include "visfield/io/json_reader.hpp"
#include "visfield/io/mesh_loader.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

// A mesh's "field": a .vfield path, or an object of table parameters (checked when the field is
// built, against the same table as `field:` specs) with an optional "path". The path is relative to
// the scene file, like the mesh path; it need not exist yet (a cache).
void read_mesh_field(const json::JsonField& field, const std::filesystem::path& folder, TriangleMesh& mesh) {
  if (field.json().is_string()) {
    mesh.field_file = (folder / field.as_string()).string();
    return;
  }
  if (!field.json().is_object()) field.fail_expected("a .vfield path or an object of field parameters");
  field.require_object({"path", "positions", "directions", "mapping", "storage", "normals"});
  if (const std::optional<json::JsonField> path = field.optional_member("path")) mesh.field_file = (folder / path->as_string()).string();
  for (const char* key : {"positions", "directions", "mapping", "storage", "normals"}) {
    const std::optional<json::JsonField> value = field.optional_member(key);
    if (!value) continue;
    const std::string text = value->json().is_number() ? std::to_string(value->as_uint64(0, 1u << 30)) : value->as_string();
    if (text.find_first_of(",=:") != std::string::npos) value->fail("expected a single value");
    if (!mesh.field_params.empty()) mesh.field_params += ',';
    mesh.field_params.append(key).append("=").append(text);
  }
}

// Loads every entry of "meshes" (paths relative to `folder`) into `scene`, recording their names.
void load_meshes(const json::JsonField& meshes, const std::filesystem::path& folder, Scene& scene,
                 io_detail::SceneNames& names) {
  for (const json::JsonField& entry : meshes.elements(1)) {
    entry.require_object({"name", "path", "occluder", "field"});
    const json::JsonField path_field = entry.member("path");
    const std::filesystem::path path = folder / path_field.as_string();
    const std::optional<json::JsonField> name_field = entry.optional_member("name");
    const std::string name = name_field ? name_field->as_string() : path.stem().string();
    if (names.meshes.contains(name))
      (name_field ? *name_field : path_field).fail("a mesh named \"" + name + "\" is already declared");
    LoadedMesh loaded;
    try {
      loaded = load_mesh(path);
    } catch (const Error& e) {
      path_field.fail(e.what());
    }
    loaded.mesh.name = name;
    if (const std::optional<json::JsonField> occluder = entry.optional_member("occluder")) {
      const std::string kind = occluder->as_string();
      if (kind == "exact")
        loaded.mesh.occluder = MeshOccluder::exact;
      else if (kind == "field")
        loaded.mesh.occluder = MeshOccluder::field;
      else
        occluder->fail("expected \"exact\" or \"field\"");
    }
    if (const std::optional<json::JsonField> field = entry.optional_member("field")) read_mesh_field(*field, folder, loaded.mesh);
    names.meshes.emplace(name, add_mesh(scene, std::move(loaded)));
  }
}

void parse_materials(const json::JsonField& materials, Scene& scene, io_detail::SceneNames& names) {
  for (const json::JsonField& entry : materials.elements()) {
    Material material = io_detail::parse_material(entry);
    if (names.materials.contains(material.name))
      entry.member("name").fail("a material named \"" + material.name + "\" is already declared");
    names.materials.emplace(material.name, static_cast<std::uint32_t>(scene.materials.size()));
    scene.materials.push_back(std::move(material));
  }
}

}  // namespace

Scene load_scene_file(const std::filesystem::path& path) {
  const nlohmann::json document = json::parse_json_file(path);
  const json::JsonField root(document, path.string());
  root.require_object({"name", "meshes", "materials", "instances", "camera", "lights", "camera_path"});

  Scene scene;
  const std::optional<json::JsonField> name = root.optional_member("name");
  scene.name = name ? name->as_string() : path.stem().string();
  io_detail::SceneNames names;
  // Materials first, so the file's own materials keep indices 1.. whatever the meshes bring along.
  if (const std::optional<json::JsonField> materials = root.optional_member("materials"))
    parse_materials(*materials, scene, names);
  load_meshes(root.member("meshes"), path.parent_path(), scene, names);

  if (const std::optional<json::JsonField> instances = root.optional_member("instances")) {
    for (const json::JsonField& entry : instances->elements(1)) {
      const ObjectId id = scene.add_instance(io_detail::parse_instance(entry, names));
      std::vector<PlacementKey> keys = io_detail::parse_keyframes(entry);
      if (!keys.empty()) scene.animation.objects.push_back(ObjectPath{id, std::move(keys)});
    }
  } else {
    for (std::uint32_t m = 0; m < scene.meshes.size(); ++m) scene.add_instance(m);
  }
  scene.check_coordinate_range(path.string());
  // Every key of a moving object must keep it inside the coordinate range too.
  for (const ObjectPath& moving : scene.animation.objects) {
    const Transform start = scene.instance(moving.object).transform;
    for (const PlacementKey& key : moving.keys) {
      scene.set_transform(moving.object, SceneAnimation::placement_at(moving, key.time));
      scene.check_coordinate_range(path.string() + " (keyframe at time " + std::to_string(key.time) + ")");
    }
    scene.set_transform(moving.object, start);
  }
  if (const std::optional<json::JsonField> camera = root.optional_member("camera"))
    scene.camera = io_detail::parse_camera(*camera);
  if (const std::optional<json::JsonField> path_keys = root.optional_member("camera_path"))
    scene.animation.camera = io_detail::parse_camera_path(*path_keys);
  if (const std::optional<json::JsonField> lights = root.optional_member("lights"))
    for (const json::JsonField& entry : lights->elements()) io_detail::parse_light(entry, scene);
  return scene;
}

Scene load_scene(const std::string& spec) {
  if (spec.empty()) throw Error("empty scene argument (expected builtin:NAME, a .json scene file or a mesh file)");
  if (spec.starts_with("builtin:")) return parse_builtin_scene(spec);
  const std::filesystem::path path(spec);
  if (io_detail::lower_extension(path) == "json") return load_scene_file(path);
  Scene scene;
  scene.name = path.stem().string();
  scene.add_instance(add_mesh(scene, load_mesh(path)));
  return scene;
}

}  // namespace vf

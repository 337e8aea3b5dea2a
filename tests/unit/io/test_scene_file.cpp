// Scene JSON files: the documented format, and one-line errors naming file and JSON path.

#include <gtest/gtest.h>

#include <cmath>

#include "io_test_support.hpp"
#include "visfield/io/scene_file.hpp"

namespace vf {
namespace {

using test::expect_one_line_error;
using test::TempDir;
using test::write_file;

const std::string kTetra = "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nv -1 -1 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n";

// A scratch folder holding meshes/tetra.obj, where tests drop scene files.
struct SceneDir {
  TempDir dir;
  SceneDir() {
    std::filesystem::create_directory(dir / "meshes");
    write_file(dir / "meshes/tetra.obj", kTetra);
  }
  std::filesystem::path scene(const std::string& json) const { return write_file(dir / "scene.json", json); }
};

// Loads `json` as a scene file and requires a one-line error "<file>: <field>: ...<detail>...".
void expect_scene_error(const std::string& json, const std::string& field, const std::string& detail) {
  SceneDir d;
  const auto path = d.scene(json);
  const std::string message = expect_one_line_error([&] { load_scene_file(path); }, path.string() + ": " + field);
  EXPECT_NE(message.find(detail), std::string::npos) << message;
}

TEST(SceneFile, ExampleFromTheRepositoryLoads) {
  const Scene scene = load_scene_file(std::filesystem::path(VISFIELD_SOURCE_DIR) / "examples/scenes/example.json");
  EXPECT_EQ(scene.name, "example");
  ASSERT_EQ(scene.meshes.size(), 2u);
  EXPECT_EQ(scene.meshes[0].triangles.size(), 4u);
  EXPECT_EQ(scene.meshes[1].triangles.size(), 2u);
  EXPECT_EQ(scene.instances().size(), 4u);
  EXPECT_EQ(scene.materials.size(), 4u);  // the default plus three
  ASSERT_TRUE(scene.camera.has_value());
  EXPECT_EQ(scene.camera->width, 640);
  EXPECT_EQ(scene.point_lights.size(), 1u);
  EXPECT_EQ(scene.sphere_lights.size(), 1u);
}

TEST(SceneFile, EveryFieldIsRead) {
  SceneDir d;
  const Scene scene = load_scene_file(d.scene(R"({
    "name": "full",
    "meshes": [{"name": "t", "path": "meshes/tetra.obj"}],
    "materials": [{"name": "shiny", "diffuse": [0.1, 0.2, 0.3], "specular": [0.4, 0.5, 0.6], "roughness": 0.25,
                   "emission": [7, 8, 9]}],
    "instances": [
      {"mesh": "t"},
      {"mesh": "t", "translate": [1, 2, 3], "rotate_euler_deg": [0, 90, 0], "scale": 2, "material": "shiny"},
      {"mesh": "t", "rotate_axis_angle": {"axis": [0, 0, 2], "degrees": 90}}
    ],
    "camera": {"position": [0, 1, 5], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 30, "width": 320, "height": 200},
    "lights": [{"type": "point", "position": [1, 5, 1], "intensity": [10, 10, 10]},
               {"type": "sphere", "center": [0, 4, 0], "radius": 0.5, "radiance": [2, 3, 4]}]
  })"));
  EXPECT_EQ(scene.name, "full");
  ASSERT_EQ(scene.materials.size(), 2u);
  const Material& shiny = scene.materials[1];
  EXPECT_EQ(shiny.name, "shiny");
  EXPECT_FLOAT_EQ(shiny.diffuse.z, 0.3f);
  EXPECT_FLOAT_EQ(shiny.specular.x, 0.4f);
  EXPECT_FLOAT_EQ(shiny.roughness, 0.25f);
  EXPECT_FLOAT_EQ(shiny.emission.y, 8.0f);

  ASSERT_EQ(scene.instances().size(), 3u);
  EXPECT_FALSE(scene.instances()[0].material.has_value());
  const Transform& moved = scene.instances()[1].transform;
  EXPECT_EQ(scene.instances()[1].material, 1u);
  EXPECT_FLOAT_EQ(moved.scale, 2.0f);
  const Vec3f p = moved.apply_point({1, 0, 0});  // rotated 90 degrees about +y: x -> -z, then *2, +t
  EXPECT_NEAR(p.x, 1.0f, 1e-5f);
  EXPECT_NEAR(p.y, 2.0f, 1e-5f);
  EXPECT_NEAR(p.z, 1.0f, 1e-5f);
  const Vec3f q = scene.instances()[2].transform.apply_point({1, 0, 0});  // 90 degrees about +z: x -> y
  EXPECT_NEAR(q.x, 0.0f, 1e-6f);
  EXPECT_NEAR(q.y, 1.0f, 1e-6f);

  ASSERT_TRUE(scene.camera.has_value());
  EXPECT_EQ(scene.camera->position, (Vec3f{0, 1, 5}));
  EXPECT_FLOAT_EQ(scene.camera->fov_degrees, 30.0f);
  EXPECT_EQ(scene.camera->width, 320);
  EXPECT_EQ(scene.camera->height, 200);
  ASSERT_EQ(scene.point_lights.size(), 1u);
  EXPECT_EQ(scene.point_lights[0].intensity, (Vec3f{10, 10, 10}));
  ASSERT_EQ(scene.sphere_lights.size(), 1u);
  EXPECT_FLOAT_EQ(scene.sphere_lights[0].radius, 0.5f);
  EXPECT_EQ(scene.sphere_lights[0].radiance, (Vec3f{2, 3, 4}));
}

TEST(SceneFile, WithoutInstancesEveryMeshGetsAnIdentityInstance) {
  SceneDir d;
  write_file(d.dir / "meshes/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const Scene scene = load_scene_file(d.scene(R"({"meshes": [{"path": "meshes/tetra.obj"}, {"path": "meshes/tri.obj"}]})"));
  ASSERT_EQ(scene.instances().size(), 2u);
  EXPECT_EQ(scene.instances()[0].mesh, 0u);
  EXPECT_EQ(scene.instances()[1].mesh, 1u);
  EXPECT_FLOAT_EQ(scene.instances()[1].transform.scale, 1.0f);
  EXPECT_EQ(scene.meshes[1].name, "tri");  // the file stem names an unnamed mesh
  EXPECT_EQ(scene.name, "scene");
  EXPECT_FALSE(scene.camera.has_value());
}

TEST(SceneFile, AMeshSaysHowFieldOccludersTreatIt) {
  SceneDir d;
  write_file(d.dir / "meshes/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const Scene scene = load_scene_file(d.scene(
      R"({"meshes": [{"path": "meshes/tetra.obj", "occluder": "field"}, {"path": "meshes/tri.obj", "occluder": "exact"},
                     {"name": "plain", "path": "meshes/tri.obj"}]})"));
  EXPECT_EQ(scene.meshes[0].occluder, MeshOccluder::field);
  EXPECT_EQ(scene.meshes[1].occluder, MeshOccluder::exact);
  EXPECT_EQ(scene.meshes[2].occluder, MeshOccluder::automatic);
  EXPECT_EQ(scene.meshes[2].field_file, "");
  const Scene cached = load_scene_file(d.scene(R"({"meshes": [{"path": "meshes/tetra.obj", "field": "fields/tetra.vfield"}]})"));
  EXPECT_EQ(cached.meshes[0].field_file, (d.dir / "fields/tetra.vfield").string());
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj", "occluder": "approximate"}]})", "meshes[0].occluder",
                     "expected \"exact\" or \"field\"");
}

TEST(SceneFile, AMeshsFieldMayGiveItsParameters) {
  SceneDir d;
  const Scene scene = load_scene_file(d.scene(
      R"({"meshes": [{"path": "meshes/tetra.obj", "occluder": "field",
                      "field": {"positions": 1090, "directions": 64, "storage": "u16", "normals": "oct16", "path": "f/t.vfield"}}]})"));
  EXPECT_EQ(scene.meshes[0].field_params, "positions=1090,directions=64,storage=u16,normals=oct16");
  EXPECT_EQ(scene.meshes[0].field_file, (d.dir / "f/t.vfield").string());
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj", "field": {"resolution": 3}}]})", "meshes[0].field",
                     "unknown key \"resolution\"");
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj", "field": 7}]})", "meshes[0].field",
                     "expected a .vfield path or an object of field parameters");
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj", "field": {"directions": -1}}]})", "meshes[0].field.directions",
                     "expected");
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj", "field": {"mapping": "a,b"}}]})", "meshes[0].field.mapping",
                     "expected a single value");
}

TEST(SceneFile, CommentsAreAllowed) {
  SceneDir d;
  const Scene scene = load_scene_file(d.scene("// a comment\n{\"meshes\": [{\"path\": \"meshes/tetra.obj\"}] /* here too */}"));
  EXPECT_EQ(scene.meshes.size(), 1u);
}

TEST(SceneFile, MalformedJsonNamesLineAndColumn) {
  expect_scene_error("{\n  \"meshes\": [\n    {\"path\": \"meshes/tetra.obj\",}\n  ]\n}", "invalid JSON at line 3, column",
                     "syntax error");
}

TEST(SceneFile, RepeatedKeyIsRefused) {
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj", "path": "meshes/tetra.obj"}]})", "invalid JSON",
                     "\"path\" appears twice");
}

TEST(SceneFile, WrongFieldType) {
  expect_scene_error(R"({"meshes": [{"path": 5}]})", "meshes[0].path", "expected a non-empty string, got 5");
  expect_scene_error(R"({"meshes": {"path": "meshes/tetra.obj"}})", "meshes", "expected an array of at least 1 element");
  expect_scene_error(R"([1, 2])", "top level", "expected an object");
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj"}], "instances": [{"mesh": "tetra", "translate": [1, 2]}]})",
                     "instances[0].translate", "expected an array of 3 numbers");
  expect_scene_error(
      R"({"meshes": [{"path": "meshes/tetra.obj"}], "materials": [{"name": "m", "diffuse": [0.5, 1.5, 0]}]})",
      "materials[0].diffuse[1]", "expected a number in [0, 1], got 1.5");
}

TEST(SceneFile, UnknownKey) {
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj"}], "instances": [{"mesh": "tetra", "scael": 2}]})",
                     "instances[0]", "unknown key \"scael\"");
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj"}], "lihgts": []})", "top level", "unknown key \"lihgts\"");
}

TEST(SceneFile, UnknownReferences) {
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj"}], "instances": [{"mesh": "bunny"}]})",
                     "instances[0].mesh", "no mesh named \"bunny\"");
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj"}], "instances": [{"mesh": "tetra", "material": "gold"}]})",
                     "instances[0].material", "no material named \"gold\"");
}

TEST(SceneFile, NegativeOrNonNumericScale) {
  const std::string head = R"({"meshes": [{"path": "meshes/tetra.obj"}], "instances": [{"mesh": "tetra"}, {"mesh": "tetra", "scale": )";
  expect_scene_error(head + "-1}]}", "instances[1].scale", "expected a number > 0, got -1");
  expect_scene_error(head + "\"big\"}]}", "instances[1].scale", "expected a number > 0, got \"big\"");
  expect_scene_error(head + "0}]}", "instances[1].scale", "expected a number > 0");
}

TEST(SceneFile, BadCamera) {
  const std::string head = R"({"meshes": [{"path": "meshes/tetra.obj"}], "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], )";
  expect_scene_error(head + R"("width": 0}})", "camera.width", "expected an integer in 1..65536, got 0");
  expect_scene_error(head + R"("width": 100.5}})", "camera.width", "expected an integer in 1..65536");
  expect_scene_error(head + R"("height": 70000}})", "camera.height", "expected an integer in 1..65536");
  expect_scene_error(head + R"("fov_deg": 180}})", "camera.fov_deg", "expected a number in (0, 180)");
  expect_scene_error(head + R"("up": [0, 0, 1]}})", "camera.up", "parallel");
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj"}], "camera": {"position": [1, 1, 1], "look_at": [1, 1, 1]}})",
                     "camera.look_at", "must differ");
}

TEST(SceneFile, BadInstancesAndLights) {
  const std::string meshes = R"({"meshes": [{"path": "meshes/tetra.obj"}], )";
  expect_scene_error(meshes + R"("instances": []})", "instances", "expected an array of at least 1 element");
  expect_scene_error(meshes + R"("instances": [{"mesh": "tetra", "rotate_euler_deg": [0, 0, 0], "rotate_axis_angle": {"axis": [0, 1, 0], "degrees": 1}}]})",
                     "instances[0]", "not both");
  expect_scene_error(meshes + R"("instances": [{"mesh": "tetra", "rotate_axis_angle": {"axis": [0, 0, 0], "degrees": 1}}]})",
                     "instances[0].rotate_axis_angle.axis", "non-zero");
  expect_scene_error(meshes + R"("lights": [{"type": "spot", "position": [0, 0, 0]}]})", "lights[0].type",
                     "expected \"point\" or \"sphere\", got \"spot\"");
  expect_scene_error(meshes + R"("lights": [{"type": "sphere", "center": [0, 0, 0], "radius": -1}]})", "lights[0].radius",
                     "expected a number > 0");
  expect_scene_error(meshes + R"("lights": [{"type": "point", "position": [0, 0, 0], "radius": 1}]})", "lights[0]",
                     "unknown key \"radius\"");
}

TEST(SceneFile, DuplicateNames) {
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj"}, {"path": "meshes/tetra.obj"}]})", "meshes[1].path",
                     "already declared");
  expect_scene_error(R"({"meshes": [{"path": "meshes/tetra.obj"}], "materials": [{"name": "a"}, {"name": "a"}]})",
                     "materials[1].name", "already declared");
}

TEST(SceneFile, MeshErrorsNameTheSceneFieldAndTheMeshFile) {
  SceneDir d;
  const auto path = d.scene(R"({"meshes": [{"path": "meshes/absent.ply"}]})");
  const std::string message =
      expect_one_line_error([&] { load_scene_file(path); }, path.string() + ": meshes[0].path: ");
  EXPECT_NE(message.find("absent.ply: no such file"), std::string::npos) << message;
}

TEST(SceneFile, MissingSceneFile) {
  TempDir dir;
  expect_one_line_error([&] { load_scene_file(dir / "nope.json"); }, "nope.json: no such file");
}

TEST(LoadScene, DispatchesOnTheArgument) {
  SceneDir d;
  const Scene from_mesh = load_scene((d.dir / "meshes/tetra.obj").string());
  ASSERT_EQ(from_mesh.meshes.size(), 1u);
  ASSERT_EQ(from_mesh.instances().size(), 1u);
  EXPECT_EQ(from_mesh.meshes[0].triangles.size(), 4u);
  EXPECT_EQ(from_mesh.name, "tetra");

  const Scene from_json = load_scene(d.scene(R"({"meshes": [{"path": "meshes/tetra.obj"}]})").string());
  EXPECT_EQ(from_json.instances().size(), 1u);

  const Scene builtin = load_scene("builtin:boxes");
  EXPECT_FALSE(builtin.meshes.empty());
  EXPECT_FALSE(builtin.instances().empty());

  expect_one_line_error([] { load_scene(""); }, "empty scene argument");
  EXPECT_THROW(load_scene("builtin:no-such-scene"), Error);
  expect_one_line_error([&] { load_scene((d.dir / "absent.obj").string()); }, "absent.obj: no such file");
}

}  // namespace
}  // namespace vf

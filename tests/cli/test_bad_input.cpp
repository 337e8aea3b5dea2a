// The bad-input catalogue: every row of the table in docs/bad-input.md ("What visfield refuses, and
// what it says") is one case here. Each runs the visfield command a user would type over the files it names
// and expects the documented exit code, exactly one line on stderr (the whole message, not a
// fragment of it), and no output file left behind. A last test checks that the catalogue quotes every
// message, so the table and the program cannot drift apart.
//
// Adding a row: one entry in catalogue() and the same message in docs/bad-input.md's table.

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "support/run_command.hpp"
#include "visfield/field/field_file.hpp"
#include "visfield/select/calibration.hpp"

namespace vf {
namespace {

namespace fs = std::filesystem;

struct Row {
  std::string name;  // test name
  std::vector<std::pair<std::string, std::string>> files;  // written into the work folder first
  std::string args;
  int exit_code = 1;
  // The line visfield prints: after "visfield: error: " when exit_code != 0, else a line of stdout
  // or stderr. "…" stands for a part that depends on the machine; the rest must match exactly.
  std::string message;
};

// gtest prints a failing parameter with this: the row's name, not its bytes.
void PrintTo(const Row& row, std::ostream* os) { *os << row.name; }

std::string u32(std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); }
std::string f32(float v) { return std::string(reinterpret_cast<const char*>(&v), 4); }

const std::string kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

std::string ply_header(const std::string& format, std::uint64_t vertices, std::uint64_t faces) {
  return "ply\nformat " + format + " 1.0\nelement vertex " + std::to_string(vertices) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(faces) +
         "\nproperty list uchar int vertex_indices\nend_header\n";
}

// A binary PLY triangle with `x1` as the second corner's x and `c2` as the third index.
std::string binary_ply(float x1, std::int32_t c2) {
  std::string body;
  for (float v : {0.0f, 0.0f, 0.0f, x1, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}) body += f32(v);
  body += '\3' + u32(0) + u32(1) + u32(static_cast<std::uint32_t>(c2));
  return ply_header("binary_little_endian", 3, 1) + body;
}

std::string stl_triangle() {
  std::string t;
  for (float v : {0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}) t += f32(v);
  return t + std::string(2, '\0');
}

std::string glb(std::uint32_t json_bytes, const std::string& json) {
  return "glTF" + u32(2) + u32(static_cast<std::uint32_t>(20 + json.size())) + u32(json_bytes) + "JSON" + json;
}

// Bytes no format accepts, the same on every run.
std::string garbage() {
  std::string g;
  std::uint32_t x = 2026;
  for (int i = 0; i < 2000; ++i) {
    x = x * 1664525u + 1013904223u;
    g += static_cast<char>(0x80 | (x >> 24));  // high bytes only: not text, not a digit
  }
  return g;
}

// The built-in calibration as if measured on another CPU, with 2 threads.
std::string calibration_of_another_machine() {
  Calibration c = builtin_calibration();
  c.machine = MachineInfo{"elsewhere", 2, "Another CPU"};
  return calibration_to_json(c);
}

std::string nested(int depth) { return std::string(static_cast<std::size_t>(depth), '[') + std::string(static_cast<std::size_t>(depth), ']'); }

// A valid .vfield file of a tetrahedron (290 positions x 8^2), optionally with one byte changed.
std::string field_file(std::size_t flip_at = 0) {
  TriangleSet set;
  const Vec3f a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0}, d{0, 0, 1};
  for (const std::array<Vec3f, 3>& t : {std::array<Vec3f, 3>{a, b, c}, {a, b, d}, {a, c, d}, {b, c, d}}) {
    set.triangles.push_back(t);
    set.prim.push_back(static_cast<std::uint32_t>(set.prim.size()));
    set.instance.push_back(kInvalidId);
    for (const Vec3f& p : t) set.bounds.extend(p);
  }
  std::string bytes = field::encode_field(field::ObjectField::build(set, {.positions = 290, .directions = 8}), field::mesh_hash(set));
  if (flip_at > 0) bytes[flip_at] ^= 0x01;
  return bytes;
}

// field_file() rewritten as format version `version`, its checksum recomputed.
std::string field_file_of_version(std::uint32_t version) {
  std::string bytes = field_file();
  std::memcpy(bytes.data() + 8, &version, 4);
  return field::with_field_checksum(std::move(bytes));
}

std::string scene_json(const std::string& rest) { return R"({"meshes": [{"path": "tri.obj"}])" + rest + "}"; }

std::vector<Row> catalogue() {
  const std::string render = "render --no-progress --width 8 --height 8 --ao-rays 1 --out out.png ";
  const std::pair<std::string, std::string> tri{"tri.obj", kTriangleObj};
  std::vector<Row> rows = {
      {"EmptyObj", {{"empty.obj", ""}}, render + "empty.obj", 1, "empty.obj: the file is empty"},
      {"EmptyPly", {{"empty.ply", ""}}, render + "empty.ply", 1, "empty.ply: the file is empty"},
      {"EmptyStl", {{"empty.stl", ""}}, render + "empty.stl", 1, "empty.stl: the file is empty"},
      {"EmptyGlb", {{"empty.glb", ""}}, render + "empty.glb", 1, "empty.glb: the file is empty"},
      {"EmptyGltf", {{"empty.gltf", ""}}, render + "empty.gltf", 1, "empty.gltf: the file is empty"},
      {"EmptySceneJson", {{"empty.json", ""}}, render + "empty.json", 1, "empty.json: the file is empty"},
      // Files that are missing, empty, cut short or not of their format.
      {"MissingFile", {}, render + "missing.obj", 1, "missing.obj: no such file"},
      {"Directory", {}, render + ".", 1, ".: is a directory, not a file"},
      {"UnsupportedFormat", {{"notes.xyz", "hello\n"}}, render + "notes.xyz", 1,
       "notes.xyz: unsupported mesh format (expected .obj, .ply, .gltf, .glb, .stl or another format Assimp reads)"},
      {"TruncatedObj", {{"cut.obj", "v 0 0 0\nv 1 0 0\nv 0 1"}}, render + "cut.obj", 1,
       "cut.obj: malformed OBJ: Validation failed: Mesh contains no faces"},
      {"TruncatedAsciiPly", {{"cut.ply", ply_header("ascii", 3, 1) + "0 0 0\n1 0 0\n"}}, render + "cut.ply", 1,
       "cut.ply: malformed PLY: the header declares 3 vertex and 1 face elements (at least 19 bytes of ascii data) but only "
       "12 bytes follow it"},
      {"TruncatedBinaryPly", {{"cut.ply", binary_ply(1.0f, 2).substr(0, 200)}}, render + "cut.ply", 1,
       "cut.ply: malformed PLY: the header declares 3 vertex and 1 face elements (at least 37 bytes of "
       "binary_little_endian data) but only 31 bytes follow it"},
      {"TruncatedBinaryStl", {{"cut.stl", std::string(80, '\0') + u32(2) + stl_triangle()}}, render + "cut.stl", 1,
       "cut.stl: malformed STL: the header declares 2 triangles (184 bytes) but the file holds 134 bytes"},
      {"TruncatedAsciiStl", {{"cut.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0"}},
       render + "cut.stl", 1,
       "cut.stl: malformed STL: Cannot parse string \"\" as a real number: does not start with digit or decimal point "
       "followed by digit."},
      {"TruncatedGltf", {{"cut.gltf", R"({"asset": {"version": "2.0"}, "meshes": [{"primitives": [)"}},
       render + "cut.gltf", 1, "cut.gltf: malformed GLTF: the JSON is invalid or cut short"},
      {"TruncatedGlb", {{"cut.glb", glb(600, R"({"asset": {"version": "2.0"}})")}}, render + "cut.glb", 1,
       "cut.glb: malformed GLB: the header declares 600 bytes of JSON but only 29 bytes follow it"},
      {"TruncatedSceneJson", {tri, {"cut.json", R"({"meshes": [{"path": "tri.obj"})"}}, render + "cut.json", 1,
       "cut.json: invalid JSON at line 1, column 32: syntax error while parsing array - unexpected end of input; expected "
       "']'"},
      {"GarbageObj", {{"junk.obj", garbage()}}, render + "junk.obj", 1, "junk.obj: the file holds no mesh (no faces)"},
      {"GarbagePly", {{"junk.ply", garbage()}}, render + "junk.ply", 1, "junk.ply: malformed PLY: the file does not start with \"ply\""},
      {"GarbageStl", {{"junk.stl", garbage()}}, render + "junk.stl", 1,
       "junk.stl: malformed STL: the header declares … triangles (… bytes) but the file holds 2000 bytes"},
      {"GarbageGlb", {{"junk.glb", garbage()}}, render + "junk.glb", 1, "junk.glb: malformed GLB: the file does not start with \"glTF\""},
      {"GarbageGltf", {{"junk.gltf", garbage()}}, render + "junk.gltf", 1, "junk.gltf: malformed GLTF: the JSON is invalid or cut short"},
      {"GarbageSceneJson", {{"junk.json", garbage()}}, render + "junk.json", 1,
       "junk.json: invalid JSON at line 1, column 1: syntax error while parsing value - invalid literal; last read: '…'"},
      // Headers that declare more than the file holds: refused from the header, nothing allocated.
      {"PlyDeclaringBillions", {{"big.ply", ply_header("ascii", 4000000000u, 1) + "0 0 0\n"}}, render + "big.ply", 1,
       "big.ply: malformed PLY: the header declares 4000000000 vertex and 1 face elements (at least 24000000001 bytes of "
       "ascii data) but only 6 bytes follow it"},
      {"StlDeclaringBillions", {{"big.stl", std::string(80, '\0') + u32(4000000000u) + stl_triangle()}}, render + "big.stl", 1,
       "big.stl: malformed STL: the header declares 4000000000 triangles (200000000084 bytes) but the file holds 134 bytes"},
      {"GlbDeclaringBillions", {{"big.glb", glb(4000000000u, "{}")}}, render + "big.glb", 1,
       "big.glb: malformed GLB: the header declares 4000000000 bytes of JSON but only 2 bytes follow it"},
      // JSON nested or sized to exhaust a parser.
      {"DeeplyNestedSceneJson", {{"deep.json", nested(100000)}}, render + "deep.json", 1,
       "deep.json: invalid JSON: arrays and objects nested more than 64 deep"},
      {"DeeplyNestedGltf", {{"deep.gltf", R"({"asset": {"version": "2.0"}, "x": )" + nested(100000) + "}"}}, render + "deep.gltf", 1,
       "deep.gltf: malformed GLTF: invalid JSON: arrays and objects nested more than 64 deep"},
      {"HugeSceneJson", {{"huge.json", ""}}, render + "huge.json", 1,  // grown to 300 MiB (sparse) below
       "huge.json: 300.00 MiB of JSON, more than the 256.00 MiB visfield reads (meshes belong in mesh files)"},
      {"NumberBeyondDouble", {tri, {"far.json", scene_json(R"(, "instances": [{"mesh": "tri", "translate": [1e999, 0, 0]}])")}},
       render + "far.json", 1, "far.json: invalid JSON: number overflow parsing '1e999'"},
      // Coordinates and indices.
      {"NanCoordinate", {{"nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"}}, render + "nan.obj", 1,
       "nan.obj: vertex 1 has a NaN or infinite coordinate"},
      {"InfiniteCoordinate", {{"inf.ply", binary_ply(1.0f / 0.0f, 2)}}, render + "inf.ply", 1,
       "inf.ply: vertex 1 has a NaN or infinite coordinate"},
      {"HugeCoordinate", {{"far.obj", "v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n"}}, render + "far.obj", 1,
       "far.obj: vertex 1 has coordinate 1e+30, beyond the ±1e+12 visfield supports"},
      {"HugeCoordinateAfterPlacement", {tri, {"placed.json", scene_json(R"(, "instances": [{"mesh": "tri", "scale": 1e13}])")}},
       render + "placed.json", 1, "placed.json: object 0 (mesh 0 \"tri\") reaches coordinate 1e+13 in world space, beyond the ±1e+12 visfield "
       "supports"},
      {"IndexOutOfRange", {{"index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"}}, render + "index.obj", 1,
       "index.obj: malformed OBJ: vertex index out of range"},
      {"NegativeIndexOutOfRange", {{"index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -9\n"}}, render + "index.obj", 1,
       "index.obj: malformed OBJ: vertex index out of range"},
      {"NegativePlyIndex", {{"index.ply", binary_ply(1.0f, -5)}}, render + "index.ply", 1,
       "index.ply: malformed PLY: Validation failed: aiMesh::mFaces[0]::mIndices[2] is out of range"},
      // Degenerate geometry and scenes.
      {"OnlyZeroAreaTriangles", {{"flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n"}}, render + "flat.obj", 1,
       "flat.obj: the scene has no non-degenerate triangles"},
      {"SomeZeroAreaTriangles", {{"some.obj", kTriangleObj + "v 2 0 0\nf 1 2 4\n"}}, render + "some.obj", 0,
       "visfield: warning: some.obj: 1 zero-area triangles left out of the acceleration structure"},
      {"DuplicateTriangles", {{"twice.obj", kTriangleObj + "f 3 1 2\n"}}, "info twice.obj", 0,
       "duplicates:         1 triangles repeat another's vertices (kept)"},
      {"SceneWithoutMeshes", {{"none.json", R"({"meshes": []})"}}, render + "none.json", 1,
       "none.json: meshes: expected an array of at least 1 element, got []"},
      {"SceneWithoutObjects", {tri, {"none.json", scene_json(R"(, "instances": [])")}}, render + "none.json", 1,
       "none.json: instances: expected an array of at least 1 element, got []"},
      {"InstanceOfMissingMesh", {tri, {"ref.json", scene_json(R"(, "instances": [{"mesh": "bunny"}])")}}, render + "ref.json", 1,
       "ref.json: instances[0].mesh: no mesh named \"bunny\""},
      {"MeshFileMissing", {{"ref.json", R"({"meshes": [{"path": "gone.obj"}]})"}}, render + "ref.json", 1,
       "ref.json: meshes[0].path: gone.obj: no such file"},
      {"IndexOfRefractionBelowOne", {tri, {"glass.json", scene_json(R"(, "materials": [{"name": "glass", "ior": 0.5}])")}},
       render + "glass.json", 1, "glass.json: materials[0].ior: expected a number in [1, 4], got 0.5"},
      {"TransmissionAboveOne", {tri, {"glass.json", scene_json(R"(, "materials": [{"name": "glass", "transmission": 2}])")}},
       render + "glass.json", 1, "glass.json: materials[0].transmission: expected a number in [0, 1], got 2"},
      {"KeyTimesOutOfOrder",
       {tri, {"path.json", scene_json(R"(, "camera_path": [{"time": 1, "position": [0, 0, 5], "look_at": [0, 0, 0]},
                                                          {"time": 1, "position": [1, 0, 5], "look_at": [0, 0, 0]}])")}},
       render + "path.json", 1, "path.json: camera_path[1].time: times must increase from key to key, got 1 after 1"},
      {"WalkOfAStillScene", {tri, {"still.json", scene_json("")}}, "walk --no-progress --csv w.csv still.json", 1,
       "still.json: the scene has no \"camera_path\" and no object \"keyframes\"; nothing to walk through"},
      // Transforms.
      {"ZeroScale", {tri, {"t.json", scene_json(R"(, "instances": [{"mesh": "tri", "scale": 0}])")}}, render + "t.json", 1,
       "t.json: instances[0].scale: expected a number > 0, got 0"},
      {"NonUniformScale", {tri, {"t.json", scene_json(R"(, "instances": [{"mesh": "tri", "scale": [1, 2, 3]}])")}},
       render + "t.json", 1, "t.json: instances[0].scale: non-uniform scale is not supported (an object takes one number > 0)"},
      {"ZeroRotationAxis",
       {tri, {"t.json", scene_json(R"(, "instances": [{"mesh": "tri", "rotate_axis_angle": {"axis": [0, 0, 0], "degrees": 10}}])")}},
       render + "t.json", 1, "t.json: instances[0].rotate_axis_angle.axis: expected a non-zero axis, got [0,0,0]"},
      // Cameras.
      {"CameraUpAlongView",
       {tri, {"c.json", scene_json(R"(, "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "up": [0, 0, 1]})")}},
       render + "c.json", 1, "c.json: camera.up: must be non-zero and not parallel to the viewing direction"},
      {"CameraFovZero",
       {tri, {"c.json", scene_json(R"(, "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_deg": 0})")}},
       render + "c.json", 1, "c.json: camera.fov_deg: expected a number in (0, 180), got 0"},
      {"CameraFov180",
       {tri, {"c.json", scene_json(R"(, "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_deg": 180})")}},
       render + "c.json", 1, "c.json: camera.fov_deg: expected a number in (0, 180), got 180"},
      {"CameraLookingAtItself", {tri, {"c.json", scene_json(R"(, "camera": {"position": [0, 0, 5], "look_at": [0, 0, 5]})")}},
       render + "c.json", 1, "c.json: camera.look_at: must differ from camera.position"},
      // Calibration files.
      {"CalibrationOfAnotherVersion", {{"cal.json", R"({"format": "visfield-calibration", "version": 99})"}},
       "select builtin:cornell --rays 1e6 --calibration cal.json", 1,
       "cal.json: version: unsupported version 99 (this build reads version 3; run visfield calibrate again)"},
      {"CalibrationOfAnotherMachine", {{"cal.json", calibration_of_another_machine()}},
       "select builtin:cornell --rays 1e6 --calibration cal.json", 1,
       "cal.json: measured on Another CPU with 2 threads, but this is …: its timings do not apply (run visfield calibrate "
       "here…)"},
      // The planner.
      {"PlanErrorOutOfRange", {}, "select builtin:cornell --rays 1e6 --error 300", 2, "--error: must be a number in [0, 255], got 300"},
      {"PlanUpdatesNotWhole", {}, "select builtin:cornell --rays 1e6 --updates 1.5", 1,
       "--updates: expected a whole number of rays in 0..1e15, got 1.500000"},
      {"PlanProfileOverMaxMemory", {}, "select builtin:boxes:size=8 --rays 100 --max-memory 6KiB", 1,
       "primary rays: … rays would need about …, more than --max-memory 6.0 KiB"},
      {"AutoErrorOutOfRange", {}, render + "builtin:cornell --accel auto:error=300", 2, "--accel: auto: error=300: expected a number in [0, 255]"},
      {"FieldTargetRmsUnreachable", {tri}, "field build tri.obj --target-rms 0.01 -o tri.vfield", 1,
       "--target-rms 0.01: no field the planner weighs is expected to meet it (lowest bound …, positions=…,directions=…)"},
      {"FieldTargetRmsWithPositions", {tri}, "field build tri.obj --target-rms 3 --positions 1090 -o tri.vfield", 2,
       "--positions excludes --target-rms"},
      {"FieldCalibrationWithoutTargetRms", {tri}, "field build tri.obj --calibration c.json -o tri.vfield", 2,
       "--calibration requires --target-rms"},
      // ObjectField files and builds.
      {"FieldFileCutShort", {{"cut.vfield", "VISFIELD\x01"}}, "field info cut.vfield", 1,
       "cut.vfield: the file is cut short (not a complete .vfield file)"},
      {"FieldFileNotAField", {{"junk.vfield", garbage()}}, "field info junk.vfield", 1,
       "junk.vfield: not a .vfield file (no VISFIELD signature)"},
      {"FieldFileCorrupted", {{"bad.vfield", field_file(500)}}, "field info bad.vfield", 1,
       "bad.vfield: checksum mismatch (the file is corrupted or cut short)"},
      {"FieldOutputNotVfield", {tri}, "field build tri.obj -o tri.png", 1, "-o tri.png: the file name must end in .vfield"},
      {"FieldDirectionsOutOfRange", {tri}, "field build tri.obj --directions 4 -o tri.vfield", 2,
       "--directions: 4: expected a non-negative integer in 8..256"},
      {"FieldFileOfAnotherVersion", {{"old.vfield", field_file_of_version(3)}}, "field info old.vfield", 1,
       "old.vfield: .vfield version 3, this visfield reads versions 1 and 2 (rebuild it with visfield field build)"},
      {"FieldNormalsUnknown", {tri}, "field build tri.obj --normals oct8 -o tri.vfield", 2, "--normals: oct8: expected one of none, oct16, oct32"},
      {"SceneFieldParameterOutOfRange",
       {tri, {"f.json", R"({"meshes": [{"path": "tri.obj", "occluder": "field", "field": {"directions": 5}}]})"}}, render + "f.json", 1,
       "mesh tri: field: directions=5: expected a non-negative integer in 8..256"},
      {"SceneFieldUnknownKey", {tri, {"k.json", R"({"meshes": [{"path": "tri.obj", "field": {"resolution": 3}}]})"}}, render + "k.json", 1,
       "k.json: meshes[0].field: unknown key \"resolution\" (expected one of: path, positions, directions, mapping, storage, normals)"},
      {"OccludersExactWithAField", {}, render + "builtin:cornell --occluders exact --occluder field", 2,
       "--occluder: field: --occluders exact needs an exact structure"},
      {"UpNotAnAxis", {}, render + "builtin:cornell --up w", 2, "--up: expected an axis x, y or z with an optional sign (+z, -y), got \"w\""},
      {"ViewOneNumber", {}, render + "builtin:cornell --view 45", 2,
       "--view: expected AZIMUTH,ELEVATION in degrees (two numbers, \"45,30\"), got \"45\""},
      {"ViewElevationOutOfRange", {}, render + "builtin:cornell --view 0,95", 2,
       "--view: the elevation must be within [-90, 90] degrees, got \"0,95\""},
      {"CameraThreeNumbers", {}, render + "builtin:cornell --camera 1,2,3", 2,
       "--camera: expected FROM,TO[,UP[,FOV]] (6, 9 or 10 numbers: \"0,1,5,0,0,0\"), got \"1,2,3\""},
      {"CameraUpAlongTheView", {}, render + "builtin:cornell --camera 0,5,0,0,0,0", 1,
       "camera: the up axis is parallel to TO - FROM (give UP, or another up axis)"},
      {"ViewAndCamera", {}, render + "builtin:cornell --view 45,30 --camera 0,0,5,0,0,0", 2,
       "--view: --camera places the camera itself: give one of them"},
      {"BackgroundUnknown", {}, render + "builtin:cornell --background pink", 2,
       "--background: expected transparent, white, black, grey, #RRGGBB or R,G,B in [0, 1], got \"pink\""},
      {"FieldTwoPositionLookups", {}, render + "builtin:cornell --occluder field:lines=1,blend=1", 2,
       "--occluder: field: lines=1 and blend=1 are two position lookups; give one"},
      {"FieldOverMaxMemory", {}, render + "builtin:cornell --occluder field:positions=16642,directions=256,storage=f32 --max-memory 100M", 1,
       "--occluder field:positions=16642,directions=256,storage=f32: the build would need about 12.19 GiB, more than --max-memory 100.00 MiB"},
      // Resources and output.
      {"StructureOverMaxMemory", {}, render + "builtin:soup:size=1000000 --accel kdtree --max-memory 10M", 1,
       "--accel kdtree: the build would need about 347.14 MiB, more than --max-memory 10.00 MiB"},
      {"OutputFolderMissing", {}, "render builtin:cornell --no-progress --out nowhere/out.png", 1,
       "nowhere/out.png: cannot write: folder nowhere does not exist"},
      {"OutputFolderIsAFile", {tri}, "render builtin:cornell --no-progress --out tri.obj/out.png", 1,
       "tri.obj/out.png: cannot write: tri.obj is not a folder"},
      {"OutputFolderUnwritable", {}, "render builtin:cornell --no-progress --out /proc/out.png", 1,
       "/proc/out.png: cannot write: cannot create a file in /proc: …"},
      {"UnknownOutputExtension", {}, "render builtin:cornell --no-progress --out out.bmp", 1,
       "out.bmp: output must end in .png or .exr"},
      // Command lines (exit 2).
      {"NegativeMaxDistance", {}, render + "builtin:cornell --max-distance -1", 2,
       "--max-distance: -1: expected a number > 0 (or inf)"},
      {"ZeroWidth", {}, "render builtin:cornell --width 0", 2, "--width: Value 0 not in range 1 to 16384"},
      {"UnknownStructure", {}, "render builtin:cornell --accel octree", 2, "--accel: octree: unknown structure (valid: …)"},
      {"StructureParameterOutOfRange", {}, "render builtin:cornell --accel bvh:leaf=0", 2, "--accel: bvh: leaf=0: expected a non-negative integer in 1..128"},
      {"MaxMemoryNotASize", {}, "render builtin:cornell --max-memory lots", 2,
       "--max-memory: expected a size such as 4G, 512MiB or 1e9 (bytes), got lots"},
  };
  return rows;
}

// True when `line` is `pattern` with each "…" standing for any text.
bool matches(const std::string& line, const std::string& pattern) {
  const std::string kAny = "…";
  std::size_t at = 0, from = 0;
  bool first = true;
  while (true) {
    const std::size_t next = pattern.find(kAny, from);
    const std::string piece = pattern.substr(from, next == std::string::npos ? std::string::npos : next - from);
    if (first) {
      if (line.compare(0, piece.size(), piece) != 0) return false;
      at = piece.size();
      first = false;
    } else if (next == std::string::npos) {
      return line.size() >= at + piece.size() && line.compare(line.size() - piece.size(), piece.size(), piece) == 0;
    } else {
      at = line.find(piece, at);
      if (at == std::string::npos) return false;
      at += piece.size();
    }
    if (next == std::string::npos) return line.size() == at;
    from = next + kAny.size();
  }
}

class BadInput : public ::testing::TestWithParam<Row> {};

TEST_P(BadInput, FailsWithOneDocumentedLineAndNoOutput) {
  const Row& row = GetParam();
  const fs::path dir = fs::path(VISFIELD_TEST_BINARY_DIR) / "bad-input" / row.name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const auto& [name, content] : row.files) std::ofstream(dir / name, std::ios::binary) << content;
  if (row.name == "HugeSceneJson") fs::resize_file(dir / "huge.json", std::uintmax_t{300} << 20);  // sparse: no disk

  const test::CommandResult r = test::run_command(std::string(VISFIELD_EXE) + " " + row.args, dir);
  EXPECT_EQ(r.exit_code, row.exit_code) << r.err;
  if (row.exit_code != 0) {
    ASSERT_EQ(test::line_count(r.err), 1) << r.err;
    const std::string line = r.err.substr(0, r.err.find('\n'));
    EXPECT_TRUE(matches(line, "visfield: error: " + row.message)) << "got:      " << line << "\nexpected: " << row.message;
    EXPECT_EQ(r.out.find("wrote"), std::string::npos) << r.out;
    // Nothing but the inputs remains: no image, no temporary file.
    std::size_t entries = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
      ++entries;
      (void)entry;
    }
    EXPECT_EQ(entries, row.files.size()) << "a file was left behind by: visfield " << row.args;
  } else {
    bool found = false;
    for (const std::string& text : {r.out, r.err}) {
      std::size_t start = 0;
      while (start < text.size()) {
        const std::size_t end = text.find('\n', start);
        found |= matches(text.substr(start, end - start), row.message);
        start = end == std::string::npos ? text.size() : end + 1;
      }
    }
    EXPECT_TRUE(found) << "expected the line: " << row.message << "\nstdout: " << r.out << "\nstderr: " << r.err;
  }
}

INSTANTIATE_TEST_SUITE_P(Catalogue, BadInput, ::testing::ValuesIn(catalogue()),
                         [](const ::testing::TestParamInfo<Row>& info) { return info.param.name; });

TEST(BadInputCatalogue, TheDocsQuoteEveryMessage) {
  std::ifstream in(fs::path(VISFIELD_SOURCE_DIR) / "docs" / "bad-input.md");
  ASSERT_TRUE(in) << "no docs/bad-input.md in " << VISFIELD_SOURCE_DIR;
  std::string table((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Table cells escape '|' as "\|"; the messages quote no '|'.
  for (const Row& row : catalogue())
    EXPECT_NE(table.find("`" + row.message + "`"), std::string::npos) << row.name << ": docs/bad-input.md does not quote `" << row.message << "`";
}

TEST(BadInputCatalogue, PatternsMatchOnlyWhatTheySay) {
  EXPECT_TRUE(matches("a: b", "a: b"));
  EXPECT_FALSE(matches("a: bc", "a: b"));
  EXPECT_FALSE(matches("xa: b", "a: b"));
  EXPECT_TRUE(matches("a 12 b 34 c", "a … b … c"));
  EXPECT_FALSE(matches("a 12 b 34 d", "a … b … c"));
  EXPECT_TRUE(matches("cannot: anything", "cannot: …"));
}

}  // namespace
}  // namespace vf

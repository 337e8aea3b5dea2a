// The table of built-in scenes: names, descriptions, size ranges, and the "builtin:" spec parser.

#include <functional>
#include <sstream>

#include "generators.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/spec.hpp"
#include "visfield/scenes/builtin.hpp"

namespace vf {
namespace {

struct BuiltinEntry {
  const char* name;
  const char* description;
  std::size_t default_size;
  std::size_t min_size;
  std::size_t triangles_per_size_unit;  // how many triangles one unit of `size` costs (bounds the size)
  std::function<Scene(std::uint64_t seed, std::size_t size)> make;
};

const std::vector<BuiltinEntry>& entries() {
  static const std::vector<BuiltinEntry> table = {
      {"soup", "size random triangles (default 100000) in the unit cube, as in the VLF-RT scaling test", 100000, 1, 1,
       scenes::make_soup_scene},
      {"stadium",
       "a torus knot of size triangles (default 50000, even) inside an open arena ~100x larger; seed unused",
       50000, 18, 1, [](std::uint64_t, std::size_t size) { return scenes::make_stadium_scene(size); }},
      {"sphere", "a sphere of size triangles (default 20000, even) on a ground plane; seed unused", 20000, 8, 1,
       [](std::uint64_t, std::size_t size) { return scenes::make_sphere_scene(size); }},
      {"boxes", "a pyramid of size boxes (default 64), 12 triangles each, on a ground plane; seed jitters them", 64,
       1, 12, scenes::make_boxes_scene},
      {"cornell",
       "a Cornell-like room with a sphere of size triangles (default 4000, even) and two boxes; seed unused", 4000,
       8, 1, [](std::uint64_t, std::size_t size) { return scenes::make_cornell_scene(size); }},
  };
  return table;
}

std::string joined_names() {
  std::string names;
  for (const BuiltinEntry& e : entries()) names += (names.empty() ? "" : ", ") + std::string(e.name);
  return names;
}

const BuiltinEntry& find_entry(const std::string& name) {
  for (const BuiltinEntry& e : entries())
    if (name == e.name) return e;
  throw Error("builtin:" + name + ": unknown built-in scene (valid names: " + joined_names() + ")");
}

// The parameters every built-in scene takes.
constexpr ParamSpec kBuiltinParams[] = {
    {"size", ParamType::whole, "0", "scene-specific size (0 = the scene's default)"},
    {"seed", ParamType::whole, "1", "random seed"},
};

}  // namespace

std::vector<std::string> builtin_scene_names() {
  std::vector<std::string> names;
  for (const BuiltinEntry& e : entries()) names.emplace_back(e.name);
  return names;
}

std::string builtin_scene_description(const std::string& name) { return find_entry(name).description; }

Scene make_builtin_scene(const std::string& name, const BuiltinParams& params) {
  const BuiltinEntry& entry = find_entry(name);
  const std::size_t size = params.size == 0 ? entry.default_size : params.size;
  const std::size_t max_size = kMaxBuiltinTriangles / entry.triangles_per_size_unit;
  if (size < entry.min_size || size > max_size) {
    std::ostringstream msg;
    msg << "builtin:" << name << ": size " << size << " is out of range [" << entry.min_size << ", " << max_size
        << "] (at most " << kMaxBuiltinTriangles << " triangles)";
    throw Error(msg.str());
  }
  Scene scene = entry.make(params.seed, size);
  scene.name = "builtin:" + name + ":size=" + std::to_string(size) + ",seed=" + std::to_string(params.seed);
  return scene;
}

BuiltinSpec parse_builtin_spec(const std::string& spec) {
  const std::string prefix = "builtin:";
  if (spec.rfind(prefix, 0) != 0)
    throw Error("'" + spec + "': a built-in scene is written builtin:NAME[:key=value,...]");
  const std::string_view rest = std::string_view(spec).substr(prefix.size());
  const BuiltinEntry& entry = find_entry(std::string(rest.substr(0, rest.find(':'))));
  const Spec parsed = parse_spec(rest, prefix);
  const ParamValues values = read_params(parsed, kBuiltinParams, prefix + entry.name);
  return {entry.name, {.seed = values.whole("seed"), .size = static_cast<std::size_t>(values.whole("size"))}};
}

Scene parse_builtin_scene(const std::string& spec) {
  const BuiltinSpec parsed = parse_builtin_spec(spec);
  return make_builtin_scene(parsed.name, parsed.params);
}

}  // namespace vf

// Calibration files: writing and strictly validated reading (every field, its type and its range).
#include <cmath>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "visfield/core/error.hpp"
#include "visfield/select/calibration.hpp"

namespace vf {
namespace {

using nlohmann::json;
using ordered = nlohmann::ordered_json;  // written in the order a reader expects: format and version first

constexpr const char* kFormat = "visfield-calibration";
constexpr int kVersion = 1;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Reads fields of one document, throwing "<source>: <field path>: <problem>" on the first bad one.
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw Error(source_ + ": " + path + ": " + problem);
  }

  const json& member(const json& object, const std::string& path, const std::string& key) const {
    const std::string field = path.empty() ? key : path + "." + key;
    if (!object.is_object()) fail(path.empty() ? "(top level)" : path, "expected an object, got " + shown(object));
    const auto it = object.find(key);
    if (it == object.end()) fail(field, "missing");
    return *it;
  }

  const json& object(const json& parent, const std::string& path, const std::string& key) const {
    const json& value = member(parent, path, key);
    if (!value.is_object()) fail(join(path, key), "expected an object, got " + shown(value));
    return value;
  }

  std::string string(const json& parent, const std::string& path, const std::string& key) const {
    const json& value = member(parent, path, key);
    if (!value.is_string()) fail(join(path, key), "expected a string, got " + shown(value));
    return value.get<std::string>();
  }

  double number(const json& parent, const std::string& path, const std::string& key, double lo, double hi,
                bool lo_inclusive = true) const {
    const json& value = member(parent, path, key);
    if (!value.is_number()) fail(join(path, key), "expected a number, got " + shown(value));
    const double x = value.get<double>();
    if (!std::isfinite(x) || (lo_inclusive ? x < lo : x <= lo) || x > hi)
      fail(join(path, key), "expected a number " + range_text(lo, hi, lo_inclusive) + ", got " + shown(value));
    return x;
  }

  std::uint64_t unsigned_integer(const json& parent, const std::string& path, const std::string& key, std::uint64_t lo,
                                 std::uint64_t hi = std::numeric_limits<std::uint64_t>::max()) const {
    const json& value = member(parent, path, key);
    if (!value.is_number_unsigned())  // JSON parsing gives non-negative integers, and only those, this type
      fail(join(path, key), "expected a non-negative integer, got " + shown(value));
    const auto x = value.get<std::uint64_t>();
    if (x < lo || x > hi)
      fail(join(path, key), "expected an integer in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + shown(value));
    return x;
  }

  int integer(const json& parent, const std::string& path, const std::string& key, int lo, int hi) const {
    return static_cast<int>(unsigned_integer(parent, path, key, static_cast<std::uint64_t>(lo), static_cast<std::uint64_t>(hi)));
  }

  static std::string join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

 private:
  static std::string shown(const json& value) {
    std::string text = value.dump();
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return text;
  }
  static std::string range_text(double lo, double hi, bool lo_inclusive) {
    std::ostringstream s;
    s << (lo_inclusive ? ">= " : "> ") << lo;
    if (hi != kInf) s << " and <= " << hi;
    return s.str();
  }

  std::string source_;
};

ordered statistics_to_json(const GridStatistics& s) {
  return ordered{{"cell_count", s.cell_count}, {"empty_cells", s.empty_cells}, {"sparseness", s.sparseness},
              {"max_refs", s.max_refs},     {"mean", s.mean},               {"variance", s.variance},
              {"std_dev", s.std_dev},       {"skewness", s.skewness},       {"kurtosis", s.kurtosis}};
}

GridStatistics statistics_from_json(const Reader& r, const json& j, const std::string& path) {
  GridStatistics s;
  s.cell_count = r.unsigned_integer(j, path, "cell_count", 1);
  s.empty_cells = r.unsigned_integer(j, path, "empty_cells", 0, s.cell_count);
  s.sparseness = r.number(j, path, "sparseness", 0.0, 1.0);
  s.max_refs = static_cast<std::uint32_t>(r.unsigned_integer(j, path, "max_refs", 0, std::numeric_limits<std::uint32_t>::max()));
  s.mean = r.number(j, path, "mean", 0.0, kInf);
  s.variance = r.number(j, path, "variance", 0.0, kInf);
  s.std_dev = r.number(j, path, "std_dev", 0.0, kInf);
  s.skewness = r.number(j, path, "skewness", -kInf, kInf);
  s.kurtosis = r.number(j, path, "kurtosis", -kInf, kInf);
  return s;
}

ordered timings_to_json(const RayTimings& t) {
  return ordered{{"count", t.ray_count},
              {"grid_us", t.grid_us},
              {"kdtree_us", t.tree_us},
              {"sample_count", t.sample_count},
              {"grid_sample_us", t.grid_sample_us}};
}

RayTimings timings_from_json(const Reader& r, const json& j, const std::string& path) {
  RayTimings t;
  t.ray_count = r.unsigned_integer(j, path, "count", 1);
  t.grid_us = r.number(j, path, "grid_us", 0.0, kInf);
  t.tree_us = r.number(j, path, "kdtree_us", 0.0, kInf);
  t.sample_count = r.unsigned_integer(j, path, "sample_count", 1);
  t.grid_sample_us = r.number(j, path, "grid_sample_us", 0.0, kInf);
  return t;
}

ordered scene_to_json(const SceneMeasurement& s) {
  ordered rays = ordered::object();
  for (RayKind kind : kRayKinds) rays[ray_kind_name(kind)] = timings_to_json(s.timings(kind));
  return ordered{{"name", s.name},
              {"triangles", s.triangles},
              {"grid",
               {{"resolution", s.grid_resolution},
                {"memory_bytes", s.grid_memory_bytes},
                {"build_ms", s.grid_build_ms},
                {"statistics", statistics_to_json(s.grid_statistics)}}},
              {"kdtree", {{"build_ms", s.tree_build_ms}, {"memory_bytes", s.tree_memory_bytes}}},
              {"rays", rays}};
}

SceneMeasurement scene_from_json(const Reader& r, const json& j, const std::string& path) {
  SceneMeasurement s;
  if (!j.is_object()) r.fail(path, "expected an object");
  s.name = r.string(j, path, "name");
  s.triangles = r.unsigned_integer(j, path, "triangles", 1);
  const std::string grid_path = path + ".grid";
  const json& grid = r.object(j, path, "grid");
  const json& resolution = r.member(grid, grid_path, "resolution");
  if (!resolution.is_array() || resolution.size() != 3)
    r.fail(grid_path + ".resolution", "expected an array of 3 cell counts");
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const json& cells = resolution[axis];
    if (!cells.is_number_unsigned() || cells.get<std::uint64_t>() < 1 || cells.get<std::uint64_t>() > (1u << 30))
      r.fail(grid_path + ".resolution[" + std::to_string(axis) + "]", "expected an integer in 1..1073741824, got " + cells.dump());
    s.grid_resolution[axis] = cells.get<int>();
  }
  s.grid_memory_bytes = r.unsigned_integer(grid, grid_path, "memory_bytes", 0);
  s.grid_build_ms = r.number(grid, grid_path, "build_ms", 0.0, kInf);
  s.grid_statistics = statistics_from_json(r, r.object(grid, grid_path, "statistics"), grid_path + ".statistics");
  const json& tree = r.object(j, path, "kdtree");
  s.tree_build_ms = r.number(tree, path + ".kdtree", "build_ms", 0.0, kInf);
  s.tree_memory_bytes = r.unsigned_integer(tree, path + ".kdtree", "memory_bytes", 0);
  const json& rays = r.object(j, path, "rays");
  for (RayKind kind : kRayKinds) {
    const std::string name = ray_kind_name(kind);
    s.rays[ray_kind_index(kind)] = timings_from_json(r, r.object(rays, path + ".rays", name), path + ".rays." + name);
  }
  return s;
}

}  // namespace

std::string calibration_to_json(const Calibration& c) {
  ordered per_kind = ordered::object();
  for (RayKind kind : kRayKinds) per_kind[ray_kind_name(kind)] = c.constants.ray_us(kind);
  ordered scenes = ordered::array();
  for (const SceneMeasurement& s : c.scenes) scenes.push_back(scene_to_json(s));
  const ordered doc{
      {"format", kFormat},
      {"version", kVersion},
      {"machine", {{"hostname", c.machine.hostname}, {"threads", c.machine.threads}, {"cpu_model", c.machine.cpu_model}}},
      {"settings",
       {{"rays", c.settings.rays},
        {"sample_rays", c.settings.sample_rays},
        {"build_repetitions", c.settings.build_repetitions},
        {"path_bounces", c.settings.path_bounces},
        {"seed", c.settings.seed}}},
      {"constants", {{"build_ms_per_n_log2_n", c.constants.build_ms_per_n_log2_n}, {"ray_us_per_log2_n", per_kind}}},
      {"scenes", scenes}};
  return doc.dump(2);
}

Calibration calibration_from_json(const std::string& text, const std::string& source) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    std::string reason = e.what();
    const std::size_t tag_end = reason.find("] ");  // drop nlohmann's "[json.exception.parse_error.N] " tag
    if (tag_end != std::string::npos) reason = reason.substr(tag_end + 2);
    throw Error(source + ": not valid JSON: " + reason);
  }
  const Reader r(source);
  if (!doc.is_object()) r.fail("(top level)", "expected an object");
  if (r.string(doc, "", "format") != kFormat)
    r.fail("format", "expected \"" + std::string(kFormat) + "\", got " + doc["format"].dump());
  const json& version = r.member(doc, "", "version");
  if (!version.is_number_integer() || version.get<std::int64_t>() != kVersion)
    r.fail("version", "unsupported version " + version.dump() + " (this build reads version " + std::to_string(kVersion) + ")");

  Calibration c;
  const json& machine = r.object(doc, "", "machine");
  c.machine.hostname = r.string(machine, "machine", "hostname");
  c.machine.threads = r.integer(machine, "machine", "threads", 1, 1 << 20);
  c.machine.cpu_model = r.string(machine, "machine", "cpu_model");

  const json& settings = r.object(doc, "", "settings");
  c.settings.rays = r.unsigned_integer(settings, "settings", "rays", 1);
  c.settings.sample_rays = r.unsigned_integer(settings, "settings", "sample_rays", 5);
  c.settings.build_repetitions = r.integer(settings, "settings", "build_repetitions", 1, 1000);
  c.settings.path_bounces = r.integer(settings, "settings", "path_bounces", 0, 16);
  c.settings.seed = r.unsigned_integer(settings, "settings", "seed", 0);

  const json& constants = r.object(doc, "", "constants");
  c.constants.build_ms_per_n_log2_n = r.number(constants, "constants", "build_ms_per_n_log2_n", 0.0, kInf, false);
  const json& per_kind = r.object(constants, "constants", "ray_us_per_log2_n");
  for (RayKind kind : kRayKinds)
    c.constants.ray_us_per_log2_n[ray_kind_index(kind)] =
        r.number(per_kind, "constants.ray_us_per_log2_n", ray_kind_name(kind), 0.0, kInf, false);

  const json& scenes = r.member(doc, "", "scenes");
  if (!scenes.is_array()) r.fail("scenes", "expected an array, got " + scenes.dump().substr(0, 40));
  for (std::size_t i = 0; i < scenes.size(); ++i)
    c.scenes.push_back(scene_from_json(r, scenes[i], "scenes[" + std::to_string(i) + "]"));
  return c;
}

}  // namespace vf

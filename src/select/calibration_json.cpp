// Calibration files: writing and strictly validated reading (every field, its type and its range).
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "visfield/core/error.hpp"
#include "visfield/io/json_reader.hpp"
#include "visfield/select/calibrate.hpp"
#include "visfield/select/calibration.hpp"

namespace vf {
namespace {

using ordered = nlohmann::ordered_json;  // written in the order a reader expects: format and version first

constexpr const char* kFormat = "visfield-calibration";
constexpr int kVersion = 3;
constexpr std::uint64_t kMaxUint64 = std::numeric_limits<std::uint64_t>::max();
using json::JsonField;
using json::NumberRange;

ordered statistics_to_json(const GridStatistics& s) {
  return ordered{{"cell_count", s.cell_count}, {"empty_cells", s.empty_cells}, {"sparseness", s.sparseness},
              {"max_refs", s.max_refs},     {"mean", s.mean},               {"variance", s.variance},
              {"std_dev", s.std_dev},       {"skewness", s.skewness},       {"kurtosis", s.kurtosis}};
}

GridStatistics statistics_from_json(const JsonField& j) {
  j.require_object({"cell_count", "empty_cells", "sparseness", "max_refs", "mean", "variance", "std_dev", "skewness",
                    "kurtosis"});
  GridStatistics s;
  s.cell_count = j.member("cell_count").as_uint64(1, kMaxUint64);
  s.empty_cells = j.member("empty_cells").as_uint64(0, s.cell_count);
  s.sparseness = j.member("sparseness").as_double(NumberRange::closed(0.0, 1.0));
  s.max_refs = static_cast<std::uint32_t>(j.member("max_refs").as_uint64(0, std::numeric_limits<std::uint32_t>::max()));
  s.mean = j.member("mean").as_double(NumberRange::non_negative());
  s.variance = j.member("variance").as_double(NumberRange::non_negative());
  s.std_dev = j.member("std_dev").as_double(NumberRange::non_negative());
  s.skewness = j.member("skewness").as_double();
  s.kurtosis = j.member("kurtosis").as_double();
  return s;
}

ordered timings_to_json(const RayTimings& t) {
  return ordered{{"count", t.ray_count},
              {"grid_us", t.grid_us},
              {"kdtree_us", t.tree_us},
              {"sample_count", t.sample_count},
              {"grid_sample_us", t.grid_sample_us}};
}

RayTimings timings_from_json(const JsonField& j) {
  j.require_object({"count", "grid_us", "kdtree_us", "sample_count", "grid_sample_us"});
  RayTimings t;
  t.ray_count = j.member("count").as_uint64(1, kMaxUint64);
  t.grid_us = j.member("grid_us").as_double(NumberRange::non_negative());
  t.tree_us = j.member("kdtree_us").as_double(NumberRange::non_negative());
  t.sample_count = j.member("sample_count").as_uint64(1, kMaxUint64);
  t.grid_sample_us = j.member("grid_sample_us").as_double(NumberRange::non_negative());
  return t;
}

// Per ray kind (every RayKind, by name) a number; `range` checks each.
ordered per_kind_to_json(const std::array<double, kPlanKinds>& values) {
  ordered out = ordered::object();
  for (std::size_t k = 0; k < kPlanKinds; ++k) out[std::string(ray_kind_name(kRayKinds[k]))] = values[k];
  return out;
}

std::array<double, kPlanKinds> per_kind_from_json(const JsonField& j, const NumberRange& range) {
  std::vector<std::string_view> names;
  for (RayKind kind : kRayKinds) names.push_back(ray_kind_name(kind));
  j.require_object(names);
  std::array<double, kPlanKinds> values{};
  for (std::size_t k = 0; k < kPlanKinds; ++k) values[k] = j.member(names[k]).as_double(range);
  return values;
}

ordered profile_to_json(const SceneProfile& p) {
  return ordered{{"triangles", p.triangles},
                 {"unique_triangles", p.unique_triangles},
                 {"objects", p.objects},
                 {"mesh_log2_sum", p.mesh_log2_sum},
                 {"grid_build_ms", p.grid_build_ms},
                 {"grid_sample_us", per_kind_to_json(p.grid_sample_us)},
                 {"bvh_build_ms", p.bvh_build_ms},
                 {"bvh_sample_us", per_kind_to_json(p.bvh_sample_us)},
                 {"ao_occluded", p.ao_occluded},
                 {"field_probe_rms", p.field_probe_rms},
                 {"threads", p.threads}};
}

SceneProfile profile_from_json(const JsonField& j) {
  j.require_object({"triangles", "unique_triangles", "objects", "mesh_log2_sum", "grid_build_ms", "grid_sample_us", "bvh_build_ms",
                    "bvh_sample_us", "ao_occluded", "field_probe_rms", "threads"});
  SceneProfile p;
  p.triangles = j.member("triangles").as_uint64(0, kMaxUint64);
  p.unique_triangles = j.member("unique_triangles").as_uint64(0, kMaxUint64);
  p.objects = j.member("objects").as_uint64(0, kMaxUint64);
  p.mesh_log2_sum = j.member("mesh_log2_sum").as_double(NumberRange::non_negative());
  p.grid_build_ms = j.member("grid_build_ms").as_double(NumberRange::non_negative());
  p.grid_sample_us = per_kind_from_json(j.member("grid_sample_us"), NumberRange::non_negative());
  p.bvh_build_ms = j.member("bvh_build_ms").as_double(NumberRange::non_negative());
  p.bvh_sample_us = per_kind_from_json(j.member("bvh_sample_us"), NumberRange::non_negative());
  p.ao_occluded = j.member("ao_occluded").as_double(NumberRange::closed(0.0, 1.0));
  p.field_probe_rms = j.member("field_probe_rms").as_double(NumberRange::closed(-1.0, 255.0));
  p.threads = j.member("threads").as_int(1, 1 << 20);
  return p;
}

ordered plan_measurement_to_json(const PlanMeasurement& m) {
  ordered candidates = ordered::array();
  for (const CandidateMeasurement& c : m.candidates)
    candidates.push_back(ordered{{"spec", c.spec},
                                 {"build_ms", c.build_ms},
                                 {"memory_bytes", c.memory_bytes},
                                 {"ray_us", per_kind_to_json(c.ray_us)},
                                 {"update_ms", c.update_ms},
                                 {"ao_rms", c.ao_rms}});
  return ordered{{"profile", profile_to_json(m.profile)}, {"candidates", candidates}};
}

PlanMeasurement plan_measurement_from_json(const JsonField& j) {
  j.require_object({"profile", "candidates"});
  PlanMeasurement m;
  m.profile = profile_from_json(j.member("profile"));
  for (const JsonField& c : j.member("candidates").elements()) {
    c.require_object({"spec", "build_ms", "memory_bytes", "ray_us", "update_ms", "ao_rms"});
    CandidateMeasurement cm;
    cm.spec = c.member("spec").as_string();
    if (plan_candidate_index(cm.spec) == static_cast<std::size_t>(-1)) c.member("spec").fail("not a candidate of this build's planner");
    cm.build_ms = c.member("build_ms").as_double(NumberRange::non_negative());
    cm.memory_bytes = c.member("memory_bytes").as_uint64(0, kMaxUint64);
    cm.ray_us = per_kind_from_json(c.member("ray_us"), NumberRange::closed(-1.0, 1e300));
    cm.update_ms = c.member("update_ms").as_double(NumberRange::closed(-1.0, 1e300));
    cm.ao_rms = c.member("ao_rms").as_double(NumberRange::closed(0.0, 255.0));
    m.candidates.push_back(std::move(cm));
  }
  return m;
}

ordered plan_model_to_json(const PlanModel& model) {
  ordered candidates = ordered::object();
  for (std::size_t i = 0; i < model.constants.size(); ++i) {
    const CandidateConstants& c = model.constants[i];
    candidates[std::string(plan_candidates()[i].spec)] =
        ordered{{"build_ms", c.build_ms},
                {"ray_us", per_kind_to_json(c.ray_us)},
                {"ray_exponent", per_kind_to_json(c.ray_exponent)},
                {"update_ms", c.update_ms}};
  }
  const FieldErrorModel& e = model.field_error;
  return ordered{{"threads", model.threads},
                 {"candidates", candidates},
                 {"field_error", {{"coefficients", e.coefficients}, {"sigma", e.sigma}, {"samples", e.samples}}}};
}

PlanModel plan_model_from_json(const JsonField& j) {
  j.require_object({"threads", "candidates", "field_error"});
  PlanModel model;
  model.threads = j.member("threads").as_int(1, 1 << 20);
  const JsonField candidates = j.member("candidates");
  std::vector<std::string_view> specs;
  for (const PlanCandidate& c : plan_candidates()) specs.push_back(c.spec);
  candidates.require_object(specs);
  for (std::string_view spec : specs) {
    const JsonField c = candidates.member(spec);
    c.require_object({"build_ms", "ray_us", "ray_exponent", "update_ms"});
    CandidateConstants k;
    k.build_ms = c.member("build_ms").as_double(NumberRange::non_negative());
    k.ray_us = per_kind_from_json(c.member("ray_us"), NumberRange::non_negative());
    k.ray_exponent = per_kind_from_json(c.member("ray_exponent"), NumberRange::closed(-8.0, 8.0));
    k.update_ms = c.member("update_ms").as_double(NumberRange::non_negative());
    model.constants.push_back(k);
  }
  const JsonField e = j.member("field_error");
  e.require_object({"coefficients", "sigma", "samples"});
  const std::vector<JsonField> coefficients = e.member("coefficients").elements(kErrorFeatures);
  if (coefficients.size() != kErrorFeatures)
    e.member("coefficients").fail_expected("an array of " + std::to_string(kErrorFeatures) + " numbers");
  for (std::size_t i = 0; i < kErrorFeatures; ++i) model.field_error.coefficients[i] = coefficients[i].as_double();
  model.field_error.sigma = e.member("sigma").as_double(NumberRange::non_negative());
  model.field_error.samples = e.member("samples").as_uint64(0, kMaxUint64);
  return model;
}

ordered scene_to_json(const SceneMeasurement& s) {
  ordered rays = ordered::object();
  for (RayKind kind : kCalibratedKinds) rays[std::string(ray_kind_name(kind))] = timings_to_json(s.timings(kind));
  return ordered{{"name", s.name},
              {"triangles", s.triangles},
              {"grid",
               {{"resolution", s.grid_resolution},
                {"memory_bytes", s.grid_memory_bytes},
                {"build_ms", s.grid_build_ms},
                {"statistics", statistics_to_json(s.grid_statistics)}}},
              {"kdtree", {{"build_ms", s.tree_build_ms}, {"memory_bytes", s.tree_memory_bytes}}},
              {"rays", rays},
              {"plan", plan_measurement_to_json(s.plan)}};
}

SceneMeasurement scene_from_json(const JsonField& j) {
  j.require_object({"name", "triangles", "grid", "kdtree", "rays", "plan"});
  SceneMeasurement s;
  s.name = j.member("name").as_string();
  s.triangles = j.member("triangles").as_uint64(1, kMaxUint64);
  const JsonField grid = j.member("grid");
  grid.require_object({"resolution", "memory_bytes", "build_ms", "statistics"});
  const JsonField resolution = grid.member("resolution");
  if (!resolution.json().is_array() || resolution.json().size() != 3) resolution.fail_expected("an array of 3 cell counts");
  const std::vector<JsonField> cells = resolution.elements();
  for (std::size_t axis = 0; axis < 3; ++axis) s.grid_resolution[axis] = cells[axis].as_int(1, 1 << 30);
  s.grid_memory_bytes = grid.member("memory_bytes").as_uint64(0, kMaxUint64);
  s.grid_build_ms = grid.member("build_ms").as_double(NumberRange::non_negative());
  s.grid_statistics = statistics_from_json(grid.member("statistics"));
  const JsonField tree = j.member("kdtree");
  tree.require_object({"build_ms", "memory_bytes"});
  s.tree_build_ms = tree.member("build_ms").as_double(NumberRange::non_negative());
  s.tree_memory_bytes = tree.member("memory_bytes").as_uint64(0, kMaxUint64);
  const JsonField rays = j.member("rays");
  rays.require_object({ray_kind_name(kCalibratedKinds[0]), ray_kind_name(kCalibratedKinds[1])});
  for (RayKind kind : kCalibratedKinds)
    s.rays[calibrated_kind_index(kind)] = timings_from_json(rays.member(ray_kind_name(kind)));
  s.plan = plan_measurement_from_json(j.member("plan"));
  return s;
}

}  // namespace

std::string calibration_to_json(const Calibration& c) {
  ordered per_kind = ordered::object();
  for (RayKind kind : kCalibratedKinds) per_kind[std::string(ray_kind_name(kind))] = c.constants.ray_us(kind);
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
      {"plan", plan_model_to_json(c.plan)},
      {"scenes", scenes}};
  return doc.dump(2);
}

namespace {

Calibration calibration_from_document(const nlohmann::json& doc, const std::string& source) {
  const JsonField root(doc, source);
  root.require_object({"format", "version", "machine", "settings", "constants", "plan", "scenes"});
  const JsonField format = root.member("format");
  if (!format.json().is_string() || format.json().get<std::string>() != kFormat)
    format.fail_expected("\"" + std::string(kFormat) + "\"");
  const JsonField version = root.member("version");
  if (!version.json().is_number_integer() || version.json().get<std::int64_t>() != kVersion)
    version.fail("unsupported version " + version.json().dump() + " (this build reads version " +
                 std::to_string(kVersion) + "; run visfield calibrate again)");

  Calibration c;
  const JsonField machine = root.member("machine");
  machine.require_object({"hostname", "threads", "cpu_model"});
  c.machine.hostname = machine.member("hostname").as_string();
  c.machine.threads = machine.member("threads").as_int(1, 1 << 20);
  c.machine.cpu_model = machine.member("cpu_model").as_string();

  const JsonField settings = root.member("settings");
  settings.require_object({"rays", "sample_rays", "build_repetitions", "path_bounces", "seed"});
  c.settings.rays = settings.member("rays").as_uint64(1, kMaxUint64);
  c.settings.sample_rays = settings.member("sample_rays").as_uint64(5, kMaxUint64);
  c.settings.build_repetitions = settings.member("build_repetitions").as_int(1, 1000);
  c.settings.path_bounces = settings.member("path_bounces").as_int(0, 16);
  c.settings.seed = settings.member("seed").as_uint64(0, kMaxUint64);

  const JsonField constants = root.member("constants");
  constants.require_object({"build_ms_per_n_log2_n", "ray_us_per_log2_n"});
  c.constants.build_ms_per_n_log2_n = constants.member("build_ms_per_n_log2_n").as_double(NumberRange::positive());
  const JsonField per_kind = constants.member("ray_us_per_log2_n");
  per_kind.require_object({ray_kind_name(kCalibratedKinds[0]), ray_kind_name(kCalibratedKinds[1])});
  for (RayKind kind : kCalibratedKinds)
    c.constants.ray_us_per_log2_n[calibrated_kind_index(kind)] =
        per_kind.member(ray_kind_name(kind)).as_double(NumberRange::positive());

  c.plan = plan_model_from_json(root.member("plan"));
  for (const JsonField& scene : root.member("scenes").elements()) c.scenes.push_back(scene_from_json(scene));
  // The measurements are the truth: a file written by an older fit gets this build's model of them.
  if (std::any_of(c.scenes.begin(), c.scenes.end(), [](const SceneMeasurement& s) { return !s.plan.candidates.empty(); }))
    c.plan = fit_plan_model(c.scenes, c.machine.threads);
  return c;
}

}  // namespace

Calibration calibration_from_json(const std::string& text, const std::string& source) {
  return calibration_from_document(json::parse_json_text(text, source), source);
}

Calibration load_calibration(const std::filesystem::path& path) {
  return calibration_from_document(json::parse_json_file(path), path.string());
}

void require_calibration_for(const Calibration& calibration, const MachineInfo& here, const std::string& source) {
  const MachineInfo& there = calibration.machine;
  if (there.cpu_model == here.cpu_model && there.threads == here.threads) return;
  throw Error(source + ": measured on " + there.cpu_model + " with " + std::to_string(there.threads) +
              " threads, but this is " + here.cpu_model + " with " + std::to_string(here.threads) +
              " threads: its timings do not apply (run visfield calibrate here" +
              (there.cpu_model == here.cpu_model ? ", or use --threads " + std::to_string(there.threads) : std::string()) + ")");
}

}  // namespace vf

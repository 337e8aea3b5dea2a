#include "visfield/registry/registry.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <initializer_list>
#include <string>
#include <type_traits>
#include <variant>

#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/text.hpp"
#include "visfield/field/field_params.hpp"
#include "visfield/render/progress.hpp"
#include "visfield/select/calibration.hpp"
#include "visfield/registry/planning.hpp"

namespace vf {
namespace {

// ---- levels: flattened (one structure over world-space triangles) or two-level (instance layer) ----

constexpr ParamSpec kLevelsParam{"levels", ParamType::choice, "auto",
                                 "1 = one structure over the flattened objects, 2 = one per mesh under a top level "
                                 "over the objects (updatable), auto = 2 for scenes of many repeated meshes",
                                 0.0, 0.0, "auto|1|2"};

// levels=auto picks two levels when the flattened scene would hold at least kInstancingRatio copies of
// its meshes' triangles and at least kMinTwoLevelTriangles triangles. Measured (bvh, AO and primary
// rays, 2 threads; docs/structures.md, "Instances and updates"): two levels are as fast or faster per ray from
// 10 bunnies (0.69M triangles) and 100 teapots (0.63M) up, and build 10-1000x faster in a fraction
// of the memory; flattened is faster per ray for 16 cows (93k) and 10000 boxes (120k).
constexpr double kInstancingRatio = 4.0;
constexpr double kMinTwoLevelTriangles = 500'000.0;

bool two_levels(const ParamValues& p, const SceneGeometry& geometry) {
  const std::string& levels = p.text("levels");
  if (levels != "auto") return levels == "2";
  const auto instanced = static_cast<double>(geometry.instanced_triangle_count());
  const auto unique = static_cast<double>(geometry.unique_triangle_count());
  return instanced >= kMinTwoLevelTriangles && instanced >= kInstancingRatio * unique;
}

// Zero-area triangles of the objects in their own space: what the two-level structure leaves out.
std::size_t object_degenerate_count(const Scene& scene) {
  std::vector<std::size_t> per_mesh(scene.meshes.size(), kInvalidId);
  std::size_t total = 0;
  for (const Instance& inst : scene.instances()) {
    if (per_mesh[inst.mesh] == kInvalidId) per_mesh[inst.mesh] = scene.meshes[inst.mesh].count_degenerate();
    total += per_mesh[inst.mesh];
  }
  return total;
}

std::string with_params(std::string_view name, const std::string& params) {
  return params.empty() ? std::string(name) : std::string(name) + ":" + params;
}

// A triangle structure S built with `config`, flattened or under the instance layer as `levels` says.
template <class S, class Config>
BuiltStructure build_triangle_structure(const ParamValues& p, SceneGeometry& geometry, const Config& config) {
  std::string resolved = p.canonical();
  const std::string levels = two_levels(p, geometry) ? "2" : "1";
  if (!p.given("levels")) resolved += std::string(resolved.empty() ? "" : ",") + "levels=" + levels;
  if (levels == "1") {
    const TriangleSet& set = geometry.flattened();
    return {S::build(set, config), with_params(S::name(), resolved), set.degenerate_count};
  }
  InstanceLayer layer = InstanceLayer::build(
      geometry.scene(), [config](const TriangleSet& object_triangles) { return MeshStructure(S::build(object_triangles, config)); });
  return {std::move(layer), with_params(S::name(), resolved), object_degenerate_count(geometry.scene())};
}

// Bytes of the flattened triangles, when a one-level build has yet to make them.
double flattening_bytes(const SceneGeometry& geometry) {
  if (geometry.is_flattened()) return 0.0;
  constexpr double kBytesPerTriangle = sizeof(std::array<Vec3f, 3>) + sizeof(std::uint32_t) + sizeof(ObjectId);
  return kBytesPerTriangle * static_cast<double>(geometry.instanced_triangle_count());
}

// Peak bytes of build_triangle_structure<S>: one structure over the flattened scene, or one per used
// mesh (all alive at the end) and the top level.
template <class S, class Config>
double estimate_triangle_structure(const ParamValues& p, const SceneGeometry& geometry, const Config& config) {
  if (!two_levels(p, geometry))
    return flattening_bytes(geometry) + S::estimate_build_bytes(geometry.instanced_triangle_count(), config);
  const Scene& scene = geometry.scene();
  std::vector<std::uint8_t> used(scene.meshes.size(), 0);
  double bytes = InstanceLayer::estimate_top_level_bytes(scene.instances().size());
  for (const Instance& inst : scene.instances()) {
    if (used[inst.mesh]) continue;
    used[inst.mesh] = 1;
    bytes += S::estimate_build_bytes(scene.meshes[inst.mesh].triangles.size(), config);
  }
  return bytes;
}

// A parameter that sets a field of a structure's Config.
template <class Config>
struct ConfigField {
  std::string_view key;
  std::variant<int Config::*, float Config::*, bool Config::*> field;
};

// The Config with every bound parameter's value written into its field.
template <class Config>
Config config_from(const ParamValues& p, std::initializer_list<ConfigField<Config>> fields) {
  Config c;
  for (const ConfigField<Config>& f : fields) {
    std::visit(
        [&](auto member) {
          using T = std::remove_reference_t<decltype(c.*member)>;
          if constexpr (std::is_same_v<T, bool>) c.*member = p.boolean(f.key);
          else if constexpr (std::is_same_v<T, int>) c.*member = static_cast<int>(p.whole(f.key));
          else c.*member = static_cast<float>(p.number(f.key));
        },
        f.field);
  }
  return c;
}

// ---- the structures ----

constexpr ParamSpec kBvhParams[] = {
    {"bins", ParamType::whole, "32", "SAH bins per axis", 2, 64},
    {"leaf", ParamType::whole, "8", "most triangles per leaf", 1, 128},
    {"kt", ParamType::number, "1", "SAH cost of a node visit, per leaf block test", 0, 1e6},
    {"ki", ParamType::number, "1", "SAH cost of a leaf block test (8 triangles)", 1e-6, 1e6},
    kLevelsParam,
};

BvhConfig bvh_config(const ParamValues& p) {
  return config_from<BvhConfig>(p, {{"bins", &BvhConfig::bin_count},
                                    {"leaf", &BvhConfig::max_leaf_size},
                                    {"kt", &BvhConfig::traversal_cost},
                                    {"ki", &BvhConfig::intersection_cost}});
}

constexpr ParamSpec kGridParams[] = {
    {"density", ParamType::number, "2", "cells per triangle", 1e-6, 64},
    {"exact", ParamType::boolean, "1", "reference a triangle only from cells its surface meets"},
    kLevelsParam,
};

UniformGridConfig grid_config(const ParamValues& p) {
  return config_from<UniformGridConfig>(p, {{"density", &UniformGridConfig::density}, {"exact", &UniformGridConfig::exact_overlap}});
}

constexpr ParamSpec kKdTreeParams[] = {
    {"kt", ParamType::number, "16", "SAH cost K_T of a node visit", 0, 1e6},
    {"ki", ParamType::number, "1", "SAH cost K_I of a leaf block test (16 triangles)", 1e-6, 1e6},
    {"empty", ParamType::number, "0.8", "factor on the cost of a split with an empty side", 1e-6, 1},
    {"depth", ParamType::whole, "0", "most splits above a leaf (0 = 8 + 1.3 log2 N)", 0, 64},
    kLevelsParam,
};

KdTreeConfig kdtree_config(const ParamValues& p) {
  return config_from<KdTreeConfig>(p, {{"kt", &KdTreeConfig::traversal_cost},
                                       {"ki", &KdTreeConfig::intersection_cost},
                                       {"empty", &KdTreeConfig::empty_bonus},
                                       {"depth", &KdTreeConfig::max_depth}});
}

constexpr ParamSpec kMedianBspParams[] = {
    {"depth", ParamType::whole, "0", "most splits above a leaf (0 = round(log2 N))", 0, 64},
    {"leaf", ParamType::whole, "8", "nodes with more triangles are split", 1, 1e9},
    kLevelsParam,
};

MedianBspConfig median_bsp_config(const ParamValues& p) {
  return config_from<MedianBspConfig>(p, {{"depth", &MedianBspConfig::max_depth}, {"leaf", &MedianBspConfig::max_leaf_size}});
}

constexpr ParamSpec kBruteParams[] = {kLevelsParam};

// BruteForce takes no config; an empty one keeps build_triangle_structure uniform.
struct NoConfig {};
struct BruteBuild {
  static BruteForce build(const TriangleSet& set, NoConfig) { return BruteForce::build(set); }
  static double estimate_build_bytes(std::size_t triangles, NoConfig) { return BruteForce::estimate_build_bytes(triangles); }
  static std::string name() { return BruteForce::name(); }
};

NoConfig no_config(const ParamValues&) { return {}; }

// The registry's build and estimate of a triangle structure S (flattened or instanced, by levels=),
// its Config read from the parameters by ConfigOf: one path for bvh, grid, kdtree, median-bsp, brute.
template <class S, auto ConfigOf>
struct TriangleEntry {
  static BuiltStructure build(const ParamValues& p, SceneGeometry& geometry, const BuildContext&) {
    return build_triangle_structure<S>(p, geometry, ConfigOf(p));
  }
  static double estimate(const ParamValues& p, const SceneGeometry& geometry) {
    return estimate_triangle_structure<S>(p, geometry, ConfigOf(p));
  }
};

constexpr ParamSpec kBeamParams[] = {
    {"dirs", ParamType::choice, "513", "directions (lines) of the field: 2*4^level+1 for level 2..6", 0, 0, "33|129|513|2049|8193"},
    {"n", ParamType::whole, "64", "tiles per side of each direction's parallel subfield", 16, 1024},
    {"depth", ParamType::whole, "4", "deepest tile-BSP: at most 2^depth leaves per tile", 0, 12},
    {"leaf", ParamType::whole, "4", "a tile of c references gets about c/leaf leaves", 1, 4096},
    {"stream", ParamType::whole, "1", "trace rays along a stored line in per-tile packets (1) or one by one (0); same answers", 0, 1},
};

BeamFieldConfig beam_config(const ParamValues& p) {
  BeamFieldConfig c = config_from<BeamFieldConfig>(
      p, {{"n", &BeamFieldConfig::resolution}, {"depth", &BeamFieldConfig::max_depth}, {"leaf", &BeamFieldConfig::leaf_size},
          {"stream", &BeamFieldConfig::stream}});
  const std::uint64_t dirs = std::stoull(p.text("dirs"));
  for (int level = DirectionLines::kMinLevel; level <= DirectionLines::kMaxLevel; ++level)
    if (DirectionLines::count(level) == dirs) c.level = level;
  return c;
}

BuiltStructure build_beam(const ParamValues& p, SceneGeometry& geometry, const BuildContext&) {
  const TriangleSet& set = geometry.flattened();
  return {BeamField::build(geometry.scene(), set, beam_config(p)), with_params("beam", p.canonical()), set.degenerate_count};
}

double estimate_beam(const ParamValues& p, const SceneGeometry& geometry) {
  return flattening_bytes(geometry) + BeamField::estimate_build_bytes(geometry.scene(), beam_config(p));
}

// The field's table parameters (field_params.hpp), then how it is looked up and cached, and which meshes it takes.
constexpr auto kFieldParams = [] {
  std::array<ParamSpec, field::kTableParams.size() + 7> params{};
  for (std::size_t i = 0; i < field::kTableParams.size(); ++i) params[i] = field::kTableParams[i];
  std::size_t i = field::kTableParams.size();
  params[i++] = {"bilinear", ParamType::boolean, "0", "interpolate between the four nearest direction cells", 0, 0};
  params[i++] = {"blend", ParamType::boolean, "0", "blend the three positional samples around the entry point", 0, 0};
  params[i++] = {"lines", ParamType::boolean, "0",
                 "from outside, the ten stored lines nearest to the ray's chord vote (both chord ends, 3 x 3 cells each): lowest error, "
                 "slowest; replaces blend",
                 0, 0};
  params[i++] = {"through", ParamType::boolean, "1",
                 "read each sample along the line through the ray's far end in the sphere (origin from inside, exit from outside), not parallel to the ray",
                 0, 0};
  params[i++] = {"cache", ParamType::text, "", "folder where each mesh's .vfield is read from, or written to when missing", 0, 0};
  params[i++] = {"meshes", ParamType::choice, "all",
                 "which meshes get fields: all (but those a scene marks exact) or marked (only those it marks \"occluder\": \"field\")", 0, 0,
                 "all|marked"};
  params[i++] = {"cull", ParamType::choice, "grid",
                 "how rays find the field objects they may meet, past 16 objects: grid (a batch's rays within one or two cells of a grid take "
                 "their objects, the rest go down a BVH over the spheres), tree (the BVH for every ray) or each (every sphere tested); same answers",
                 0, 0, "grid|tree|each"};
  return params;
}();

field::ObjectFieldConfig field_config(const ParamValues& p) {
  field::ObjectFieldConfig c = field::with_table_params({}, p);
  c.direction_lookup = p.boolean("bilinear") ? field::DirectionLookup::bilinear : field::DirectionLookup::nearest;
  if (p.boolean("lines") && p.boolean("blend")) throw Error("field: lines=1 and blend=1 are two position lookups; give one");
  c.position_lookup = p.boolean("lines")   ? field::PositionLookup::lines
                      : p.boolean("blend") ? field::PositionLookup::blend
                                           : field::PositionLookup::nearest;
  c.sample_line = p.boolean("through") ? field::SampleLine::through : field::SampleLine::parallel;
  return c;
}

field::FieldMeshes field_meshes(const ParamValues& p) {
  return p.text("meshes") == "marked" ? field::FieldMeshes::marked : field::FieldMeshes::all;
}

BuiltStructure build_field(const ParamValues& p, SceneGeometry& geometry, const BuildContext& context) {
  const field::ObjectFieldConfig config = field_config(p);
  ProgressBar bar("field", field::FieldScene::progress_total(geometry.scene(), config, field_meshes(p)), context.progress);
  field::FieldScene fields = field::FieldScene::build(geometry.scene(), config, [&](std::size_t n) { bar.tick(n); },
                                                     p.has("cache") ? p.text("cache") : std::string(), field_meshes(p),
                                                     p.text("cull") == "each"   ? field::ObjectCull::each
                                                     : p.text("cull") == "tree" ? field::ObjectCull::tree
                                                                                : field::ObjectCull::grid);
  bar.finish();
  return {std::move(fields), with_params("field", p.canonical()), object_degenerate_count(geometry.scene())};
}

double estimate_field(const ParamValues& p, const SceneGeometry& geometry) {
  return field::FieldScene::estimate_build_bytes(geometry.scene(), field_config(p), field_meshes(p));
}

constexpr ParamSpec kAutoParams[] = {
    {"rays", ParamType::whole, "", "R, the rays the workload traces (default: the command's own count)", 1, 1e15},
    {"kind", ParamType::choice, "path", "kind of the workload's rays (camera = primary)", 0, 0, "ao|shadow|camera|primary|random|path"},
    {"error", ParamType::number, "0", "E, the RMS (0-255) of an AO image allowed against the exact one; 0 = exact structures only", 0, 255},
    {"updates", ParamType::whole, "0", "U, object moves the workload makes", 0, 1e15},
    {"calibration", ParamType::text, "", "calibration file from `visfield calibrate` (default: built in)"},
};

// The planner's request of an auto spec; the calibration is loaded (and checked against this machine)
// when the spec names one.
PlanRequest auto_request(const ParamValues& p, const BuildContext& context) {
  PlanRequest request;
  request.rays = static_cast<double>(p.has("rays") ? p.whole("rays") : context.expected_rays);
  request.kind = *parse_ray_kind(p.text("kind"));
  request.max_error = p.number("error");
  request.updates = static_cast<double>(p.whole("updates"));
  request.max_memory = memory_limit().bytes;
  return request;
}

Calibration auto_calibration(const ParamValues& p) {
  if (!p.has("calibration")) return builtin_calibration();
  Calibration calibration = load_calibration(p.text("calibration"));
  require_calibration_for(calibration, this_machine(threads_in_force()), p.text("calibration"));
  return calibration;
}

BuiltStructure build_auto(const ParamValues& p, SceneGeometry& geometry, const BuildContext& context) {
  const PlanRequest request = auto_request(p, context);
  const Calibration calibration = auto_calibration(p);
  const RayKind kinds[] = {request.kind};
  const SceneProfile profile = profile_for_plan(geometry, kinds, request.max_error > 0.0 && is_occlusion_kind(request.kind));
  std::optional<BuiltStructure> measured;  // a field the plan built to measure its error, when it won
  const Plan plan = plan_structures(geometry, profile, calibration, request, &measured);
  const std::string& chosen = plan.rows[plan.chosen].spec;
  BuiltStructure built = measured ? std::move(*measured) : build_structure(chosen, geometry, context, "auto -> ");
  built.resolved = "auto:kind=" + p.text("kind") + ",rays=" + std::to_string(static_cast<std::uint64_t>(request.rays)) +
                   (request.max_error > 0.0 ? ",error=" + formatted("%g", request.max_error) : "") +
                   (request.updates > 0.0 ? ",updates=" + std::to_string(p.whole("updates")) : "") +
                   (p.has("calibration") ? ",calibration=" + p.text("calibration") : "") + " -> " + built.resolved;
  return built;
}

// The profile's flattening and grid, then (the planner stays within the limit) at most the limit itself.
double estimate_auto(const ParamValues&, const SceneGeometry& geometry) {
  const std::size_t n = geometry.instanced_triangle_count();
  return n > kProfileFlattenLimit ? 0.0 : flattening_bytes(geometry) + UniformGrid::estimate_build_bytes(n);
}

constexpr std::string_view kTwoLevelUpdates = "with levels=2";

const StructureInfo kTable[] = {
    {"bvh", "SAH BVH, 8-wide nodes, SIMD box and triangle tests", Exactness::exact, kTwoLevelUpdates, kBvhParams,
     TriangleEntry<Bvh, bvh_config>::build, TriangleEntry<Bvh, bvh_config>::estimate},
    {"grid", "uniform grid, density x N cells, 3D-DDA traversal (Havran et al.)", Exactness::exact, kTwoLevelUpdates,
     kGridParams, TriangleEntry<UniformGrid, grid_config>::build, TriangleEntry<UniformGrid, grid_config>::estimate},
    {"kdtree", "SAH kd-tree, O(N log N) event sorting, perfect splits (Wald & Havran)", Exactness::exact,
     kTwoLevelUpdates, kKdTreeParams, TriangleEntry<KdTree, kdtree_config>::build, TriangleEntry<KdTree, kdtree_config>::estimate},
    {"median-bsp", "spatial-median BSP, the VLF-RT paper's CRT baseline", Exactness::exact, kTwoLevelUpdates,
     kMedianBspParams, TriangleEntry<MedianBsp, median_bsp_config>::build, TriangleEntry<MedianBsp, median_bsp_config>::estimate},
    {"brute", "every triangle for every ray: the test oracle, O(N) per ray", Exactness::exact, kTwoLevelUpdates,
     kBruteParams, TriangleEntry<BruteBuild, no_config>::build, TriangleEntry<BruteBuild, no_config>::estimate},
    {"beam", "BeamField (VLF-RT): directions x n*n parallel beams x tile-BSP, exact; fast along its directions",
     Exactness::exact, "always", kBeamParams, build_beam, estimate_beam},
    {"field", "ObjectFields: per-mesh 4D distance fields on the bounding sphere, shared by instances; approximate, "
              "constant time per object (meshes marked exact stay exact)",
     Exactness::approximate, "", kFieldParams, build_field, estimate_field},
    {"auto", "the structure the planner predicts finishes the workload first (build + rays + updates) within the memory limit "
             "and the error allowed (`visfield select` shows its table)",
     Exactness::exact, "", kAutoParams, build_auto, estimate_auto},
};

}  // namespace

std::span<const StructureInfo> structure_table() { return kTable; }

const StructureInfo& find_structure(std::string_view name, std::string_view what) {
  for (const StructureInfo& info : kTable)
    if (info.name == name) return info;
  std::string valid;
  for (const StructureInfo& info : kTable) valid += (valid.empty() ? "" : ", ") + std::string(info.name);
  throw Error(std::string(what) + std::string(name) + ": unknown structure (valid: " + valid + ")");
}

namespace {

std::pair<const StructureInfo*, ParamValues> read_spec(std::string_view text, std::string_view what) {
  const Spec spec = parse_spec(text, what);
  const StructureInfo& info = find_structure(spec.name, what);
  return {&info, read_params(spec, info.params, std::string(what) + spec.name)};
}

}  // namespace

void check_structure_spec(std::string_view spec, std::string_view what) {
  const auto [info, params] = read_spec(spec, what);
  // The field's parameters that exclude each other: refused here as a bad spec, not at the build.
  if (info->name == "field") field_config(params);
}

BuiltStructure build_structure(std::string_view spec, SceneGeometry& geometry, const BuildContext& context,
                               std::string_view what) {
  const auto [info, params] = read_spec(spec, what);
  check_interrupt();
  const double estimate = info->estimate(params, geometry);
  require_memory(estimate, std::string(what) + std::string(spec) + ": the build");
  BuiltStructure built = info->build(params, geometry, context);
  // auto's own estimate covers its profile; the structure it picked was checked against its own.
  built.estimated_bytes = std::max(estimate, built.estimated_bytes);
  return built;
}

field::ObjectFieldConfig field_config_from_spec(std::string_view spec, std::string_view what) {
  const auto [info, params] = read_spec(spec, what);
  if (info->name != "field") throw Error(std::string(what) + std::string(spec) + ": expected a field:... spec");
  return field_config(params);
}

double estimate_structure_bytes(std::string_view spec, const SceneGeometry& geometry, std::string_view what) {
  const auto [info, params] = read_spec(spec, what);
  return info->estimate(params, geometry);
}

std::vector<std::string> structure_names() {
  std::vector<std::string> names;
  for (const StructureInfo& info : kTable) names.emplace_back(info.name);
  return names;
}

std::string structures_help(std::string_view indent) {
  std::string out;
  for (const StructureInfo& info : kTable) {
    out += std::string(indent) + std::string(info.name) + " (" + exactness_name(info.exactness) +
           (info.updates.empty() ? "" : ", updatable " + std::string(info.updates)) + "): " + std::string(info.summary) +
           "\n";
    out += describe_params(info.params, std::string(indent) + "    ");
  }
  return out;
}

bool update_in_place(AnyStructure& structure, ObjectId id, const Transform& t) {
  return std::visit(
      [&](auto& s) {
        if constexpr (UpdatableStructure<std::decay_t<decltype(s)>>) {
          s.move(id, t);
          s.commit();
          return true;
        } else {
          return false;
        }
      },
      structure);
}

std::unique_ptr<SceneQueries> scene_queries(const AnyStructure& closest, const AnyStructure& occluder) {
  return std::visit(
      [](const auto& c, const auto& o) -> std::unique_ptr<SceneQueries> {
        return std::make_unique<QueriesOver<std::decay_t<decltype(c)>, std::decay_t<decltype(o)>>>(c, o);
      },
      closest, occluder);
}

AccelStats structure_stats(const AnyStructure& structure) {
  return std::visit([](const auto& s) -> AccelStats { return s.stats(); }, structure);
}

}  // namespace vf

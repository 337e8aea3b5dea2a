#pragma once
/// \file The one table of structures. Each entry gives a structure's name, whether it is exact or
/// approximate, whether its objects can be edited after the build, its parameters and how to build it
/// from them. The CLI's --accel and --occluder values, visfield-bench's names, the help texts and the
/// test lists all come from this table: adding a structure is one entry here plus its folder.
///
/// A structure is named by a spec, "name[:key=value,...]" (`bvh:leaf=4,levels=2`); unknown names and
/// keys, and values of the wrong type or range, are refused with a one-line vf::Error.

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "visfield/accel/beam_field.hpp"
#include "visfield/accel/brute_force.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/accel/instance_layer.hpp"
#include "visfield/accel/kdtree.hpp"
#include "visfield/accel/median_bsp.hpp"
#include "visfield/accel/scene_queries.hpp"
#include "visfield/accel/uniform_grid.hpp"
#include "visfield/core/spec.hpp"
#include "visfield/field/field_scene.hpp"
#include "visfield/registry/scene_geometry.hpp"

namespace vf {

/// Every structure type the table builds; std::visit it so that callers stay generic.
using AnyStructure = std::variant<Bvh, UniformGrid, KdTree, MedianBsp, BruteForce, InstanceLayer, BeamField, field::FieldScene>;

/// What a build may need to know beyond the scene.
struct BuildContext {
  std::uint64_t expected_rays = 1'000'000;  ///< R for `auto` when its rays= is not given: the rays the structure will trace.
  bool progress = false;                    ///< Show a progress bar on stderr for long precomputes (fields).
};

/// A built structure and how its spec was resolved.
struct BuiltStructure {
  AnyStructure structure;
  std::string resolved;                  ///< The spec with automatic choices made: "bvh:levels=1", "auto:kind=path,rays=16000000 -> grid".
  std::size_t degenerate_triangles = 0;  ///< Zero-area triangles (counted once per object) left out of the structure.
  double estimated_bytes = 0.0;          ///< The estimate the build was checked against (StructureInfo::estimate).
};

/// One row of the table.
struct StructureInfo {
  std::string_view name;               ///< Spec name.
  std::string_view summary;            ///< One line for help texts.
  Exactness exactness;                 ///< Exact (agrees with brute force) or approximate (states its error).
  std::string_view updates;            ///< When objects can be removed, inserted and moved after the build ("" = never).
  std::span<const ParamSpec> params;   ///< Its parameters, with defaults and ranges.
  /// Builds it from validated parameters; throws vf::Error on a failed build.
  BuiltStructure (*build)(const ParamValues& params, SceneGeometry& geometry, const BuildContext& context);
  /// Peak bytes the build would take, from triangle and object counts (the structure's own
  /// estimate_build_bytes, plus the flattened triangles when they are still to be made). O(objects).
  double (*estimate)(const ParamValues& params, const SceneGeometry& geometry);
};

/// The table, in help order.
std::span<const StructureInfo> structure_table();

/// The entry named `name`; throws vf::Error "<what><name>: unknown structure (valid: ...)".
const StructureInfo& find_structure(std::string_view name, std::string_view what = "--accel ");

/// Checks a spec without building anything (for command lines: fail before loading a scene). Throws
/// vf::Error starting with `what` on an unknown name or a bad parameter.
void check_structure_spec(std::string_view spec, std::string_view what = "--accel ");

/// Builds the structure `spec` names over `geometry`, after checking its estimate against the memory
/// limit (memory_limit(); vf::Error "<what><spec>: the build would need about ..."). Throws vf::Error
/// on a bad spec (messages start with `what`) or a failed build. Build timing is in stats().build_ms.
BuiltStructure build_structure(std::string_view spec, SceneGeometry& geometry, const BuildContext& context = {},
                               std::string_view what = "--accel ");

/// The ObjectField parameters of a "field[:key=value,...]" spec (lookup options included); throws
/// vf::Error starting with `what` on a bad spec or another structure's name.
field::ObjectFieldConfig field_config_from_spec(std::string_view spec, std::string_view what = "--accel ");

/// The estimate build_structure() checks for `spec` over `geometry`, in bytes; throws on a bad spec.
double estimate_structure_bytes(std::string_view spec, const SceneGeometry& geometry, std::string_view what = "--accel ");

/// The names of the table's structures, in order.
std::vector<std::string> structure_names();

/// Every structure with its metadata and parameters, indented by `indent`, for --help texts.
std::string structures_help(std::string_view indent = "  ");

/// Build statistics of whichever structure `structure` holds.
AccelStats structure_stats(const AnyStructure& structure);

/// Moves object `id` to `t` and commits, when `structure` is updatable (UpdatableStructure: BeamField and
/// the levels=2 instance layer); returns false, leaving it untouched, when it is not (the caller rebuilds it).
bool update_in_place(AnyStructure& structure, ObjectId id, const Transform& t);

/// The renderers' view of two built structures (they must outlive the result): camera rays through
/// `closest`, every later ray through `occluder` (which may be the same object).
std::unique_ptr<SceneQueries> scene_queries(const AnyStructure& closest, const AnyStructure& occluder);

}  // namespace vf

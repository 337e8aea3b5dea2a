#pragma once
/// \file visfield-bench's output: a table for people, a JSON document for scripts.

#include <cstddef>
#include <limits>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "agreement.hpp"
#include "visfield/core/text.hpp"
#include "visfield/render/ray_kind.hpp"

namespace vf::bench {

/// A BeamField's work on the ray set (an untimed counting pass), per ray: for checking its cost model.
struct BeamWork {
  double single_tile_fraction = 0.0;  ///< Rays whose segment stayed in one tile (the fast path).
  double tiles = 0.0;                 ///< Tiles visited per ray.
  double leaves = 0.0;                ///< Tile-BSP leaves visited per ray.
  double triangle_tests = 0.0;        ///< Ray–triangle tests per ray.
};

/// A flattened Bvh's work on the ray set (an untimed counting pass), per ray: where its time goes.
struct BvhWork {
  double nodes = 0.0;           ///< 8-wide nodes whose children's boxes were tested.
  double leaves = 0.0;          ///< Leaves visited.
  double blocks = 0.0;          ///< 8-triangle blocks tested.
  double triangle_tests = 0.0;  ///< Triangles in those blocks.
};

/// One structure's figures.
struct ResultRow {
  std::string accel;                      ///< --accel spec as resolved (automatic choices made).
  double build_ms = 0.0;                  ///< Build wall time.
  std::size_t bytes = 0;                  ///< Memory held by the built structure.
  double median_ms = 0.0;                 ///< Median time to trace the whole ray set.
  double mrays_per_s = 0.0;               ///< Rays / median time, in millions per second.
  std::optional<double> ratio_to_embree;  ///< mrays_per_s / the first Embree row's (> 1 = faster); absent without Embree.
  std::size_t mismatches = 0;             ///< Rays answered differently from the reference structure (exact rows).
  std::optional<ApproximateAgreement> approximate;  ///< Approximate rows (fields): their error against the reference.
  std::optional<BeamWork> beam_work;      ///< BeamField rows only: its work per ray.
  std::optional<BvhWork> bvh_work;        ///< Flattened Bvh rows only: its work per ray.
  std::optional<double> ratio_to_embree_best;  ///< mrays_per_s / the fastest Embree row's; absent without Embree.
  bool embree = false;                    ///< An Embree row.
};

/// Everything one run reports.
struct BenchReport {
  std::string scene;          ///< Scene name.
  std::size_t triangles = 0;  ///< Triangles of the scene's objects (each object's mesh counted).
  RayKind kind = RayKind::primary;
  std::size_t rays = 0;       ///< Rays traced per repetition.
  int threads = 1;            ///< Worker threads in force.
  std::string isa;            ///< The kernels' path that ran (isa_name(active_isa())).
  int width = 0, height = 0;  ///< Camera image the rays were made from (before --count scaling).
  int reps = 0, warmup = 0;
  int ao_rays = 0;                                              ///< AO rays per primary hit (ao kind only).
  float max_distance = std::numeric_limits<float>::infinity();  ///< AO ray length (ao kind only).
  std::string reference;                                        ///< Structure the mismatches are counted against.
  std::optional<std::string> embree;                            ///< embree_description() when Embree ran.
  std::optional<std::string> embree_best;                       ///< The fastest Embree row's accel ("Embree best" for these rays).
  std::vector<ResultRow> rows;                                  ///< In --accel order.
};

/// 12345678 -> "12,345,678".
std::string with_separators(std::size_t value);
/// `text` right-aligned in `width` columns (never cut).
std::string padded_left(const std::string& text, std::size_t width);
/// `text` left-aligned in `width` columns (never cut).
std::string padded_right(const std::string& text, std::size_t width);

/// Millions of rays per second for `rays` rays traced in `ms` milliseconds (0 when ms <= 0).
double mrays_per_second(std::size_t rays, double ms);

/// Prints the header line and the table (accel | build ms | bytes | Mrays/s | ratio to Embree |
/// mismatches), then one line of work per ray for each BeamField row and each flattened Bvh row.
void print_table(std::ostream& out, const BenchReport& report);

/// {"scene", "triangles", "rays", "kind", "threads", ..., ("ao_rays", "max_distance" (null = unlimited)
/// for ao,) "results": [{"accel", "build_ms", "bytes",
/// "mrays_per_s", "ratio_to_embree" (null without Embree), "mismatches", ("beam_work": {"single_tile_fraction",
/// "tiles", "leaves", "triangle_tests"} per ray, BeamField rows only; "bvh_work": {"nodes", "leaves",
/// "blocks", "triangle_tests"} per ray, flattened Bvh rows only)}]}.
nlohmann::ordered_json report_json(const BenchReport& report);

}  // namespace vf::bench

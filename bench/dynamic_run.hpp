#pragma once
/// \file visfield-bench --dynamic: one object moves every frame; each structure is brought up to
/// date (remove and insert for the structures that can update, a full rebuild for the others) and
/// the same ray set is traced through it. Reports what an animation pays per frame.

#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_options.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/render/ray_kind.hpp"

namespace vf::bench {

/// One structure's figures over the frames.
struct DynamicRow {
  std::string accel;            ///< Spec as resolved.
  bool incremental = false;     ///< Updated in place (UpdatableStructure) rather than rebuilt each frame.
  double update_ms = 0.0;       ///< Median per frame: move + commit, or the full rebuild.
  double rebuild_ms = 0.0;      ///< A full build over the last frame's scene.
  double trace_ms = 0.0;        ///< Median per frame: the ray set.
  double mrays_per_s = 0.0;     ///< Rays / trace_ms.
  std::size_t full_rebuilds = 0;  ///< Frames whose commit rebuilt everything (BeamField: the object left its sphere).
  std::size_t mismatches = 0;   ///< Rays answered differently from the fresh build of the last frame's scene.
};

/// Everything --dynamic reports.
struct DynamicReport {
  std::string scene;
  std::size_t triangles = 0;         ///< Triangles of all objects.
  std::uint32_t moved_object = 0;    ///< Id of the object that moves.
  std::size_t moved_triangles = 0;   ///< Its triangles.
  int frames = 0;
  RayKind kind = RayKind::primary;
  std::size_t rays = 0;              ///< Rays traced per frame (made once, from the first frame's scene).
  int threads = 1;
  std::vector<DynamicRow> rows;      ///< In --accel order.
};

/// Runs --dynamic: per structure, builds it over the scene, then for each frame moves the object
/// (a small deterministic orbit of 1% of the scene's radius around its place), updates or rebuilds
/// the structure (timed) and traces the ray set (timed); finally builds it fresh over the last
/// frame's scene (timed) and counts the rays the updated structure answers differently. Throws
/// vf::Error on bad input (an unknown --move-object id, a scene without objects).
DynamicReport run_dynamic_bench(const BenchOptions& options);

/// The object --dynamic moves by default: the one whose triangle count is nearest to 5% of the
/// scene's (ties: the lowest id). The scene must have an object.
std::uint32_t default_moving_object(const Scene& scene);

/// Prints the header line and one row per structure (accel | update ms | rebuild ms | update/rebuild |
/// trace ms | Mrays/s | full rebuilds | mismatches vs fresh build).
void print_dynamic_table(std::ostream& out, const DynamicReport& report);

/// {"scene", "triangles", "moved_object", "moved_triangles", "frames", "kind", "rays", "threads",
/// "results": [{"accel", "incremental", "update_ms", "rebuild_ms", "trace_ms", "mrays_per_s",
/// "full_rebuilds", "mismatches"}]}.
nlohmann::ordered_json dynamic_report_json(const DynamicReport& report);

}  // namespace vf::bench
